// Drives the page of `meshmorph pick A.png B.png` in headless Chromium, as
// a user would: clicks anchors on both pictures (given in each picture's
// pixels), drags one and undoes it, deletes one and undoes it, waits for
// the morph's preview after each change, saves. Prints what the page
// shows as one JSON object and saves a screenshot.
//
//   node pick-pictures.mjs URL OUTDIR PLAN.json [--chromium PATH]
//
// PLAN.json: { "anchors": [[[ax, ay], [bx, by]], ...],
//              "drag": { "anchor": k, "side": "b", "to": [x, y] } (then undone),
//              "delete": k (then undone), "save": true,
//              "screenshot": "name.png", "size": [width, height], "done": true }
// Every step is optional. Exits 0 when every step ran, 1 when one failed,
// 2 on a usage or setup error.
import { readFile, mkdir } from 'node:fs/promises';
import { join, resolve } from 'node:path';
import puppeteer from 'puppeteer-core';

const args = process.argv.slice(2);
const chromiumAt = args.indexOf('--chromium');
const chromium = chromiumAt >= 0 ? args.splice(chromiumAt, 2)[1] : process.env.CHROMIUM ?? '/usr/bin/chromium';
if (args.length !== 3) {
  console.error('usage: node pick-pictures.mjs URL OUTDIR PLAN.json [--chromium PATH]');
  process.exit(2);
}
const [url, outdirArg, planPath] = args;
const outdir = resolve(outdirArg);
await mkdir(outdir, { recursive: true });
const plan = JSON.parse(await readFile(planPath, 'utf8'));
const [width, height] = plan.size ?? [1280, 640];

const browser = await puppeteer.launch({ executablePath: chromium, headless: true, args: ['--no-sandbox'] });
const result = { errors: [], preview_ms: [] };
let failed = false;
try {
  const page = await browser.newPage();
  page.on('pageerror', (e) => result.errors.push(e.message));
  page.on('console', (m) => { if (m.type() === 'error') result.errors.push(m.text()); });
  await page.setViewport({ width, height });
  const begin = Date.now();
  await page.goto(url);
  await page.waitForSelector('body[data-ready="yes"]', { timeout: 60000 });
  result.ready_ms = Date.now() - begin;
  const screen = (side, p) => page.evaluate((s, q) => window.pick.toScreen(s, q[0], q[1]), side, p);
  const anchors = () => page.evaluate(() => window.pick.anchors());
  // Waits for the page's preview of the anchors as they are now.
  const settled = async () => {
    const before = Date.now();
    await page.waitForFunction(() => !window.pick.previewing(), { timeout: 120000 });
    result.preview_ms.push(Date.now() - before);
  };
  await settled();
  result.start = await anchors();
  for (const [a, b] of plan.anchors ?? []) {
    for (const [side, p] of [['a', a], ['b', b]]) {
      const at = await screen(side, p);
      await page.mouse.click(at.x, at.y);
    }
    await settled();
  }
  result.after_clicks = await anchors();
  if (plan.drag) {
    const { anchor, side, to } = plan.drag;
    const from = (await anchors())[anchor][side];
    const [p, q] = [await screen(side, from), await screen(side, to)];
    await page.mouse.move(p.x, p.y);
    await page.mouse.down();
    await page.mouse.move(q.x, q.y, { steps: 8 });
    await page.mouse.up();
    result.dragged = (await anchors())[anchor][side];
    await settled();
    await page.click('#undo');
    result.drag_undone = (await anchors())[anchor][side];
    await settled();
  }
  if (plan.delete !== undefined) {
    await page.click(`#anchors li:nth-child(${plan.delete + 1}) .number`);
    await page.keyboard.press('Delete');
    result.after_delete = (await anchors()).length;
    await settled();
    await page.click('#undo');
    result.after_undo = (await anchors()).length;
    await settled();
  }
  result.previews = await page.evaluate(() => window.pick.previews());
  result.preview_error = await page.evaluate(() => window.pick.previewError());
  if (plan.save) {
    await page.click('#save');
    await page.waitForSelector('body[data-saved]', { timeout: 30000 });
    result.saved = await page.evaluate(() => document.body.dataset.saved);
  }
  result.status = await page.evaluate(() => window.pick.status());
  result.anchors = await anchors();
  if (plan.screenshot) {
    // Half a second of the preview playing, then the picture.
    await new Promise((ok) => setTimeout(ok, 500));
    await page.screenshot({ path: join(outdir, plan.screenshot) });
  }
  if (plan.done) {
    await Promise.all([
      page.waitForResponse((r) => r.url().endsWith('/api/done'), { timeout: 60000 }),
      page.click('#done'),
    ]);
  }
} catch (e) {
  result.errors.push(String(e));
  failed = true;
} finally {
  await browser.close();
}
if (result.errors.length) failed = true;
console.log(JSON.stringify(result));
process.exit(failed ? 1 : 0);
