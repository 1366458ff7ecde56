// A drawing morph in its players: a Lottie file in lottie-web (SVG
// renderer) and an animated SVG (SMIL) in headless Chromium.
//
//   node drawing.mjs CHROMIUM MORPH.json MORPH.svg
//
// Prints one JSON object: for the Lottie file, its frame count, and the
// rendered path of its first, middle and last frames (how many paths,
// their fill rule, the length of their data); for the SVG, how many
// values its animation has and whether two pictures a second apart differ;
// and every error the page reported.
import fs from 'node:fs';
import { createRequire } from 'node:module';
import puppeteer from 'puppeteer-core';

const [chromium, lottieFile, svgFile] = process.argv.slice(2);
const require = createRequire(import.meta.url);
const player = fs.readFileSync(require.resolve('lottie-web/build/player/lottie.min.js'), 'utf8');
const data = JSON.parse(fs.readFileSync(lottieFile, 'utf8'));
const browser = await puppeteer.launch({ executablePath: chromium, args: ['--no-sandbox', '--headless=new'] });
const errors = [];
try {
  const page = await browser.newPage();
  page.on('pageerror', (e) => errors.push(String(e)));
  page.on('console', (m) => m.type() === 'error' && errors.push(m.text()));
  await page.setContent('<html><body><div id="a" style="width:400px;height:400px"></div></body></html>');
  await page.addScriptTag({ content: player });
  const lottie = await page.evaluate(async (data) => {
    const anim = globalThis.lottie.loadAnimation({
      container: document.getElementById('a'), renderer: 'svg', loop: false, autoplay: false, animationData: data,
    });
    await new Promise((r) => (anim.isLoaded ? r() : anim.addEventListener('DOMLoaded', r)));
    const frames = [];
    for (const f of [0, Math.floor(anim.totalFrames / 2), anim.totalFrames - 1]) {
      anim.goToAndStop(f, true);
      const paths = [...document.querySelectorAll('#a svg path')];
      frames.push({ paths: paths.length, fillRule: paths[0]?.getAttribute('fill-rule'), d: paths[0]?.getAttribute('d') ?? '' });
    }
    return { totalFrames: anim.totalFrames, frames };
  }, data);
  const svgPage = await browser.newPage();
  svgPage.on('pageerror', (e) => errors.push(String(e)));
  await svgPage.goto('file://' + fs.realpathSync(svgFile));
  const before = await svgPage.screenshot({ encoding: 'base64' });
  await new Promise((r) => setTimeout(r, 1000));
  const after = await svgPage.screenshot({ encoding: 'base64' });
  const values = await svgPage.evaluate(() => document.querySelector('animate').getAttribute('values').split(';').length);
  console.log(JSON.stringify({ lottie, svg: { values, moves: before !== after }, errors }));
} finally {
  await browser.close();
}
