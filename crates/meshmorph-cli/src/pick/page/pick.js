// The page of `meshmorph pick`: the source and the target side by side (or
// overlaid), marker pairs made by clicking a point of each, and the
// correspondence's fit and a transferred pose shown on demand. Every URL is
// relative: the page's address holds the session's token.
import * as THREE from './three.module.js';
import { OrbitControls } from './OrbitControls.js';
import { request } from './server.js';

const $ = (id) => document.getElementById(id);
const SOURCE = 0, TARGET = 1;
const SIDES = ['source', 'target'];
// The fit's colour scale, as `correspond --png` draws it: a colour every
// 0.25 % of the target's diagonal, green to red up to 1.75 %, then purple.
const FIT_STEP = 0.0025;
const FIT_COLOURS = [0x2e9e4f, 0x7cbf3a, 0xd8d23a, 0xf0a830, 0xee7a2a, 0xe0502a, 0xc8302a, 0x8e3fbf];
const MARKER_RADIUS = 0.006; // of a mesh's bounding-box diagonal
const CLICK_SLOP = 4; // pixels a click may move and stay a click
const UNDO_LIMIT = 500;

// ---------------------------------------------------------------- server

/** A mesh as the server sends it: counts, f32 positions, u32 corners. */
function parseMesh(buffer) {
  const view = new DataView(buffer);
  const nv = view.getUint32(0, true), nt = view.getUint32(4, true);
  return {
    positions: new Float32Array(buffer, 8, 3 * nv),
    index: new Uint32Array(buffer, 8 + 12 * nv, 3 * nt),
  };
}

/** A fit as the server sends it: the report, then f32 arrays. */
function parseFit(buffer, sourceVertices, targetVertices) {
  const length = new DataView(buffer).getUint32(0, true);
  const report = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, 4, length)));
  let at = 4 + length;
  at += (4 - (at % 4)) % 4;
  const take = (n) => { const a = new Float32Array(buffer, at, n); at += 4 * n; return a; };
  const deformed = take(3 * sourceVertices);
  const distances = take(targetVertices);
  const pose = report.pose ? take(3 * targetVertices) : null;
  return { report, deformed, distances, pose };
}

// ---------------------------------------------------------------- surfaces

/** A surface point's position on a mesh (file coordinates). */
function pointPosition(mesh, p, out = new THREE.Vector3()) {
  const pos = mesh.positions;
  if (p.vertex !== undefined) return out.fromArray(pos, 3 * p.vertex);
  out.set(0, 0, 0);
  for (let i = 0; i < 3; i++) {
    const v = mesh.index[3 * p.triangle + i];
    out.x += p.barycentric[i] * pos[3 * v];
    out.y += p.barycentric[i] * pos[3 * v + 1];
    out.z += p.barycentric[i] * pos[3 * v + 2];
  }
  return out;
}

/** The surface point a ray hit: a triangle's point, or its nearest corner.
 * The triangle's corners are taken where the object hit draws them (a
 * posed copy of the mesh gives the same point of the mesh). */
function surfacePoint(mesh, hit, object, snap) {
  const local = object.worldToLocal(hit.point.clone());
  const t = hit.faceIndex;
  const drawn = object.geometry.attributes.position.array;
  const corners = [0, 1, 2].map((i) => new THREE.Vector3().fromArray(drawn, 3 * mesh.index[3 * t + i]));
  const b = new THREE.Vector3();
  THREE.Triangle.getBarycoord(local, corners[0], corners[1], corners[2], b);
  let w = [b.x, b.y, b.z].map((x) => Math.min(1, Math.max(0, x)));
  if (snap) {
    const k = w.indexOf(Math.max(...w));
    return { vertex: mesh.index[3 * t + k] };
  }
  const sum = w[0] + w[1] + w[2];
  w = w.map((x) => x / sum);
  return { triangle: t, barycentric: w };
}

// ---------------------------------------------------------------- views

const sphere = new THREE.SphereGeometry(1, 16, 12);
const markerMaterials = {
  plain: new THREE.MeshBasicMaterial({ color: 0x4da3ff }),
  pending: new THREE.MeshBasicMaterial({ color: 0xffffff }),
  selected: new THREE.MeshBasicMaterial({ color: 0xff4dd2 }),
  hover: new THREE.MeshBasicMaterial({ color: 0xffd34d }),
  poor: new THREE.MeshBasicMaterial({ color: 0xff3b2f, wireframe: true }),
};

/** A mesh's geometry and the transform that centres it and makes its
 * bounding-box diagonal 1, so that linked views show both alike. */
function prepare(mesh) {
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(mesh.positions, 3));
  geometry.setIndex(new THREE.BufferAttribute(mesh.index, 1));
  geometry.computeVertexNormals();
  geometry.computeBoundingBox();
  geometry.computeBoundingSphere();
  const box = geometry.boundingBox;
  mesh.diagonal = box.getSize(new THREE.Vector3()).length() || 1;
  mesh.centre = box.getCenter(new THREE.Vector3());
  mesh.geometry = geometry;
  return mesh;
}

/** A group holding a mesh's objects in its normalised place. */
function normalised(mesh) {
  const group = new THREE.Group();
  group.scale.setScalar(1 / mesh.diagonal);
  group.position.copy(mesh.centre).multiplyScalar(-1 / mesh.diagonal);
  return group;
}

class View {
  constructor(canvas, mesh, colour) {
    this.canvas = canvas;
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio);
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0x2a2d33);
    this.camera = new THREE.PerspectiveCamera(35, 1, 0.01, 100);
    // Y up (as glTF, Blender's exports and most characters stand), looking
    // across the thinner of the other two sides: a character from the side,
    // a face or a sheet from the front.
    const size = mesh.geometry.boundingBox.getSize(new THREE.Vector3());
    if (size.x < size.z) this.camera.position.set(1.9, 0, 0);
    else this.camera.position.set(0, 0, 1.9);
    this.camera.lookAt(0, 0, 0);
    const light = new THREE.DirectionalLight(0xffffff, 2.2);
    light.position.set(0.6, 0.8, 1);
    this.camera.add(light);
    this.scene.add(this.camera, new THREE.HemisphereLight(0xffffff, 0x404050, 1.1));
    this.root = normalised(mesh);
    this.material = new THREE.MeshStandardMaterial({ color: colour, roughness: 0.85, side: THREE.DoubleSide });
    this.object = new THREE.Mesh(mesh.geometry, this.material);
    this.markers = new THREE.Group();
    this.root.add(this.object, this.markers);
    this.scene.add(this.root);
    this.controls = new OrbitControls(this.camera, canvas);
    this.controls.enableDamping = false;
    this.mesh = mesh;
    // The other mesh drawn in this view when overlaid, and the fit's layers.
    this.extra = new THREE.Group();
    this.scene.add(this.extra);
    new ResizeObserver(() => this.resize()).observe(canvas);
    this.resize();
  }

  resize() {
    const { clientWidth: w, clientHeight: h } = this.canvas;
    if (!w || !h) return;
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    render();
  }

  /** Normalised device coordinates of a pointer event. */
  ndc(event) {
    const r = this.canvas.getBoundingClientRect();
    return new THREE.Vector2(((event.clientX - r.left) / r.width) * 2 - 1, -((event.clientY - r.top) / r.height) * 2 + 1);
  }
}

// ---------------------------------------------------------------- state

const state = {
  session: null,
  meshes: [null, null],
  views: [null, null],
  ghost: null, // the source drawn in the target's view when overlaid
  pairs: [], // { name, source, target }: a side is null until picked
  selected: -1,
  hovered: -1,
  undo: [],
  redo: [],
  fit: null,
  nearPoor: new Set(),
  closed: false,
};
const timings = { ready: null, lastClickWork: null, lastClick: null, lastFit: null };
let fitGeneration = 0;

function snapshot() {
  return JSON.stringify({ pairs: state.pairs, selected: state.selected });
}

function restore(text) {
  const s = JSON.parse(text);
  state.pairs = s.pairs;
  state.selected = s.selected;
}

/** Makes a change that undo can take back. */
function change(apply, { fit = true } = {}) {
  state.undo.push(snapshot());
  if (state.undo.length > UNDO_LIMIT) state.undo.shift();
  state.redo = [];
  apply();
  changed(fit);
}

function changed(fit = true) {
  if (fit) state.nearPoor = new Set(); // the last fit's pairs are not these
  drawMarkers();
  listPairs();
  showGuide();
  // Guided, a fit needs three landmarks (the preview twelve).
  if (fit && $('autofit').checked && (!guide.list.length || placed().size >= 3)) scheduleFit();
}

function undo() {
  if (!state.undo.length) return;
  state.redo.push(snapshot());
  restore(state.undo.pop());
  changed();
}

function redo() {
  if (!state.redo.length) return;
  state.undo.push(snapshot());
  restore(state.redo.pop());
  changed();
}

const complete = (p) => p.source && p.target;
const completePairs = () => state.pairs.filter(complete).map((p) => ({ name: p.name || null, source: p.source, target: p.target }));

/** A point picked on `side`: it completes the pair waiting for it, replaces
 * the waiting pair's point on the same side, or starts a new pair. */
function addPoint(side, point) {
  if (guide.list.length) return placeLandmark(side, point);
  const key = SIDES[side], other = SIDES[1 - side];
  change(() => {
    const waiting = state.pairs.findIndex((p) => !complete(p));
    if (waiting >= 0) {
      state.pairs[waiting][key] = point;
      state.selected = waiting;
    } else {
      state.pairs.push({ name: '', [key]: point, [other]: null });
      state.selected = state.pairs.length - 1;
    }
  }, { fit: state.pairs.some((p) => !complete(p)) });
}

function deleteSelected() {
  if (state.selected < 0 || state.selected >= state.pairs.length) return;
  change(() => {
    state.pairs.splice(state.selected, 1);
    state.selected = Math.min(state.selected, state.pairs.length - 1);
  });
}

function cancelPending() {
  const waiting = state.pairs.findIndex((p) => !complete(p));
  if (waiting >= 0) change(() => { state.pairs.splice(waiting, 1); state.selected = -1; }, { fit: false });
}

// ---------------------------------------------------------------- guided (pick --template)

// The template's landmarks to place on the head (the target), in order:
// each pair is named by its landmark, its source point the landmark's
// vertex on the template.
const guide = { list: [], current: -1, marker: null };

function placed() {
  return new Set(state.pairs.filter(complete).map((p) => p.name));
}

/** The first landmark not yet placed from `from` on (wrapping), or -1. */
function nextToPlace(from) {
  const done = placed();
  for (let i = 0; i < guide.list.length; i++) {
    const k = (from + i) % guide.list.length;
    if (!done.has(guide.list[k].name)) return k;
  }
  return -1;
}

/** A click on the head places the landmark lit on the template (again,
 * when it was placed); a click on the template only says what to do. */
function placeLandmark(side, point) {
  const g = guide.list[guide.current];
  if (side === SOURCE || !g) {
    status(g ? `the template's points are fixed: click ${g.name} on your head` : 'every landmark is placed: click one in the list to place it again', !g);
    return;
  }
  change(() => {
    const pair = { name: g.name, source: { vertex: g.vertex }, target: point };
    const k = state.pairs.findIndex((p) => p.name === g.name);
    if (k >= 0) state.pairs[k] = pair;
    else state.pairs.push(pair);
    state.selected = state.pairs.findIndex((p) => p.name === g.name);
    guide.current = nextToPlace(guide.current + 1);
  });
}

function skip() {
  if (guide.current < 0) return;
  guide.current = nextToPlace(guide.current + 1);
  showGuide();
}

/** The next landmark named and lit on the template, and how many are placed. */
function showGuide() {
  if (!guide.list.length) return;
  const g = guide.list[guide.current];
  const n = placed().size, needed = state.session.guide.needed;
  $('guide-next').textContent = g ? `Next: ${g.name} (${guide.current + 1} of ${guide.list.length}): lit on the template, click it on your head` : 'Every landmark is placed.';
  $('guide-count').textContent = `${n} placed; ${n >= needed ? `each fit previews ${state.session.guide.preview.join(' and ')} on your head` : `the preview starts at ${needed}`}`;
  guide.marker.visible = !!g;
  if (g) {
    pointPosition(state.meshes[SOURCE], { vertex: g.vertex }, guide.marker.position);
    guide.marker.scale.setScalar(2 * MARKER_RADIUS * state.meshes[SOURCE].diagonal);
  }
  render();
}

function startGuide(session) {
  guide.list = session.guide.landmarks;
  guide.marker = new THREE.Mesh(sphere, new THREE.MeshBasicMaterial({ color: 0x40e0ff }));
  state.views[SOURCE].root.add(guide.marker);
  guide.current = nextToPlace(0);
  $('guide').hidden = false;
  $('skip').addEventListener('click', skip);
  document.querySelector('#source-view .label').textContent = `template (${session.guide.template})`;
  document.querySelector('#target-view .label').textContent = 'your head';
  document.querySelector('#pose-toggle').lastChild.textContent = ` preview ${session.guide.preview.join(' + ')}`;
  $('show-pose').checked = true;
  $('autofit').checked = true;
  $('mirror').hidden = true;
  for (const hint of document.querySelectorAll('aside > .hint')) hint.hidden = true;
}

// ---------------------------------------------------------------- drawing

let renderQueued = false;
function render() {
  if (renderQueued) return;
  renderQueued = true;
  requestAnimationFrame(() => {
    renderQueued = false;
    for (const v of state.views) if (v && v.canvas.clientWidth) v.renderer.render(v.scene, v.camera);
  });
}

function markerMaterial(k, pending) {
  if (k === state.hovered) return markerMaterials.hover;
  if (k === state.selected) return markerMaterials.selected;
  return pending ? markerMaterials.pending : markerMaterials.plain;
}

function drawMarkers() {
  const groups = [[state.views[SOURCE].markers], [state.views[TARGET].markers]];
  if (state.ghost) groups[SOURCE].push(state.ghost.markers);
  for (let side = 0; side < 2; side++) {
    const mesh = state.meshes[side];
    for (const group of groups[side]) {
      group.clear();
      state.pairs.forEach((pair, k) => {
        const p = pair[SIDES[side]];
        if (!p) return;
        const m = new THREE.Mesh(sphere, markerMaterial(k, !complete(pair)));
        pointPosition(mesh, p, m.position);
        m.scale.setScalar(MARKER_RADIUS * mesh.diagonal * (k === state.hovered || k === state.selected ? 1.5 : 1));
        m.userData.pair = k;
        group.add(m);
      });
    }
  }
  render();
}

function listPairs() {
  const list = $('pairs');
  list.replaceChildren(...state.pairs.map((pair, k) => {
    const li = document.createElement('li');
    li.className = [k === state.selected && 'selected', k === state.hovered && 'hover', !complete(pair) && 'pending', state.nearPoor.has(k) && 'near-poor'].filter(Boolean).join(' ');
    const number = document.createElement('span');
    number.className = 'number';
    number.textContent = String(k + 1);
    const name = document.createElement('input');
    name.value = pair.name ?? '';
    name.placeholder = 'name';
    name.readOnly = guide.list.length > 0;
    name.addEventListener('change', () => change(() => { state.pairs[k].name = name.value.trim(); }, { fit: false }));
    const remove = document.createElement('button');
    remove.textContent = '×';
    remove.title = 'delete this pair';
    remove.addEventListener('click', (e) => { e.stopPropagation(); state.selected = k; deleteSelected(); });
    li.append(number, name, remove);
    li.addEventListener('click', () => {
      state.selected = k;
      const g = guide.list.findIndex((l) => l.name === pair.name);
      if (g >= 0) guide.current = g;
      changed(false);
    });
    li.addEventListener('mouseenter', () => hover(k));
    li.addEventListener('mouseleave', () => hover(-1));
    return li;
  }));
  $('count').textContent = `(${state.pairs.filter(complete).length})`;
  const canMirror = state.session.mirror_planes.every(Boolean) && state.selected >= 0 && state.pairs[state.selected] && complete(state.pairs[state.selected]);
  $('mirror').disabled = state.closed || !canMirror;
  $('delete').disabled = state.closed || state.selected < 0;
  $('undo').disabled = state.closed || !state.undo.length;
  $('redo').disabled = state.closed || !state.redo.length;
}

function hover(k) {
  if (k === state.hovered) return;
  state.hovered = k;
  drawMarkers();
  for (const [i, li] of [...$('pairs').children].entries()) li.classList.toggle('hover', i === k);
}

function status(text, error = false) {
  $('status').textContent = text;
  $('status').classList.toggle('error', error);
}

// ---------------------------------------------------------------- pointer

const raycaster = new THREE.Raycaster();

/** What the pointer is over in `view`: a marker (its pair and side) or a
 * mesh (its side and the hit). */
function under(view, event) {
  raycaster.setFromCamera(view.ndc(event), view.camera);
  const markerGroups = [[view.markers, view === state.views[SOURCE] ? SOURCE : TARGET]];
  const meshes = [[view.object, view === state.views[SOURCE] ? SOURCE : TARGET]];
  // The target shown posed (a transferred pose, the expressions' preview).
  if (view.poseObject) meshes.push([view.poseObject, TARGET]);
  if (view === state.views[TARGET] && state.ghost && state.ghost.root.visible) {
    markerGroups.push([state.ghost.markers, SOURCE]);
    meshes.push([state.ghost.object, SOURCE]);
  }
  // The nearest visible surface, then a marker in front of it (a marker on
  // the far side of the mesh is hidden, and not picked).
  let surface = null;
  for (const [object, side] of meshes) {
    if (!object.visible || !object.parent?.visible) continue;
    const hit = raycaster.intersectObject(object, false)[0];
    if (hit && (!surface || hit.distance < surface.hit.distance)) surface = { side, hit, object };
  }
  let marker = null;
  for (const [group, side] of markerGroups) {
    if (!group.parent?.visible) continue;
    for (const hit of raycaster.intersectObjects(group.children, false)) {
      const radius = hit.object.scale.x * group.parent.scale.x;
      const visible = !surface || hit.distance <= surface.hit.distance + radius;
      if (visible && (!marker || hit.distance < marker.hit.distance)) marker = { marker: hit.object.userData.pair, side, hit };
    }
  }
  return marker ?? surface;
}

function attachPointer(view) {
  let down = null, drag = null;
  view.canvas.addEventListener('pointerdown', (event) => {
    if (state.closed || event.button !== 0) return;
    down = { x: event.clientX, y: event.clientY };
    const u = under(view, event);
    if (u && u.marker !== undefined && u.marker === state.selected) {
      drag = { pair: u.marker, side: u.side, before: snapshot() };
      view.controls.enabled = false;
      view.canvas.setPointerCapture(event.pointerId);
    }
  });
  view.canvas.addEventListener('pointermove', (event) => {
    if (drag) {
      raycaster.setFromCamera(view.ndc(event), view.camera);
      const object = drag.side === SOURCE && view === state.views[TARGET] ? state.ghost.object : view.object;
      const hit = raycaster.intersectObject(object, false)[0];
      if (hit) {
        state.pairs[drag.pair][SIDES[drag.side]] = surfacePoint(state.meshes[drag.side], hit, object, event.altKey);
        drawMarkers();
      }
      return;
    }
    if (down) return;
    const u = under(view, event);
    hover(u && u.marker !== undefined ? u.marker : -1);
  });
  view.canvas.addEventListener('pointerup', (event) => {
    const start = performance.now();
    const wasDown = down;
    down = null;
    if (drag) {
      view.controls.enabled = true;
      const moved = snapshot() !== drag.before;
      if (moved) {
        state.undo.push(drag.before);
        state.redo = [];
        changed();
      }
      drag = null;
      if (moved) return;
    }
    if (!wasDown || Math.hypot(event.clientX - wasDown.x, event.clientY - wasDown.y) > CLICK_SLOP) return;
    const u = under(view, event);
    if (!u) return;
    if (u.marker !== undefined) {
      state.selected = u.marker;
      changed(false);
    } else {
      addPoint(u.side, surfacePoint(state.meshes[u.side], u.hit, u.object, event.altKey));
    }
    timings.lastClickWork = performance.now() - start;
    requestAnimationFrame(() => { timings.lastClick = performance.now() - start; });
  });
}

// ---------------------------------------------------------------- linked views

let syncing = false;
function link(from, to) {
  from.controls.addEventListener('change', () => {
    render();
    if (syncing || !$('linked').checked) return;
    syncing = true;
    to.camera.position.copy(from.camera.position);
    to.camera.quaternion.copy(from.camera.quaternion);
    to.controls.target.copy(from.controls.target);
    to.controls.update();
    syncing = false;
  });
}

// ---------------------------------------------------------------- fit

let fitTimer = null;
function scheduleFit() {
  clearTimeout(fitTimer);
  fitTimer = setTimeout(fit, 300);
}

function colourOf(d) {
  return FIT_COLOURS[Math.min(FIT_COLOURS.length - 1, Math.floor(d / FIT_STEP))];
}

let fitRunning = false, fitAgain = false;
/** One fit at a time: a fit asked for meanwhile runs when it is done. */
async function fit() {
  if (fitRunning) { fitAgain = true; return; }
  fitRunning = true;
  try {
    do {
      fitAgain = false;
      await fitOnce();
    } while (fitAgain);
  } finally {
    fitRunning = false;
  }
}

async function fitOnce() {
  const pairs = completePairs();
  // The list's index of each pair sent, to name the pairs the fit names.
  const sent = state.pairs.map((p, k) => (complete(p) ? k : -1)).filter((k) => k >= 0);
  const generation = ++fitGeneration;
  const start = performance.now();
  status(`fitting ${pairs.length} pairs…`);
  document.body.dataset.fit = 'running';
  let result;
  try {
    const buffer = await request('api/fit', { pairs }, 'binary');
    result = parseFit(buffer, state.meshes[SOURCE].positions.length / 3, state.meshes[TARGET].positions.length / 3);
  } catch (e) {
    if (generation === fitGeneration) {
      status(`fit failed: ${e.message}`, true);
      document.body.dataset.fit = 'failed';
    }
    return;
  }
  if (generation !== fitGeneration) return; // a newer fit is on its way
  result.report.nearest_pairs = result.report.nearest_pairs.map((ks) => ks.map((k) => sent[k]));
  showFit(result);
  requestAnimationFrame(() => {
    timings.lastFit = performance.now() - start;
    document.body.dataset.fit = 'done';
  });
}

function showFit({ report, deformed, distances, pose }) {
  state.fit = report;
  const view = state.views[TARGET];
  const target = state.meshes[TARGET];
  // The target coloured by its distance to the deformed source.
  const colours = new Float32Array(distances.length * 3);
  const c = new THREE.Color();
  distances.forEach((d, v) => { c.setHex(colourOf(d)); colours.set([c.r, c.g, c.b], 3 * v); });
  target.geometry.setAttribute('color', new THREE.BufferAttribute(colours, 3));
  view.material.vertexColors = true;
  view.material.color.set(0xffffff);
  view.material.needsUpdate = true;
  // The deformed source over it, and the poor regions.
  view.fitLayer?.removeFromParent();
  view.poseObject = null;
  const layer = normalised(target);
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(deformed, 3));
  g.setIndex(new THREE.BufferAttribute(state.meshes[SOURCE].index, 1));
  const wire = new THREE.Mesh(g, new THREE.MeshBasicMaterial({ color: 0xffffff, wireframe: true, transparent: true, opacity: 0.12 }));
  layer.add(wire);
  view.fitWire = wire;
  for (const region of report.fit.poor_regions) {
    const ring = new THREE.Mesh(sphere, markerMaterials.poor);
    ring.position.fromArray(region.point);
    ring.scale.setScalar(0.02 * target.diagonal);
    layer.add(ring);
  }
  if (pose) {
    const pg = new THREE.BufferGeometry();
    pg.setAttribute('position', new THREE.BufferAttribute(pose, 3));
    pg.setIndex(new THREE.BufferAttribute(target.index, 1));
    pg.computeVertexNormals();
    view.poseObject = new THREE.Mesh(pg, new THREE.MeshStandardMaterial({ color: 0xd9b38f, roughness: 0.85, side: THREE.DoubleSide }));
    view.poseObject.visible = $('show-pose').checked;
    layer.add(view.poseObject);
    $('pose-toggle').hidden = false;
  }
  view.fitLayer = layer;
  view.extra.add(layer);
  showPose();
  state.nearPoor = new Set(report.nearest_pairs.flat());
  listPairs();
  reportFit(report);
  status(`fitted ${report.markers.markers} pairs in ${report.seconds.toFixed(2)} s`);
  render();
}

function showPose() {
  const view = state.views[TARGET];
  const on = $('show-pose').checked && view.poseObject;
  if (view.poseObject) view.poseObject.visible = !!on;
  if (view.fitWire) view.fitWire.visible = !on;
  view.object.visible = !on;
  render();
}

function percent(x) {
  return `${(100 * x).toFixed(2)} %`;
}

function reportFit(report) {
  const f = report.fit;
  const rows = [
    ['mean distance', percent(f.mean_distance)],
    ['95th percentile', percent(f.distance_95th_percentile)],
    ['uncovered', percent(f.uncovered_area)],
    [`poor (past ${percent(f.poor_threshold)})`, `${percent(f.poor_area)} in ${f.poor_regions.length} regions`],
    ['matched triangle pairs', String(report.matched_pairs)],
  ];
  const table = document.createElement('table');
  for (const [k, v] of rows) {
    const tr = table.insertRow();
    tr.insertCell().textContent = k;
    tr.insertCell().textContent = v;
  }
  const regions = f.poor_regions.map((r, i) => {
    const p = document.createElement('p');
    const near = (report.nearest_pairs[i] ?? []).map((k) => `#${k + 1}${state.pairs[k]?.name ? ` ${state.pairs[k].name}` : ''}`);
    p.textContent = `region ${i + 1}: ${percent(r.area)} of the area, up to ${percent(r.largest_distance)}; nearest pairs ${near.join(', ') || '(none)'}`;
    return p;
  });
  const warnings = report.warnings.map((w) => {
    const p = document.createElement('p');
    p.className = 'warn';
    p.textContent = w;
    return p;
  });
  $('fit-report').replaceChildren(table, ...regions, ...warnings);
  $('fit-report').dataset.mean = String(f.mean_distance);
}

// ---------------------------------------------------------------- actions

async function mirror() {
  const pair = state.pairs[state.selected];
  if (!pair || !complete(pair)) return;
  try {
    const answer = await request('api/mirror', { pairs: [{ source: pair.source, target: pair.target }] });
    const m = answer.pairs[0];
    change(() => {
      state.pairs.push({ name: mirroredName(pair.name), source: m.source, target: m.target });
      state.selected = state.pairs.length - 1;
    });
  } catch (e) {
    status(`mirror failed: ${e.message}`, true);
  }
}

/** "left_eye" for "right_eye", "hand.L" for "hand.R"; else "name (mirrored)". */
function mirroredName(name) {
  if (!name) return '';
  const words = { left: 'right', right: 'left', Left: 'Right', Right: 'Left', LEFT: 'RIGHT', RIGHT: 'LEFT' };
  const swapped = name
    .replace(/left|right|Left|Right|LEFT|RIGHT/g, (w) => words[w])
    .replace(/([._-])([LR])$/, (_, sep, side) => sep + (side === 'L' ? 'R' : 'L'));
  return swapped === name ? `${name} (mirrored)` : swapped;
}

async function save() {
  const pairs = completePairs();
  const waiting = state.pairs.length - pairs.length;
  try {
    const answer = await request('api/save', { pairs });
    status(`saved ${answer.pairs} ${guide.list.length ? 'landmarks' : 'pairs'} to ${answer.saved}${waiting ? ` (${waiting} half-made left out)` : ''}`);
    document.body.dataset.saved = String(answer.pairs);
  } catch (e) {
    status(`save failed: ${e.message}`, true);
  }
}

async function done() {
  try {
    await request('api/done', {});
  } catch { /* the server may already be gone */ }
  state.closed = true;
  status('closed: the server has stopped; this page can be closed');
  for (const b of document.querySelectorAll('button')) b.disabled = true;
}

function keys(event) {
  if (state.closed) return;
  if (event.target instanceof HTMLInputElement && event.target.type === 'text') return;
  const mod = event.ctrlKey || event.metaKey;
  const plain = !mod && !event.altKey;
  if (mod && event.key.toLowerCase() === 'z') { event.preventDefault(); if (event.shiftKey) redo(); else undo(); }
  else if (mod && event.key.toLowerCase() === 'y') { event.preventDefault(); redo(); }
  else if (mod && event.key.toLowerCase() === 's') { event.preventDefault(); save(); }
  else if (event.key === 'Delete' || event.key === 'Backspace') deleteSelected();
  else if (event.key === 'Escape') cancelPending();
  else if (plain && event.key === 'f') fit();
  else if (plain && event.key === 'm' && !guide.list.length) mirror();
  else if (plain && event.key === 's' && guide.list.length) skip();
}

function overlay() {
  const on = $('overlay').checked;
  document.body.classList.toggle('overlay', on);
  state.ghost.root.visible = on;
  state.views[TARGET].resize();
  render();
}

// ---------------------------------------------------------------- start

async function start() {
  const [session, source, target] = await Promise.all([
    request('api/session'),
    request('api/mesh/source', undefined, 'binary').then(parseMesh),
    request('api/mesh/target', undefined, 'binary').then(parseMesh),
  ]);
  state.session = session;
  state.meshes = [prepare(source), prepare(target)];
  const base = (path) => path.split(/[\\/]/).pop();
  $('files').textContent = `${base(session.source)} → ${base(session.target)}, saving to ${base(session.output)}`;
  $('files').title = `${session.source} → ${session.target}, saving to ${session.output}`;
  state.views = [new View($('source'), source, 0x8fb3d9), new View($('target'), target, 0xd9b38f)];
  // The source drawn over the target when overlaid.
  const ghostRoot = normalised(source);
  // Drawn after the target, seen through it (an x-ray): where the two
  // surfaces coincide, the source tints the target instead of fighting it.
  const ghost = { root: ghostRoot, object: new THREE.Mesh(source.geometry, new THREE.MeshStandardMaterial({ color: 0x8fb3d9, transparent: true, opacity: 0.35, depthWrite: false, depthTest: false, side: THREE.DoubleSide })), markers: new THREE.Group() };
  ghost.object.renderOrder = 1;
  ghostRoot.add(ghost.object, ghost.markers);
  ghostRoot.visible = false;
  state.views[TARGET].scene.add(ghostRoot);
  state.ghost = ghost;
  link(state.views[SOURCE], state.views[TARGET]);
  link(state.views[TARGET], state.views[SOURCE]);
  state.views.forEach(attachPointer);
  state.pairs = session.pairs.map((p) => ({ name: p.name ?? '', source: p.source, target: p.target }));
  if (session.guide) startGuide(session);
  $('undo').addEventListener('click', undo);
  $('redo').addEventListener('click', redo);
  $('delete').addEventListener('click', deleteSelected);
  $('mirror').addEventListener('click', mirror);
  $('fit').addEventListener('click', fit);
  $('save').addEventListener('click', save);
  $('done').addEventListener('click', done);
  $('overlay').addEventListener('change', overlay);
  $('show-pose').addEventListener('change', showPose);
  $('autofit').addEventListener('change', () => { if ($('autofit').checked) scheduleFit(); });
  window.addEventListener('keydown', keys);
  drawMarkers();
  listPairs();
  showGuide();
  status(`source ${source.positions.length / 3} vertices, target ${target.positions.length / 3} vertices`);
  await new Promise((ok) => requestAnimationFrame(() => requestAnimationFrame(ok)));
  timings.ready = performance.now();
  document.body.dataset.ready = 'yes';
}

// What a test (or a curious user's console) can see.
window.pick = {
  ready: start().catch((e) => { status(`cannot start: ${e.message}`, true); throw e; }),
  pairs: () => JSON.parse(JSON.stringify(state.pairs)),
  fit: () => state.fit,
  timings,
  /** With --template: the landmark to place next, or null. */
  next: () => guide.list[guide.current] ?? null,
  /** Where a surface point (as the pairs hold them) lies on its mesh. */
  position(side, point) {
    return pointPosition(state.meshes[side === 'source' ? SOURCE : TARGET], point).toArray();
  },
  /** Where a point of a mesh (file coordinates) is on the screen. */
  project(side, [x, y, z]) {
    const view = state.views[side === 'source' ? SOURCE : TARGET];
    view.root.updateMatrixWorld();
    const p = new THREE.Vector3(x, y, z).applyMatrix4(view.object.matrixWorld).project(view.camera);
    const r = view.canvas.getBoundingClientRect();
    return { x: r.left + ((p.x + 1) / 2) * r.width, y: r.top + ((1 - p.y) / 2) * r.height };
  },
};
