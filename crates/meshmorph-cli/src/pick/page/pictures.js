// The page of `meshmorph pick A.png B.png`: anchors clicked on two
// pictures, the morph they make played beside them, saved as the anchor
// file `meshmorph interpolate --anchors` reads.
//
// Everything it reads or writes goes through the server that served it
// (the token is in the page's address; every request is relative to it).
import { request } from './server.js';

const GRAB_RADIUS = 9; // screen pixels within which a press grabs an anchor
const CLICK_SLOP = 4; // pixels a click may move and stay a click
const UNDO_LIMIT = 500;
const PREVIEW_FPS = 12;

// ----------------------------------------------------------------- state

const state = {
  session: null,
  pictures: [null, null], // ImageBitmaps
  anchors: [], // { name, a: [x, y] | null, b: [x, y] | null }
  selected: -1,
  undo: [],
  redo: [],
  drag: null, // { index, side, moved, start: [x, y] }
  ended: false,
  previews: 0,
  previewError: null,
  previewSent: null, // the anchors' JSON of the preview in flight
  previewShown: null, // the anchors' JSON of the last answered
  previewWanted: false,
  sheet: null, // { image, frames, width, height }
};
const SIDES = ['a', 'b'];
const $ = (id) => document.getElementById(id);

function status(text, error = false) {
  const el = $('status');
  el.textContent = text;
  el.classList.toggle('error', error);
}

function complete() {
  return state.anchors.filter((x) => x.a && x.b);
}

function snapshot() {
  return JSON.stringify(state.anchors);
}

/** Records the state before a change, for undo. */
function remember() {
  state.undo.push(snapshot());
  if (state.undo.length > UNDO_LIMIT) state.undo.shift();
  state.redo = [];
}

function restore(from, to) {
  const text = from.pop();
  if (text === undefined) return;
  to.push(snapshot());
  state.anchors = JSON.parse(text);
  state.selected = Math.min(state.selected, state.anchors.length - 1);
  changed();
}

function freshName() {
  const taken = new Set(state.anchors.map((x) => x.name));
  for (let k = state.anchors.length + 1; ; k++) {
    if (!taken.has(`p${k}`)) return `p${k}`;
  }
}

// ------------------------------------------------------------------ views

/** Where picture `side` lies on its canvas: scale and offset (CSS px). */
function layout(side) {
  const canvas = $(side);
  const picture = state.session.pictures[SIDES.indexOf(side)];
  const w = canvas.clientWidth, h = canvas.clientHeight;
  const margin = 12;
  const s = Math.min((w - 2 * margin) / picture.width, (h - 2 * margin) / picture.height);
  return { s, ox: (w - s * picture.width) / 2, oy: (h - s * picture.height) / 2 };
}

/** A picture's pixel point to page (client) coordinates. */
function toScreen(side, x, y) {
  const { s, ox, oy } = layout(side);
  const r = $(side).getBoundingClientRect();
  return { x: r.left + ox + s * x, y: r.top + oy + s * y };
}

/** Client coordinates to a picture's pixels, or null outside it. */
function fromScreen(side, cx, cy) {
  const { s, ox, oy } = layout(side);
  const r = $(side).getBoundingClientRect();
  const x = (cx - r.left - ox) / s, y = (cy - r.top - oy) / s;
  const picture = state.session.pictures[SIDES.indexOf(side)];
  if (x < 0 || y < 0 || x > picture.width || y > picture.height) return null;
  return [x, y];
}

function draw(side) {
  const canvas = $(side);
  const ratio = window.devicePixelRatio || 1;
  const w = canvas.clientWidth, h = canvas.clientHeight;
  if (canvas.width !== Math.round(w * ratio) || canvas.height !== Math.round(h * ratio)) {
    canvas.width = Math.round(w * ratio);
    canvas.height = Math.round(h * ratio);
  }
  const g = canvas.getContext('2d');
  g.setTransform(ratio, 0, 0, ratio, 0, 0);
  g.clearRect(0, 0, w, h);
  const picture = state.pictures[SIDES.indexOf(side)];
  if (!picture) return;
  const { s, ox, oy } = layout(side);
  // A checkerboard behind, so that transparency shows.
  g.fillStyle = '#2c2f35';
  g.fillRect(ox, oy, s * picture.width, s * picture.height);
  g.imageSmoothingEnabled = s < 1;
  g.drawImage(picture, ox, oy, s * picture.width, s * picture.height);
  g.strokeStyle = '#555';
  g.strokeRect(ox - 0.5, oy - 0.5, s * picture.width + 1, s * picture.height + 1);
  g.font = 'bold 12px system-ui, sans-serif';
  state.anchors.forEach((anchor, k) => {
    const p = anchor[side];
    if (!p) return;
    const x = ox + s * p[0], y = oy + s * p[1];
    const selected = k === state.selected;
    const pending = !(anchor.a && anchor.b);
    g.beginPath();
    g.arc(x, y, selected ? 7 : 5, 0, 2 * Math.PI);
    g.fillStyle = pending ? '#ffd34d' : selected ? '#6cf' : '#ff5b8a';
    g.fill();
    g.lineWidth = 2;
    g.strokeStyle = '#111';
    g.stroke();
    g.fillStyle = '#fff';
    g.strokeStyle = '#000';
    g.lineWidth = 3;
    g.strokeText(String(k + 1), x + 8, y - 8);
    g.fillText(String(k + 1), x + 8, y - 8);
  });
}

function drawAll() {
  for (const side of SIDES) draw(side);
}

function listAnchors() {
  const list = $('anchors');
  list.replaceChildren();
  state.anchors.forEach((anchor, k) => {
    const li = document.createElement('li');
    li.classList.toggle('selected', k === state.selected);
    li.classList.toggle('pending', !(anchor.a && anchor.b));
    const number = document.createElement('span');
    number.className = 'number';
    number.textContent = String(k + 1);
    const name = document.createElement('input');
    name.value = anchor.name;
    name.title = 'its name in the anchor file: one word';
    name.addEventListener('change', () => {
      const word = name.value.trim().replace(/[\s,#]+/g, '_');
      remember();
      anchor.name = word;
      changed();
    });
    li.addEventListener('click', () => { state.selected = k; listAnchors(); drawAll(); });
    li.append(number, name);
    list.append(li);
  });
  const done = complete().length;
  $('count').textContent = `(${done}${done === state.anchors.length ? '' : ` + ${state.anchors.length - done} half-made`})`;
  $('undo').disabled = state.undo.length === 0 || state.ended;
  $('redo').disabled = state.redo.length === 0 || state.ended;
  $('delete').disabled = state.selected < 0 || state.ended;
}

/** After every change of the anchors: drawn, listed, previewed again. */
function changed() {
  drawAll();
  listAnchors();
  wantPreview();
}

// ---------------------------------------------------------------- preview

function anchorsToSend() {
  return complete().map((x) => ({ name: x.name, a: x.a, b: x.b }));
}

function wantPreview() {
  if (state.ended) return;
  const body = JSON.stringify(anchorsToSend());
  if (state.previewSent === body || (state.previewSent === null && state.previewShown === body)) return;
  state.previewWanted = true;
  if (state.previewSent === null) sendPreview();
}

async function sendPreview() {
  state.previewWanted = false;
  const anchors = anchorsToSend();
  state.previewSent = JSON.stringify(anchors);
  const note = $('preview-state');
  note.textContent = `making the morph with ${anchors.length} anchor${anchors.length === 1 ? '' : 's'}…`;
  note.classList.remove('error');
  try {
    const blob = await request('api/preview', { anchors }, 'blob');
    const image = await createImageBitmap(blob);
    const frames = state.session.preview.frames;
    state.sheet = { image, frames, width: image.width / frames, height: image.height };
    state.previewError = null;
    state.previews += 1;
    note.textContent = `the morph with ${anchors.length} anchor${anchors.length === 1 ? '' : 's'} (${frames} frames, played forward and back)`;
  } catch (e) {
    state.previewError = e.message;
    note.textContent = `no morph: ${e.message}`;
    note.classList.add('error');
  }
  const sent = state.previewSent;
  state.previewShown = sent;
  state.previewSent = null;
  if (state.previewWanted || sent !== JSON.stringify(anchorsToSend())) {
    if (!state.ended) sendPreview();
  }
}

function play(now) {
  const sheet = state.sheet;
  const canvas = $('preview');
  if (sheet) {
    if (canvas.width !== sheet.width || canvas.height !== sheet.height) {
      canvas.width = sheet.width;
      canvas.height = sheet.height;
    }
    const cycle = 2 * (sheet.frames - 1);
    const step = Math.floor((now / 1000) * PREVIEW_FPS) % cycle;
    const k = step < sheet.frames ? step : cycle - step;
    const g = canvas.getContext('2d');
    g.clearRect(0, 0, canvas.width, canvas.height);
    g.drawImage(sheet.image, k * sheet.width, 0, sheet.width, sheet.height, 0, 0, sheet.width, sheet.height);
  }
  requestAnimationFrame(play);
}

// ------------------------------------------------------------------ input

function nearest(side, cx, cy) {
  let best = -1, bestDistance = GRAB_RADIUS;
  state.anchors.forEach((anchor, k) => {
    const p = anchor[side];
    if (!p) return;
    const s = toScreen(side, p[0], p[1]);
    const d = Math.hypot(s.x - cx, s.y - cy);
    if (d <= bestDistance) { best = k; bestDistance = d; }
  });
  return best;
}

function press(side, event) {
  if (state.ended || event.button !== 0) return;
  const grabbed = nearest(side, event.clientX, event.clientY);
  if (grabbed >= 0) {
    state.selected = grabbed;
    state.drag = { index: grabbed, side, moved: false, start: [event.clientX, event.clientY], before: snapshot() };
    listAnchors();
    drawAll();
    return;
  }
  const point = fromScreen(side, event.clientX, event.clientY);
  if (!point) return;
  remember();
  const pending = state.anchors.findIndex((x) => !(x.a && x.b));
  if (pending >= 0) {
    // The half-made anchor completed (or its point on this side placed again).
    state.anchors[pending][side] = point;
    state.selected = pending;
  } else {
    const anchor = { name: freshName(), a: null, b: null };
    anchor[side] = point;
    state.anchors.push(anchor);
    state.selected = state.anchors.length - 1;
  }
  changed();
}

function move(side, event) {
  const drag = state.drag;
  if (!drag || drag.side !== side) return;
  const d = Math.hypot(event.clientX - drag.start[0], event.clientY - drag.start[1]);
  if (!drag.moved && d < CLICK_SLOP) return;
  const point = fromScreen(side, event.clientX, event.clientY);
  if (!point) return;
  drag.moved = true;
  state.anchors[drag.index][side] = point;
  drawAll();
}

function release() {
  const drag = state.drag;
  state.drag = null;
  if (!drag || !drag.moved) return;
  state.undo.push(drag.before);
  if (state.undo.length > UNDO_LIMIT) state.undo.shift();
  state.redo = [];
  changed();
}

function remove() {
  if (state.selected < 0 || state.ended) return;
  remember();
  state.anchors.splice(state.selected, 1);
  state.selected = Math.min(state.selected, state.anchors.length - 1);
  changed();
}

async function save() {
  if (state.ended) return;
  const anchors = anchorsToSend();
  try {
    const answer = await request('api/save', { anchors });
    const half = state.anchors.length - anchors.length;
    document.body.dataset.saved = String(answer.anchors);
    status(`saved ${answer.anchors} anchor${answer.anchors === 1 ? '' : 's'} to ${answer.saved}${half ? ` (${half} half-made left out)` : ''}`);
  } catch (e) {
    status(`not saved: ${e.message}`, true);
  }
}

async function done() {
  if (state.ended) return;
  try {
    await request('api/done', {});
  } catch (e) {
    status(`the server did not answer "done": ${e.message}`, true);
    return;
  }
  state.ended = true;
  listAnchors();
  for (const id of ['save', 'done']) $(id).disabled = true;
  status('done: the server has stopped; this page can be closed');
}

// ------------------------------------------------------------------ start

async function start() {
  try {
    state.session = await request('api/session');
  } catch (e) {
    status(`cannot read the session: ${e.message}`, true);
    return;
  }
  const [pa, pb] = state.session.pictures;
  $('files').textContent = `${pa.name} (${pa.width} × ${pa.height}) → ${pb.name} (${pb.width} × ${pb.height}), saved to ${state.session.output}`;
  state.anchors = state.session.anchors.map((x) => ({ name: x.name || freshName(), a: x.a, b: x.b }));
  try {
    state.pictures = await Promise.all(['a', 'b'].map(async (side) =>
      createImageBitmap(await request(`api/picture/${side}`, undefined, 'blob'))));
  } catch (e) {
    status(`cannot read the pictures: ${e.message}`, true);
    return;
  }
  for (const side of SIDES) {
    const canvas = $(side);
    canvas.addEventListener('pointerdown', (e) => { canvas.setPointerCapture(e.pointerId); press(side, e); });
    canvas.addEventListener('pointermove', (e) => move(side, e));
    canvas.addEventListener('pointerup', release);
  }
  $('undo').addEventListener('click', () => restore(state.undo, state.redo));
  $('redo').addEventListener('click', () => restore(state.redo, state.undo));
  $('delete').addEventListener('click', remove);
  $('save').addEventListener('click', save);
  $('done').addEventListener('click', done);
  window.addEventListener('keydown', (e) => {
    if (e.target instanceof HTMLInputElement) return;
    const key = e.key.toLowerCase();
    if ((e.ctrlKey || e.metaKey) && key === 's') { e.preventDefault(); save(); }
    else if ((e.ctrlKey || e.metaKey) && key === 'z' && e.shiftKey) { e.preventDefault(); restore(state.redo, state.undo); }
    else if ((e.ctrlKey || e.metaKey) && key === 'z') { e.preventDefault(); restore(state.undo, state.redo); }
    else if (key === 'delete' || key === 'backspace') remove();
    else if (key === 'escape') {
      const pending = state.anchors.findIndex((x) => !(x.a && x.b));
      if (pending >= 0) { remember(); state.anchors.splice(pending, 1); state.selected = -1; changed(); }
    }
  });
  window.addEventListener('resize', drawAll);
  status('click a point on either picture, then the same point on the other');
  changed();
  requestAnimationFrame(play);
  document.body.dataset.ready = 'yes';
}

// What a check drives the page by.
window.pick = {
  toScreen,
  anchors: () => JSON.parse(JSON.stringify(state.anchors)),
  previews: () => state.previews,
  previewError: () => state.previewError,
  previewing: () => state.previewSent !== null || state.previewWanted,
  status: () => ({ text: $('status').textContent, error: $('status').classList.contains('error') }),
};

start();
