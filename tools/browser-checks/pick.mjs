// Drives the page of `meshmorph pick` in headless Chromium, as a user would:
// clicks pairs of points (given in each mesh's own coordinates, found on the
// screen through the page's camera), deletes one, undoes, saves, fits.
// Prints what the page shows as one JSON object and saves a screenshot.
//
//   node pick.mjs URL OUTDIR PLAN.json [--chromium PATH]
//
// PLAN.json: { "pairs": [[[sx, sy, sz], [tx, ty, tz]], ...],
//              "delete": k, "undo": true, "redo": true (then undone),
//              "mirror": k (then undone), "overlay": "overlay.png",
//              "drag": { "pair": k, "side": "source", "to": [x, y, z] } (then undone),
//              "save": true, "fit": true,
//              "guided": { "points": { landmark: [x, y, z] on the head, ... },
//                          "skip": landmark } (with `pick --template`: each
//                          landmark the page asks for clicked on the head,
//                          "skip" and those not given skipped, then the fit
//                          after the last click awaited),
//              "screenshot": "name.png", "size": [width, height] }
// Every step is optional. Exits 0 when every step ran, 1 when one failed,
// 2 on a usage or setup error.
import { readFile, mkdir } from 'node:fs/promises';
import { join, resolve } from 'node:path';
import puppeteer from 'puppeteer-core';

const args = process.argv.slice(2);
const chromiumAt = args.indexOf('--chromium');
const chromium = chromiumAt >= 0 ? args.splice(chromiumAt, 2)[1] : process.env.CHROMIUM ?? '/usr/bin/chromium';
if (args.length !== 3) {
  console.error('usage: node pick.mjs URL OUTDIR PLAN.json [--chromium PATH]');
  process.exit(2);
}
const [url, outdirArg, planPath] = args;
const outdir = resolve(outdirArg);
await mkdir(outdir, { recursive: true });
const plan = JSON.parse(await readFile(planPath, 'utf8'));
const [width, height] = plan.size ?? [1280, 720];

const browser = await puppeteer.launch({
  executablePath: chromium,
  headless: true,
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'],
});
const result = { errors: [], steps: [] };
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
  const project = (side, p) => page.evaluate((s, q) => window.pick.project(s, q), side, p);
  const clicks = [];
  for (const [s, t] of plan.pairs ?? []) {
    for (const [side, point] of [['source', s], ['target', t]]) {
      const at = await project(side, point);
      const before = Date.now();
      await page.mouse.click(at.x, at.y);
      await page.evaluate(() => new Promise((ok) => requestAnimationFrame(() => requestAnimationFrame(ok))));
      clicks.push({ side, at, wall_ms: Date.now() - before, ...(await page.evaluate(() => ({ work_ms: window.pick.timings.lastClickWork, frame_ms: window.pick.timings.lastClick }))) });
    }
  }
  if (plan.guided) {
    // As the page asks: the lit landmark clicked on the head, or skipped.
    const { points, skip } = plan.guided;
    const asked = [];
    for (let step = 0; step < 200; step++) {
      const next = await page.evaluate(() => window.pick.next());
      if (!next || asked.filter((n) => n === next.name).length > 1) break;
      asked.push(next.name);
      const point = points[next.name];
      // Each click is waited on until the page has taken it (it asks for
      // another landmark, or none): on a loaded machine a click can land
      // after two frames. A click that missed is asked again, as before.
      const taken = () =>
        page
          .waitForFunction((name) => window.pick.next()?.name !== name, { timeout: 20000 }, next.name)
          .catch(() => {});
      if (!point || (next.name === skip && asked.filter((n) => n === skip).length === 1)) {
        await page.click('#skip');
        await taken();
        continue;
      }
      const at = await project('target', point);
      await page.mouse.click(at.x, at.y);
      await page.evaluate(() => new Promise((ok) => requestAnimationFrame(() => requestAnimationFrame(ok))));
      // The skipped landmark, asked again once every other one had been
      // asked, is placed: the round is over.
      if (next.name === skip) break;
      await taken();
    }
    result.asked = asked;
    result.guide_text = await page.evaluate(() => document.getElementById('guide').innerText);
    // The fit after the last click (each click asks for one) with its preview.
    await page.waitForFunction(() => document.body.dataset.fit === 'done' && window.pick.fit()?.pose, { timeout: 300000 });
    result.fit = await page.evaluate(() => window.pick.fit());
  }
  result.clicks = clicks;
  result.after_clicks = await page.evaluate(() => window.pick.pairs().length);
  if (plan.delete !== undefined) {
    await page.click(`#pairs li:nth-child(${plan.delete + 1})`);
    await page.keyboard.press('Delete');
    result.after_delete = await page.evaluate(() => window.pick.pairs().length);
  }
  if (plan.undo) {
    await page.click('#undo');
    result.after_undo = await page.evaluate(() => window.pick.pairs().length);
  }
  if (plan.redo) {
    await page.click('#redo');
    result.after_redo = await page.evaluate(() => window.pick.pairs().length);
    await page.click('#undo');
  }
  if (plan.mirror !== undefined) {
    await page.click(`#pairs li:nth-child(${plan.mirror + 1})`);
    const before = await page.evaluate(() => window.pick.pairs().length);
    await page.click('#mirror');
    await page.waitForFunction((n) => window.pick.pairs().length > n, { timeout: 30000 }, before);
    result.mirrored = await page.evaluate(() => window.pick.pairs().at(-1));
    await page.click('#undo');
  }
  if (plan.drag) {
    // Select the pair, then drag its marker on one mesh to another point.
    const { pair, side, to } = plan.drag;
    await page.click(`#pairs li:nth-child(${pair + 1})`);
    const from = await page.evaluate((k, s) => window.pick.position(s, window.pick.pairs()[k][s]), pair, side);
    const [a, b] = [await project(side, from), await project(side, to)];
    await page.mouse.move(a.x, a.y);
    await page.mouse.down();
    await page.mouse.move(b.x, b.y, { steps: 8 });
    await page.mouse.up();
    result.dragged = await page.evaluate((k, s) => window.pick.position(s, window.pick.pairs()[k][s]), pair, side);
    await page.click('#undo');
    result.after_drag_undone = await page.evaluate((k, s) => window.pick.position(s, window.pick.pairs()[k][s]), pair, side);
  }
  if (plan.overlay) {
    await page.click('#overlay');
    await page.evaluate(() => new Promise((ok) => requestAnimationFrame(() => requestAnimationFrame(ok))));
    await page.screenshot({ path: join(outdir, plan.overlay) });
    await page.click('#overlay');
  }
  if (plan.save) {
    await page.click('#save');
    await page.waitForSelector('body[data-saved]', { timeout: 30000 });
    result.saved = await page.evaluate(() => document.body.dataset.saved);
  }
  if (plan.fit) {
    const before = Date.now();
    await page.click('#fit');
    await page.waitForFunction(() => ['done', 'failed'].includes(document.body.dataset.fit), { timeout: 300000 });
    result.fit_wall_ms = Date.now() - before;
    result.fit_state = await page.evaluate(() => document.body.dataset.fit);
    result.fit_page_ms = await page.evaluate(() => window.pick.timings.lastFit);
    result.fit = await page.evaluate(() => window.pick.fit());
    result.fit_text = await page.evaluate(() => document.getElementById('fit-report').innerText);
    if (plan.pose && await page.$eval('#pose-toggle', (e) => !e.hidden)) {
      await page.click('#show-pose');
    }
  }
  result.status = await page.evaluate(() => document.getElementById('status').innerText);
  result.pairs = await page.evaluate(() => window.pick.pairs());
  if (plan.screenshot) {
    await page.evaluate(() => new Promise((ok) => requestAnimationFrame(() => requestAnimationFrame(ok))));
    await page.screenshot({ path: join(outdir, plan.screenshot) });
  }
  if (plan.done) {
    // The click sends "done" from the page: wait for the server's answer,
    // or closing the browser may cancel the request before it is sent.
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
