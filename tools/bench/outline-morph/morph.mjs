// The peers of crates/meshmorph/examples/outline_benchmark.rs: GSAP's
// MorphSVG (linear and rotational) and flubber morph the same pairs of
// drawings; their frames are written as loops of points for the example to
// measure, with the times of the 500-point pairs.
//
//   node morph.mjs PAIRS.json FRAMES.json
//
// GSAP runs without a browser: its path is tweened as a property of a plain
// object (`prop: 'd'`), and the frames are read at full precision from the
// plugin's `render` callback (each subpath a run of cubic Béziers, sampled
// at 4 points a curve; the last frame is read just short of the end, where
// the plugin shows the end path as given). flubber takes one ring a shape (no holes).

import { createRequire } from 'node:module';
import { readFileSync, writeFileSync } from 'node:fs';
import { performance } from 'node:perf_hooks';

const require = createRequire(import.meta.url);
// The plugin reads `document` once when it registers; nothing else of the DOM.
globalThis.document ??= {};
const { gsap } = require('gsap/dist/gsap.js');
const { MorphSVGPlugin } = require('gsap/dist/MorphSVGPlugin.js');
const flubber = require('flubber');

MorphSVGPlugin.headless = true;
gsap.registerPlugin(MorphSVGPlugin);

const [pairsPath, outPath] = process.argv.slice(2);
if (!pairsPath || !outPath) {
  console.error('usage: node morph.mjs PAIRS.json FRAMES.json');
  process.exit(2);
}
const input = JSON.parse(readFileSync(pairsPath, 'utf8'));
const frames = input.frames;

/** An SVG path of loops of points. */
function pathString(loops) {
  return loops.map((l) => 'M' + l.map((p) => `${p[0]} ${p[1]}`).join(' L') + ' Z').join(' ');
}

/** GSAP's raw path (subpaths of cubic Béziers) as loops of points. */
function rawToLoops(raw) {
  return raw.map((s) => {
    const out = [];
    for (let i = 0; i + 7 < s.length; i += 6) {
      const [x0, y0, x1, y1, x2, y2, x3, y3] = s.slice(i, i + 8);
      for (const u of [0, 0.25, 0.5, 0.75]) {
        const v = 1 - u;
        const b = [v * v * v, 3 * v * v * u, 3 * v * u * u, u * u * u];
        out.push([
          b[0] * x0 + b[1] * x1 + b[2] * x2 + b[3] * x3,
          b[0] * y0 + b[1] * y1 + b[2] * y2 + b[3] * y3,
        ]);
      }
    }
    return out;
  });
}

/** A paused GSAP tween of `a` into `b`, and the object it writes to. */
function gsapTween(a, b, type, render) {
  const target = { d: pathString(a) };
  const tween = gsap.to(target, {
    morphSVG: { shape: pathString(b), prop: 'd', type, render },
    duration: 1,
    ease: 'none',
    paused: true,
  });
  return { target, tween };
}

function gsapFrames(a, b, type) {
  let raw = null;
  const { tween } = gsapTween(a, b, type, (r) => {
    raw = r;
  });
  const out = [];
  for (let k = 0; k < frames; k++) {
    // At 1 (GSAP's times are rounded: within about 1e-8 of it) the plugin
    // writes the end path as given and leaves the raw path's control points
    // where they were: the last frame is read just short of it.
    tween.progress(Math.min(k / (frames - 1), 1 - 1e-6));
    if (!raw) throw new Error('GSAP rendered nothing');
    out.push(rawToLoops(raw));
  }
  return out;
}

function flubberFrames(a, b) {
  if (a.length > 1 || b.length > 1) return { unsupported: 'one ring a shape (holes dropped)' };
  const interpolate = flubber.interpolate(a[0], b[0], { string: false });
  const out = [];
  for (let k = 0; k < frames; k++) out.push([interpolate(k / (frames - 1))]);
  return { frames: out };
}

const methods = [
  { name: 'GSAP MorphSVG linear', run: (a, b) => ({ frames: gsapFrames(a, b, 'linear') }) },
  { name: 'GSAP MorphSVG rotational', run: (a, b) => ({ frames: gsapFrames(a, b, 'rotational') }) },
  { name: 'flubber', run: flubberFrames },
];

const result = { methods: [], timed: [] };
for (const m of methods) {
  const pairs = {};
  for (const p of input.pairs) {
    try {
      pairs[p.name] = m.run(p.a, p.b);
    } catch (e) {
      pairs[p.name] = { unsupported: `failed: ${e.message}` };
    }
  }
  result.methods.push({ name: m.name, pairs });
}

/** Setup and per-frame times (ms, µs) of 60 SVG path strings: the median of 5 runs after a warm-up. */
function time(setup, frame) {
  const runs = [];
  for (let r = 0; r < 6; r++) {
    const t0 = performance.now();
    const state = setup();
    const t1 = performance.now();
    let total = 0;
    for (let f = 0; f < 60; f++) total += frame(state, f / 59).length;
    const t2 = performance.now();
    if (total === 0) throw new Error('no path written');
    if (r > 0) runs.push([t1 - t0, ((t2 - t1) / 60) * 1000]);
  }
  const median = (k) => runs.map((x) => x[k]).sort((x, y) => x - y)[2];
  return { setup_ms: median(0), frame_us: median(1) };
}

for (const p of input.timed) {
  for (const type of ['linear', 'rotational']) {
    const t = time(
      () => {
        const tw = gsapTween(p.a, p.b, type);
        tw.tween.progress(0); // the plugin matches the two paths here, on the first render
        return tw;
      },
      ({ target, tween }, t) => {
        tween.progress(t);
        return target.d;
      },
    );
    result.timed.push({ pair: p.name, method: `GSAP MorphSVG ${type}`, ...t });
  }
  const t = time(
    () => flubber.interpolate(p.a[0], p.b[0]),
    (interpolate, t) => interpolate(t),
  );
  result.timed.push({ pair: p.name, method: 'flubber', ...t });
}

writeFileSync(outPath, JSON.stringify(result));
console.log(`wrote ${outPath}`);
