// The figures of `meshmorph pick` in headless Chromium, as a table: the page
// ready with both meshes drawn, a click until its pair is drawn (the page's
// own work, and until the next frame), and "fit" until the fit is shown.
// Runs pick.mjs on horse -> camel (../shared/data, its 107 markers and a
// pose) and on two bumpy sheets of about 500k triangles each (made here),
// three times each.
//
//   node pick-bench.mjs MESHMORPH [--chromium PATH]
import { spawn, spawnSync } from 'node:child_process';
import { mkdtempSync, writeFileSync, createWriteStream } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { createInterface } from 'node:readline';

const here = dirname(fileURLToPath(import.meta.url));
const args = process.argv.slice(2);
const chromiumAt = args.indexOf('--chromium');
const chromium = chromiumAt >= 0 ? args.splice(chromiumAt, 2)[1] : process.env.CHROMIUM ?? '/usr/bin/chromium';
if (args.length !== 1) {
  console.error('usage: node pick-bench.mjs MESHMORPH [--chromium PATH]');
  process.exit(2);
}
const meshmorph = resolve(args[0]);
const work = mkdtempSync(join(tmpdir(), 'pick-bench-'));
const data = resolve(here, '../../../shared/data/dt/horse-camel');

const height = (x, y, s) => 0.08 * s * (Math.sin((1.7 * x) / s) + Math.cos((1.3 * y) / s));

/** A bumpy sheet of 2 n² triangles over [-s, s]², as an OBJ file. */
function sheet(path, n, s) {
  const out = createWriteStream(path);
  const lines = [];
  for (let j = 0; j <= n; j++) for (let i = 0; i <= n; i++) {
    const x = s * ((2 * i) / n - 1), y = s * ((2 * j) / n - 1);
    lines.push(`v ${x} ${y} ${height(x, y, s)}`);
  }
  const v = (i, j) => j * (n + 1) + i + 1;
  for (let j = 0; j < n; j++) for (let i = 0; i < n; i++) {
    lines.push(`f ${v(i, j)} ${v(i + 1, j)} ${v(i + 1, j + 1)}`, `f ${v(i, j)} ${v(i + 1, j + 1)} ${v(i, j + 1)}`);
  }
  return new Promise((ok) => out.end(lines.join('\n') + '\n', ok));
}

function vertices(path) {
  const text = spawnSync('grep', ['^v ', path], { encoding: 'utf8', maxBuffer: 1 << 30 }).stdout;
  return text.trim().split('\n').map((l) => l.split(/\s+/).slice(1, 4).map(Number));
}

/** Starts pick, drives the page with `plan`, returns the page's report. */
async function run(pickArgs, plan) {
  const planPath = join(work, 'plan.json');
  writeFileSync(planPath, JSON.stringify(plan));
  const child = spawn(meshmorph, ['pick', ...pickArgs, '-o', join(work, 'picked.txt')], { stdio: ['ignore', 'pipe', 'inherit'] });
  const line = await new Promise((ok) => createInterface({ input: child.stdout }).once('line', ok));
  const url = line.split(/\s+/).find((w) => w.startsWith('http://'));
  const page = spawnSync('node', [join(here, 'pick.mjs'), url, work, planPath, '--chromium', chromium], { encoding: 'utf8', maxBuffer: 1 << 26 });
  if (child.exitCode === null) await new Promise((ok) => child.once('exit', ok));
  if (page.status !== 0) throw new Error(`pick.mjs failed: ${page.stdout}${page.stderr}`);
  return JSON.parse(page.stdout);
}

const cases = [];
const h = vertices(join(data, 'horse-poses/horse-reference.obj'));
const c = vertices(join(data, 'camel-poses/camel-reference.obj'));
cases.push({
  name: 'horse → camel (16,843 + 43,814 triangles), 107 markers, a pose',
  args: [join(data, 'horse-poses/horse-reference.obj'), join(data, 'camel-poses/camel-reference.obj'), '--markers', join(data, 'markers/horse-camel-107.cons'), '--pose', join(data, 'horse-poses/horse-09.obj')],
  // Marker vertices of the file: points surely on both surfaces.
  pairs: [[750, 3386], [524, 3737], [2716, 9514]].map(([a, b]) => [h[a], c[b]]),
});
await sheet(join(work, 'big-source.obj'), 500, 1);
await sheet(join(work, 'big-target.obj'), 510, 1.5);
const bigPoints = [[-0.5, -0.4], [0.45, -0.3], [0, 0.5], [0.6, 0.6]];
writeFileSync(join(work, 'big.markers'), bigPoints.map(([x, y]) => `${x} ${y} ${height(x, y, 1)} ${1.5 * x} ${1.5 * y} ${height(1.5 * x, 1.5 * y, 1.5)}`).join('\n') + '\n');
cases.push({
  name: 'two sheets (500,000 + 520,200 triangles), 4 markers',
  args: [join(work, 'big-source.obj'), join(work, 'big-target.obj'), '--markers', join(work, 'big.markers')],
  pairs: [[-0.2, 0.1], [0.3, 0.2], [-0.1, -0.6]].map(([x, y]) => [[x, y, height(x, y, 1)], [1.5 * x, 1.5 * y, height(1.5 * x, 1.5 * y, 1.5)]]),
});

const fmt = (xs) => xs.map((x) => Math.round(x)).join(', ');
console.log('| pair | page ready | a click: the page\'s work | a click: until drawn (SwiftShader) | "fit" until shown | the fit in the server |');
console.log('|---|---:|---:|---:|---:|---:|');
for (const k of cases) {
  const ready = [], work_ = [], frame = [], fit = [], server = [];
  for (let run_ = 0; run_ < 3; run_++) {
    const r = await run(k.args, { pairs: k.pairs, fit: true, size: [1280, 720], done: true });
    ready.push(r.ready_ms);
    for (const click of r.clicks) { work_.push(click.work_ms); frame.push(click.frame_ms); }
    fit.push(r.fit_page_ms);
    server.push(1000 * r.fit.seconds);
  }
  const median = (xs) => [...xs].sort((a, b) => a - b)[Math.floor(xs.length / 2)];
  console.log(`| ${k.name} | ${fmt(ready)} ms | median ${median(work_).toFixed(1)} ms, at most ${Math.max(...work_).toFixed(1)} ms | median ${Math.round(median(frame))} ms, at most ${Math.round(Math.max(...frame))} ms | ${fmt(fit)} ms | ${fmt(server)} ms |`);
}
