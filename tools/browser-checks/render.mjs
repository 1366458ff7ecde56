// Opens each GLB in headless Chromium with three.js's GLTFLoader (one
// browser, a page for each), plays its animation to the start, the middle
// and the end, and checks from the rendered pixels that the mesh is drawn
// and moves. Saves a screenshot of each time to OUTDIR, and prints a
// paragraph for each file, starting with its name.
//
//   node render.mjs FILE.glb... OUTDIR [--chromium PATH]
//
// Exits 0 when the checks pass, 1 when they fail, 2 on a usage or setup error.
import { createServer } from 'node:http';
import { readFile, mkdir } from 'node:fs/promises';
import { basename, dirname, extname, join, relative, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import puppeteer from 'puppeteer-core';

const here = dirname(fileURLToPath(import.meta.url));
const args = process.argv.slice(2);
const chromiumAt = args.indexOf('--chromium');
const chromium = chromiumAt >= 0 ? args.splice(chromiumAt, 2)[1] : process.env.CHROMIUM ?? '/usr/bin/chromium';
if (args.length < 2) {
  console.error('usage: node render.mjs FILE.glb... OUTDIR [--chromium PATH]');
  process.exit(2);
}
const paths = args.map((a) => resolve(a));
const outdir = paths.pop();
const glbs = paths;
await mkdir(outdir, { recursive: true });

const TYPES = { '.html': 'text/html', '.js': 'text/javascript', '.glb': 'model/gltf-binary' };
// Serves this folder (the page, three.js) and the GLBs named (/model/K.glb
// the K-th), on loopback only.
const server = createServer(async (req, res) => {
  let path;
  try {
    path = decodeURIComponent(new URL(req.url, 'http://127.0.0.1').pathname);
  } catch {
    res.writeHead(400).end();
    return;
  }
  const model = path.match(/^\/model\/(\d+)\.glb$/);
  const file = model ? glbs[Number(model[1])] : join(here, path);
  if (!file || (!model && relative(here, file).startsWith('..'))) {
    res.writeHead(403).end();
    return;
  }
  try {
    const body = await readFile(file);
    res.writeHead(200, { 'content-type': TYPES[extname(file)] ?? 'application/octet-stream' }).end(body);
  } catch {
    res.writeHead(404).end();
  }
});
await new Promise((ok) => server.listen(0, '127.0.0.1', ok));
const port = server.address().port;

const browser = await puppeteer.launch({
  executablePath: chromium,
  headless: true,
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'],
});
let failed = false;
try {
  for (const [k, glb] of glbs.entries()) await check(k, glb);
} finally {
  await browser.close();
  server.close();
}
process.exit(failed ? 1 : 0);

async function check(k, glb) {
  const page = await browser.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  await page.setViewport({ width: 480, height: 360 });
  await page.goto(`http://127.0.0.1:${port}/view.html?file=/model/${k}.glb&width=480&height=360`);
  const info = await page.evaluate(async () => {
    const m = await window.meshmorph;
    return { duration: m.duration, targets: m.targets, targetNames: m.targetNames };
  }).catch((e) => { throw new Error(`${e.message}\n${errors.join('\n')}`); });
  console.log(`${basename(glb)}: ${info.targets} morph targets (${info.targetNames.slice(0, 3).join(', ')}${info.targets > 3 ? ', ...' : ''}), animation ${info.duration.toFixed(3)} s`);
  if (info.targets === 0 || info.duration <= 0) {
    console.log('  FAIL: no morph targets or no animation');
    failed = true;
  }
  const times = { start: 0, middle: info.duration / 2, end: info.duration };
  const stem = basename(glb, '.glb');
  for (const [name, t] of Object.entries(times)) {
    const { drawn, total } = await page.evaluate((t) => window.meshmorph.then((m) => m.show(t)), t);
    const shot = join(outdir, `${stem}-${name}.png`);
    await page.screenshot({ path: shot });
    const share = drawn / total;
    const ok = share > 0.01 && share < 0.95;
    console.log(`  ${name} (t = ${t.toFixed(3)} s): ${(100 * share).toFixed(1)}% of the pixels drawn ${ok ? 'ok' : 'FAIL'}; ${shot}`);
    failed ||= !ok;
  }
  for (const [a, b] of [['start', 'middle'], ['middle', 'end']]) {
    const changed = await page.evaluate((x, y) => window.meshmorph.then((m) => m.differ(x, y)), times[a], times[b]);
    const ok = changed > 0.002 * 480 * 360;
    console.log(`  ${a} -> ${b}: ${changed} pixels changed ${ok ? 'ok' : 'FAIL: the mesh does not move'}`);
    failed ||= !ok;
  }
  if (errors.length) {
    console.log(`  page errors:\n    ${errors.join('\n    ')}`);
    failed = true;
  }
  console.log('');
  await page.close();
}
