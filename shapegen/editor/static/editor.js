// shapegen edit: the page. Plain ES module, no build step; three.js is served by the package.
// It talks to the server only through the JSON API of docs/editor.md.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';

const $ = (id) => document.getElementById(id);
const POLL_MS = 400;

// What the tests (and a curious designer, in the console) can read.
const app = {
  state: null,
  scene: null,
  renderedModelVersion: -1,
  modelsRendered: 0,
  colourMode: 'labels',
  inflight: false,
  pending: null,
  pendingGesture: null,
  dragging: null,
  gesture: null,
  lastLatencyMs: null,
  errors: [],
  framesDrawn: 0,
  selected: null,
  blockDetails: null,
  noteAfterChange: '',
  hiddenLabels: new Set(),
  section: null,
};
window.shapegenEditor = app;

// ------------------------------------------------------------------ the 3D view
const canvas = $('canvas');
const renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio || 1);
const view = new THREE.Scene();
view.background = new THREE.Color(0xeef1f5);
const perspective = new THREE.PerspectiveCamera(40, 1, 0.05, 5000);
const orthographic = new THREE.OrthographicCamera(-1, 1, 1, -1, 0.05, 5000);
let camera = perspective;
const controls = new OrbitControls(camera, canvas);
controls.enableDamping = true;
view.add(new THREE.HemisphereLight(0xffffff, 0x8a8470, 1.3));
const sun = new THREE.DirectionalLight(0xffffff, 2.0);
view.add(sun);
const groundPlane = new THREE.Mesh(
  new THREE.PlaneGeometry(1, 1),
  new THREE.MeshStandardMaterial({ color: 0xd9d5cb, roughness: 1, metalness: 0 }),
);
groundPlane.rotation.x = -Math.PI / 2;
view.add(groundPlane);
let grid = null;
let modelGroup = null;
let sectionPlane = null; // the section plane, when one cuts the model (a THREE.Plane)
const forceGroups = { joints: new THREE.Group(), ground: new THREE.Group() };
view.add(forceGroups.joints, forceGroups.ground);
const FORCE_COLOURS = { joints: 0x202020, ground: 0x1b7f3b };
const EDGE_MATERIAL = new THREE.LineBasicMaterial({ color: 0x000000, transparent: true, opacity: 0.25 });

function resize() {
  const box = canvas.parentElement.getBoundingClientRect();
  renderer.setSize(box.width, box.height, false);
  aspect = box.width / Math.max(box.height, 1);
  perspective.aspect = aspect;
  perspective.updateProjectionMatrix();
  setOrthographicHeight(orthographicHalfHeight);
  if (cameraAuto && app.scene) fit(currentDirection()); // the framed model stays framed
  requestRender();
}

// The view is drawn only when something changed (a new model, colours, forces, the camera):
// an idle page draws nothing, which with software WebGL saves a whole processor. The controls
// ask for a frame on every move; with damping the view glides on for a few frames after a drag,
// while update() says the camera still moves.
let frameQueued = false;
function requestRender() {
  if (frameQueued) return;
  frameQueued = true;
  requestAnimationFrame(drawFrame);
}

function drawFrame() {
  frameQueued = false;
  const moving = controls.update();
  renderer.render(view, camera);
  app.framesDrawn += 1;
  if (moving) requestRender();
}
controls.addEventListener('change', requestRender);

// ------------------------------------------------------------------ the camera
// Framing fits the model's box to the view from a direction (each corner inside, whatever the
// window's shape), for the perspective or the orthographic camera. The first view looks from
// the side across the model's longer horizontal extent, so a long bridge fills the width and a
// tall tower the height. While the designer has not moved the camera since the last framing,
// the view is framed again when the window changes size or a new model would not fit (or
// would fill less than a third of it).
let aspect = 1;
let orthographicHalfHeight = 1;
let cameraAuto = true;
const FIT_MARGIN = 1.08;
const UP = new THREE.Vector3(0, 1, 0);
const VIEW_DIRECTIONS = {
  top: new THREE.Vector3(0, 1, 1e-3),
  front: new THREE.Vector3(0, 0, 1),
  side: new THREE.Vector3(1, 0, 0),
};

function setOrthographicHeight(half) {
  orthographicHalfHeight = half;
  Object.assign(orthographic, { left: -half * aspect, right: half * aspect, top: half, bottom: -half });
  orthographic.updateProjectionMatrix();
}

function modelBox() {
  const [lo, hi] = app.scene.bounds;
  return new THREE.Box3(new THREE.Vector3(...lo), new THREE.Vector3(...hi));
}

// The first view's direction: from the front and a little above, turned so that the model's
// longer horizontal extent runs across the screen.
function homeDirection() {
  const size = modelBox().getSize(new THREE.Vector3());
  const across = size.x >= size.z ? new THREE.Vector3(0.55, 0.45, 1) : new THREE.Vector3(1, 0.45, 0.55);
  return across.normalize();
}

function currentDirection() {
  return camera.position.clone().sub(controls.target).normalize();
}

// Stop the glide an orbit leaves (damping), so that it does not carry the view off a framing.
function stopGlide() {
  controls.enableDamping = false;
  controls.update();
  controls.enableDamping = true;
}

function fit(direction) {
  if (!app.scene) return;
  stopGlide();
  const box = modelBox();
  const size = Math.max(...box.getSize(new THREE.Vector3()).toArray(), 1e-3);
  const back = direction.clone().normalize();
  const right = new THREE.Vector3().crossVectors(UP, back);
  if (right.lengthSq() < 1e-12) right.set(1, 0, 0);
  right.normalize();
  const up = new THREE.Vector3().crossVectors(back, right).normalize();
  const corners = boxCorners(box);
  // centre the view on the middle of the box's extent across the screen
  const across = corners.map((c) => [c.dot(right), c.dot(up), c.dot(back)]);
  const mid = (k) => (Math.min(...across.map((a) => a[k])) + Math.max(...across.map((a) => a[k]))) / 2;
  const target = right.clone().multiplyScalar(mid(0)).addScaledVector(up, mid(1)).addScaledVector(back, mid(2));
  const local = corners.map((c) => { const v = c.clone().sub(target); return [v.dot(right), v.dot(up), v.dot(back)]; });
  const tanV = Math.tan(THREE.MathUtils.degToRad(perspective.fov / 2));
  const tanH = tanV * aspect;
  let distance = 0;
  for (const [x, y, z] of local) distance = Math.max(distance, z + (FIT_MARGIN * Math.abs(x)) / tanH, z + (FIT_MARGIN * Math.abs(y)) / tanV);
  const halfHeight = FIT_MARGIN * Math.max(...local.map(([x, y]) => Math.max(Math.abs(y), Math.abs(x) / aspect)));
  const depth = Math.max(...local.map(([, , z]) => Math.abs(z)));
  if (camera === orthographic) {
    setOrthographicHeight(halfHeight);
    orthographic.zoom = 1;
    distance = 2 * depth + size;
  }
  const place = () => {
    camera.position.copy(target).addScaledVector(back, distance);
    camera.near = Math.max(size / 1000, (distance - depth) / 100);
    camera.far = distance + size * 20;
    camera.lookAt(target);
    camera.updateProjectionMatrix();
    camera.updateMatrixWorld();
  };
  place();
  // Centre and scale the projected box in the part of the view the panel leaves free, a few
  // times: in perspective, near corners spread more than far ones.
  const region = freeRegion();
  const [centreX, halfWidth] = [(region[0] + region[1]) / 2, (region[1] - region[0]) / 2];
  for (let k = 0; k < 4; k += 1) {
    const [x0, x1, y0, y1] = projectedExtent(corners);
    const seen = camera === perspective ? distance * tanV : orthographicHalfHeight;
    target.addScaledVector(right, ((x0 + x1) / 2 - centreX) * seen * aspect).addScaledVector(up, ((y0 + y1) / 2) * seen);
    const scale = Math.max((x1 - x0) / 2 / halfWidth, (y1 - y0) / 2) * FIT_MARGIN;
    if (camera === perspective) distance *= scale;
    else setOrthographicHeight(orthographicHalfHeight * scale);
    place();
  }
  for (let k = 0; k < 20 && !inside(projectedExtent(corners), region); k += 1) {
    if (camera === perspective) distance *= 1.05;
    else setOrthographicHeight(orthographicHalfHeight * 1.05);
    place();
  }
  controls.target.copy(target);
  controls.update();
  cameraAuto = true;
  requestRender();
}

function projectedExtent(points) {
  const xs = [];
  const ys = [];
  for (const point of points) {
    const p = point.clone().project(camera);
    xs.push(p.x);
    ys.push(p.y);
  }
  return [Math.min(...xs), Math.max(...xs), Math.min(...ys), Math.max(...ys)];
}

function inside([x0, x1, y0, y1], [left, right, bottom, top] = [-1, 1, -1, 1]) {
  return x0 >= left && x1 <= right && y0 >= bottom && y1 <= top;
}

// The part of the view the panel at its top left leaves free, in normalized device
// coordinates [left, right, bottom, top]: the model is framed beside the panel (when the
// panel takes less than 40 % of the view's width).
function freeRegion() {
  const view = canvas.getBoundingClientRect();
  const panel = $('view-controls').getBoundingClientRect();
  const covered = (panel.right - view.left) / Math.max(view.width, 1);
  return [covered > 0 && covered < 0.4 ? 2 * covered - 1 : -1, 1, -1, 1];
}

function boxCorners(box) {
  const corners = [];
  for (const x of [box.min.x, box.max.x]) for (const y of [box.min.y, box.max.y]) for (const z of [box.min.z, box.max.z]) corners.push(new THREE.Vector3(x, y, z));
  return corners;
}

// The share of the view the model's box spans, and whether all of it is inside: the NDC
// extent of its corners, [xmin, xmax, ymin, ymax]. For the tests and the auto framing.
app.modelExtent = () => (app.scene ? projectedExtent(boxCorners(modelBox())) : null);
app.freeRegion = () => freeRegion();

app.cameraView = () => ({
  kind: camera.isOrthographicCamera ? 'orthographic' : 'perspective',
  direction: currentDirection().toArray(),
  auto: cameraAuto,
});

function modelFits() {
  const extent = app.modelExtent();
  const [x0, x1, y0, y1] = extent;
  return inside(extent, freeRegion()) && Math.max(x1 - x0, y1 - y0) >= 2 / 3;
}

function useCamera(wanted) {
  if (wanted === camera) return;
  stopGlide();
  // the same view: the orthographic height is what the perspective sees at the target
  const distance = camera.position.distanceTo(controls.target);
  const tanV = Math.tan(THREE.MathUtils.degToRad(perspective.fov / 2));
  if (wanted === orthographic) {
    setOrthographicHeight(distance * tanV);
    orthographic.zoom = 1;
    orthographic.position.copy(camera.position);
    orthographic.near = camera.near;
    orthographic.far = camera.far;
  } else {
    const seen = orthographicHalfHeight / orthographic.zoom;
    const direction = currentDirection();
    perspective.position.copy(controls.target).addScaledVector(direction, seen / tanV);
    perspective.near = camera.near;
    perspective.far = Math.max(camera.far, seen / tanV * 2);
  }
  wanted.updateProjectionMatrix();
  camera = wanted;
  controls.object = camera;
  controls.update();
  // a framed view stays framed: the perspective's near corners spread past the orthographic's box
  if (cameraAuto) fit(currentDirection());
  requestRender();
}

controls.addEventListener('start', () => { cameraAuto = false; });
$('frame-all').addEventListener('click', () => fit(currentDirection()));
$('view-reset').addEventListener('click', () => fit(homeDirection()));
for (const [id, direction] of Object.entries(VIEW_DIRECTIONS)) $(`view-${id}`).addEventListener('click', () => fit(direction));
$('orthographic').addEventListener('change', () => { useCamera($('orthographic').checked ? orthographic : perspective); });
document.addEventListener('keydown', (event) => {
  const target = event.target;
  if (event.ctrlKey || event.metaKey || event.altKey || ['INPUT', 'SELECT', 'TEXTAREA'].includes(target.tagName)) return;
  if (event.key === 'f') fit(currentDirection());
});
window.addEventListener('resize', resize);
resize();

// The fraction of the canvas's pixels the model changes (drawn with and without it): the
// browser tests' check that the view shows the model, not a blank or ground-only canvas.
app.modelCoverage = () => {
  if (!modelGroup) return 0;
  const gl = renderer.getContext();
  const [w, h] = [gl.drawingBufferWidth, gl.drawingBufferHeight];
  const read = () => {
    renderer.render(view, camera);
    const pixels = new Uint8Array(w * h * 4);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, pixels);
    return pixels;
  };
  const shown = read();
  modelGroup.visible = false;
  const hidden = read();
  modelGroup.visible = true;
  renderer.render(view, camera);
  let changed = 0;
  for (let i = 0; i < shown.length; i += 4) {
    const d = Math.abs(shown[i] - hidden[i]) + Math.abs(shown[i + 1] - hidden[i + 1]) + Math.abs(shown[i + 2] - hidden[i + 2]);
    if (d > 24) changed += 1;
  }
  return changed / (w * h);
};

// The colour the view shows at a point of the screen (client pixels), drawn afresh.
app.pixelAt = (clientX, clientY) => {
  const gl = renderer.getContext();
  const box = canvas.getBoundingClientRect();
  const x = Math.round(((clientX - box.left) / box.width) * gl.drawingBufferWidth);
  const y = Math.round((1 - (clientY - box.top) / box.height) * gl.drawingBufferHeight);
  renderer.render(view, camera);
  const pixel = new Uint8Array(4);
  gl.readPixels(x, y, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel);
  return Array.from(pixel.slice(0, 3));
};

function rgb(c) {
  return new THREE.Color().setRGB(c[0] / 255, c[1] / 255, c[2] / 255, THREE.SRGBColorSpace);
}

let framed = false;
let loading = false;
let loadAgain = false;

async function loadModel() {
  if (loading) { loadAgain = true; return; }
  loading = true;
  try {
    do {
      loadAgain = false;
      const version = app.state.model_version;
      const [sceneData, gltf] = await Promise.all([
        getJSON('/api/scene'),
        new GLTFLoader().loadAsync(`/api/model.glb?v=${version}`),
      ]);
      showModel(sceneData, gltf);
      app.renderedModelVersion = sceneData.model_version;
      app.modelsRendered += 1;
      if (app.selected) select(app.selected); // the same id in the new model, if it has one
      showExports();
    } while (loadAgain);
  } catch (err) {
    note(`the model could not be loaded: ${err.message || err}`);
  } finally {
    loading = false;
  }
}

function showModel(sceneData, gltf) {
  app.scene = sceneData;
  if (modelGroup) {
    view.remove(modelGroup);
    modelGroup.traverse((o) => { if (o.geometry) o.geometry.dispose(); if (o.material) o.material.dispose?.(); });
  }
  modelGroup = gltf.scene;
  const byId = new Map(sceneData.blocks.map((b) => [b.id, b]));
  const meshes = [];
  modelGroup.traverse((o) => {
    if (!o.isMesh) return;
    if (o.userData.role === 'resultants') { o.visible = false; return; }
    const block = byId.get(o.name);
    if (!block) return;
    o.userData.block = block;
    o.material = new THREE.MeshStandardMaterial({ roughness: 0.85, metalness: 0, flatShading: true });
    meshes.push(o);
  });
  for (const o of meshes) {
    o.add(new THREE.LineSegments(new THREE.EdgesGeometry(o.geometry, 25), EDGE_MATERIAL));
  }
  view.add(modelGroup);
  showLabels();
  updateSection();
  applyColours();
  drawForces();
  frame(sceneData);
  legend();
  requestRender();
}

function frame(sceneData) {
  const [lo, hi] = sceneData.bounds;
  const centre = new THREE.Vector3((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2);
  const size = Math.max(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-3);
  const groundY = sceneData.ground ?? lo[1];
  groundPlane.scale.set(size * 6, size * 6, 1);
  groundPlane.position.set(centre.x, groundY - size * 1e-4, centre.z);
  groundPlane.visible = sceneData.ground !== null;
  if (grid) view.remove(grid);
  grid = new THREE.GridHelper(size * 4, 20, 0x999999, 0xbbbbbb);
  grid.position.set(centre.x, groundY + size * 1e-4, centre.z);
  grid.visible = sceneData.ground !== null;
  view.add(grid);
  sun.position.set(centre.x + size, centre.y + 2 * size, centre.z + 1.5 * size);
  sun.target.position.copy(centre);
  view.add(sun.target);
  if (!framed) {
    framed = true;
    fit(homeDirection());
  } else if (cameraAuto && !modelFits()) {
    fit(currentDirection()); // a change of size: the model is framed again
  }
}

function applyColours() {
  if (!modelGroup) return;
  const tension = app.colourMode === 'tension' && app.scene?.legend.max_tension !== null;
  // with forces shown the blocks turn translucent, so the arrows inside them can be seen
  const seeThrough = Boolean(app.scene?.forces) && ($('show-joints').checked || $('show-ground').checked);
  modelGroup.traverse((o) => {
    const block = o.userData.block;
    if (!o.isMesh || !block) return;
    const c = tension && block.tension_color ? block.tension_color : block.color;
    const opacity = Math.min(c[3] / 255, seeThrough ? 0.35 : 1);
    o.material.color = rgb(c);
    o.material.transparent = opacity < 1;
    o.material.opacity = opacity;
    o.material.depthWrite = opacity >= 1;
    // the block clicked: lit from within, so it shows in any colour mode
    o.material.emissive = new THREE.Color(block.id === app.selected ? 0x8a6d00 : 0x000000);
    o.material.needsUpdate = true;
  });
  requestRender();
}

// ------------------------------------------------------------------ search and derivation
// The margin of the search, the seed, the lot; which attrs are free (the marks on the rows).
async function setSettings(body) {
  try {
    applyState(await post('/api/settings', body));
    note('');
  } catch (err) {
    note(err.message);
    refresh();
  }
}

function showSettings(settings) {
  const idle = (id) => document.activeElement !== $(id);
  if (idle('margin')) $('margin').value = settings.margin;
  if (idle('seed')) $('seed').value = settings.seed;
  // a lot with holes (a courtyard) is {polygon, holes}: its outline is shown, and it is changed
  // in its file only, as the polygon field has no way to write holes
  const holed = settings.lot !== null && !Array.isArray(settings.lot);
  const lot = holed ? settings.lot.polygon : settings.lot;
  const rectangle = lot === null ? settings.file_lot : (lot.length === 2 && !Array.isArray(lot[0]) ? lot : null);
  if (idle('lot-width')) $('lot-width').value = rectangle ? rectangle[0] : '';
  if (idle('lot-depth')) $('lot-depth').value = rectangle ? rectangle[1] : '';
  if (idle('lot-polygon')) $('lot-polygon').value = rectangle ? '' : lot.map(([x, z]) => `${x},${z}`).join(' ');
  $('lot-polygon').disabled = holed;
  $('lot-polygon').title = holed ? `the lot has ${settings.lot.holes.length} hole(s): change it in its file` : '';
  $('lot-file').disabled = lot === null;
}

$('margin').addEventListener('change', () => setSettings({ margin: Number($('margin').value) }));
$('seed').addEventListener('change', () => setSettings({ seed: Number($('seed').value) }));
for (const id of ['lot-width', 'lot-depth']) {
  $(id).addEventListener('change', () => setSettings({ lot: [Number($('lot-width').value), Number($('lot-depth').value)] }));
}
$('lot-file').addEventListener('click', () => setSettings({ lot: null }));
$('lot-polygon').addEventListener('change', () => {
  const text = $('lot-polygon').value.trim();
  if (!text) return;
  const points = text.split(/\s+/).map((pair) => pair.split(',').map(Number));
  if (points.some((p) => p.length !== 2 || p.some((v) => !Number.isFinite(v)))) {
    note('a polygon lot is x,z pairs separated by spaces: 0,0 0,8 10,8 10,0');
    return;
  }
  setSettings({ lot: points });
});

// ------------------------------------------------------------------ export
// Downloads named after the rule file, and the shapegen build line of the current design.
async function showExports() {
  const stem = (app.state?.grammar.name || 'design').replace(/\.[^.]*$/, '');
  const v = app.state?.model_version ?? 0;
  for (const [id, path, suffix] of [['download-model', '/api/model.glb', '.glb'], ['download-report', '/api/report.json', '.report.json'], ['download-attrs', '/api/attrs.json', '.attrs.json']]) {
    $(id).href = `${path}?v=${v}`;
    $(id).download = stem + suffix;
  }
  try {
    const exported = await getJSON('/api/attrs.json');
    app.exported = exported;
    $('command').textContent = exported.command;
  } catch (err) {
    note(err.message);
  }
}

$('copy-command').addEventListener('click', async () => {
  const text = $('command').textContent;
  try {
    await navigator.clipboard.writeText(text);
    note('the command line is copied');
  } catch (err) { // no clipboard for this page: the text is selected, for Ctrl+C
    const range = document.createRange();
    range.selectNodeContents($('command'));
    window.getSelection().removeAllRanges();
    window.getSelection().addRange(range);
    note('the command line is selected: Ctrl+C copies it');
  }
});

// ------------------------------------------------------------------ a block clicked
// A click (not a drag: the orbit) on a block selects it: highlighted, and its account shown
// (GET /api/blocks/ID): labels, rule path, the attrs its rules read, its joints' forces.
const raycaster = new THREE.Raycaster();
let pressed = null;
canvas.addEventListener('pointerdown', (event) => { pressed = { x: event.clientX, y: event.clientY }; });
canvas.addEventListener('pointerup', (event) => {
  if (!pressed || Math.hypot(event.clientX - pressed.x, event.clientY - pressed.y) > 4) return;
  pressed = null;
  select(blockAt(event.clientX, event.clientY));
});

function blockAt(clientX, clientY) {
  if (!modelGroup) return null;
  const box = canvas.getBoundingClientRect();
  const pointer = new THREE.Vector2(((clientX - box.left) / box.width) * 2 - 1, -((clientY - box.top) / box.height) * 2 + 1);
  raycaster.setFromCamera(pointer, camera);
  const meshes = [];
  modelGroup.traverse((o) => { if (o.isMesh && o.userData.block && o.visible && o.parent.visible) meshes.push(o); });
  for (const hit of raycaster.intersectObjects(meshes, false)) {
    if (visibleHit(hit.point)) return hit.object.userData.block.id;
  }
  return null;
}

// A hit the view shows (not cut away by the section plane).
function visibleHit(point) {
  return !sectionPlane || sectionPlane.distanceToPoint(point) >= 0;
}

// Where a block's centre shows on the screen (client pixels): for the tests and the console.
app.blockScreenPoint = (id) => {
  let mesh = null;
  modelGroup?.traverse((o) => { if (o.isMesh && o.userData.block?.id === id) mesh = o; });
  if (!mesh) return null;
  const centre = new THREE.Box3().setFromObject(mesh).getCenter(new THREE.Vector3()).project(camera);
  const box = canvas.getBoundingClientRect();
  return [box.left + ((centre.x + 1) / 2) * box.width, box.top + ((1 - centre.y) / 2) * box.height];
};

async function select(id) {
  app.selected = id;
  applyColours();
  if (!id) { app.blockDetails = null; showBlock(null); return; }
  try {
    const details = await getJSON(`/api/blocks/${encodeURIComponent(id)}`);
    if (app.selected === id) { app.blockDetails = details; showBlock(details); }
  } catch (err) {
    if (app.selected === id) { app.selected = null; app.blockDetails = null; showBlock(null); applyColours(); }
  }
}

function showBlock(b) {
  const panel = $('block');
  panel.hidden = !b;
  if (!b) return;
  const rows = (b.joints || []).map((j) => `<tr><td>${escape(j.other)}${j.support ? ' (support)' : ''}</td><td>${newtons(j.compression)}</td><td>${newtons(j.shear)}</td><td class="${j.tension > 0 ? 'needs' : ''}">${newtons(j.tension)}</td></tr>`).join('');
  const specs = new Map((app.state?.attrs || []).map((spec) => [spec.name, spec]));
  const value = (a) => (typeof a.value === 'number' ? (specs.has(a.name) ? shown(specs.get(a.name), a.value) : number(a.value)) : JSON.stringify(a.value));
  const attrs = b.attrs.map((a) => `<a href="#" data-attr="${escape(a.name)}" title="show it in the Inspector">${escape(a.name)}</a> = ${escape(value(a))}`).join(', ');
  const tension = b.tension === null ? '' : (b.tension > 0 ? `its worst joint needs <strong>${newtons(b.tension)}</strong> of tension` : 'needs no tension');
  panel.innerHTML = `<div class="title"><strong>Block ${escape(b.id)}</strong><button class="close" title="deselect (Esc)">×</button></div>
    <div>labels: ${b.labels.length ? b.labels.map(escape).join(', ') : '–'}${b.fixed ? ' · support (fixed)' : ''}${b.structural ? '' : ' · not structural'}</div>
    <div>rules: ${b.rule_path.map(escape).join(' › ') || '–'}</div>
    <div>attrs its rules read: ${attrs || '–'}</div>
    <div>weight ${newtons(b.weight)}${tension ? ` · ${tension}` : ''}</div>
    ${b.joints ? `<table class="joints"><tr><th>joint with</th><th>compression</th><th>shear</th><th title="the sum of the tensions at the joint's corners">tension</th></tr>${rows}</table>` : `<div>judged by ${escape(app.state?.grammar?.judged_by || 'its structure')}, not by its joints</div>`}`;
  panel.querySelector('.close').addEventListener('click', () => select(null));
  for (const link of panel.querySelectorAll('a[data-attr]')) {
    link.addEventListener('click', (event) => {
      event.preventDefault();
      const row = attrRows.get(link.dataset.attr);
      if (!row) return;
      for (let e = row.parentElement; e; e = e.parentElement) if (e.tagName === 'DETAILS') e.open = true;
      row.scrollIntoView({ block: 'center' });
      row.classList.add('flash');
      setTimeout(() => row.classList.remove('flash'), 1200);
    });
  }
}

document.addEventListener('keydown', (event) => { if (event.key === 'Escape' && app.selected) select(null); });

// Arrows as in the seed paper's Figure 1: solid shafts and heads, drawn through translucent
// blocks. A joint's resultant is centred on its centre of pressure; a reaction starts where the
// support pushes and points into the structure.
function drawForces() {
  const unitY = new THREE.Vector3(0, 1, 0);
  for (const kind of ['joints', 'ground']) {
    const group = forceGroups[kind];
    group.children.slice().forEach((c) => { group.remove(c); c.geometry.dispose(); c.material.dispose(); });
    const forces = app.scene?.forces;
    if (!forces || !forces[kind].length) continue;
    const scale = forces.metres_per_newton;
    const longest = forces.peak * scale;
    const arrows = [];
    for (const [x, y, z, fx, fy, fz] of forces[kind]) {
      const f = new THREE.Vector3(fx, fy, fz);
      const length = f.length() * scale;
      if (!(length > 0)) continue;
      const dir = f.normalize();
      const point = new THREE.Vector3(x, y, z);
      const start = kind === 'ground' ? point : point.clone().addScaledVector(dir, -length / 2);
      arrows.push({ start, dir, length });
    }
    const colour = FORCE_COLOURS[kind];
    const material = new THREE.MeshBasicMaterial({ color: colour });
    const shaft = new THREE.CylinderGeometry(1, 1, 1, 8);
    shaft.translate(0, 0.5, 0);
    const head = new THREE.ConeGeometry(1, 1, 10);
    head.translate(0, 0.5, 0);
    const shafts = new THREE.InstancedMesh(shaft, material, arrows.length);
    const heads = new THREE.InstancedMesh(head, material, arrows.length);
    const m = new THREE.Matrix4();
    const q = new THREE.Quaternion();
    const radius = 0.025 * longest;
    arrows.forEach((a, i) => {
      const headLength = Math.min(0.2 * longest, 0.5 * a.length);
      q.setFromUnitVectors(unitY, a.dir);
      m.compose(a.start, q, new THREE.Vector3(radius, a.length - headLength, radius));
      shafts.setMatrixAt(i, m);
      const headStart = a.start.clone().addScaledVector(a.dir, a.length - headLength);
      m.compose(headStart, q, new THREE.Vector3(2.4 * radius, headLength, 2.4 * radius));
      heads.setMatrixAt(i, m);
    });
    group.add(shafts, heads);
  }
  showForces();
}

function showForces() {
  forceGroups.joints.visible = $('show-joints').checked;
  forceGroups.ground.visible = $('show-ground').checked;
  applyColours();
}

function swatch(c) {
  return `<span class="swatch" style="background: rgba(${c[0]},${c[1]},${c[2]},${c[3] / 255})"></span>`;
}

function legend() {
  const s = app.scene;
  if (!s) return;
  const parts = [];
  const tension = app.colourMode === 'tension' && s.legend.max_tension !== null;
  if (tension) {
    const [a, b] = [s.legend.tension_zero, s.legend.tension_max];
    parts.push('<div>largest joint tension of each block</div>');
    parts.push(`<div class="ramp" style="background: linear-gradient(to right, rgb(${a.slice(0, 3)}), rgb(${b.slice(0, 3)}))"></div>`);
    parts.push(`<div class="ends"><span>0</span><span>${newtons(s.legend.max_tension)}</span></div>`);
  }
  // every label of the model, with a check box that shows or hides its blocks
  const colours = new Map(s.legend.labels);
  for (const b of s.blocks) if (!colours.has(b.label)) colours.set(b.label, b.color);
  for (const label of [...colours.keys()].sort()) {
    const shown = !app.hiddenLabels.has(label);
    const name = label === '' ? '(no label)' : label;
    parts.push(`<label class="label-row" title="show or hide the blocks labelled so"><input type="checkbox" data-label="${escape(label)}"${shown ? ' checked' : ''}>${tension ? '' : swatch(colours.get(label))}${escape(name)}</label>`);
  }
  if (s.blocks.some((b) => b.color.join() === s.legend.support.join())) {
    parts.push(`<div>${swatch(s.legend.support)}support (fixed)</div>`);
  }
  const f = s.forces;
  if (f && ($('show-joints').checked || $('show-ground').checked)) {
    const c = (k) => `#${FORCE_COLOURS[k].toString(16).padStart(6, '0')}`;
    if ($('show-joints').checked) parts.push(`<div><span class="swatch" style="background:${c('joints')}"></span>joint resultant</div>`);
    if ($('show-ground').checked) parts.push(`<div><span class="swatch" style="background:${c('ground')}"></span>ground reaction</div>`);
    if (f.metres_per_newton > 0) parts.push(`<div>arrow of 1 m = ${newtons(1 / f.metres_per_newton)}</div>`);
  }
  $('legend').innerHTML = parts.join('');
  for (const box of $('legend').querySelectorAll('input[data-label]')) {
    box.addEventListener('change', () => {
      if (box.checked) app.hiddenLabels.delete(box.dataset.label);
      else app.hiddenLabels.add(box.dataset.label);
      showLabels();
    });
  }
}

// Blocks of a hidden label are not drawn (nor picked): to see inside, hide the roof.
function showLabels() {
  if (!modelGroup) return;
  modelGroup.traverse((o) => { if (o.isMesh && o.userData.block) o.visible = !app.hiddenLabels.has(o.userData.block.label); });
  if (app.selected && app.hiddenLabels.has(app.blockDetails?.labels?.[0] ?? '')) select(null);
  requestRender();
}

// ------------------------------------------------------------------ the section plane
// A plane across one axis cuts the blocks (and their edges) away on one side, so the inside of
// a vault shows; what is cut away is neither drawn nor picked.
renderer.localClippingEnabled = true;

function sectionBounds(axis) {
  const [lo, hi] = app.scene ? app.scene.bounds : [[0, 0, 0], [1, 1, 1]];
  const k = { x: 0, y: 1, z: 2 }[axis];
  return [lo[k], hi[k]];
}

function updateSection() {
  const on = $('section-on').checked;
  const axis = $('section-axis').value;
  const [lo, hi] = sectionBounds(axis);
  const at = lo + (Number($('section-at').value) / 1000) * (hi - lo);
  $('section-value').textContent = on ? `${axis} = ${number(at)} m` : '';
  const normal = new THREE.Vector3(...{ x: [-1, 0, 0], y: [0, -1, 0], z: [0, 0, -1] }[axis]);
  if ($('section-flip').checked) normal.negate();
  // the side kept: normal · p + constant >= 0
  const point = new THREE.Vector3().setComponent({ x: 0, y: 1, z: 2 }[axis], at);
  sectionPlane = on ? new THREE.Plane(normal, -normal.dot(point)) : null;
  const planes = sectionPlane ? [sectionPlane] : [];
  EDGE_MATERIAL.clippingPlanes = planes;
  modelGroup?.traverse((o) => {
    if (!o.isMesh || !o.userData.block) return;
    o.material.clippingPlanes = planes;
    o.material.side = sectionPlane ? THREE.DoubleSide : THREE.FrontSide; // the cut shows the inside
    o.material.needsUpdate = true;
  });
  EDGE_MATERIAL.needsUpdate = true;
  app.section = sectionPlane ? { axis, at, keep: $('section-flip').checked ? 'above' : 'below' } : null;
  requestRender();
}

for (const id of ['section-on', 'section-axis', 'section-flip']) $(id).addEventListener('change', updateSection);
$('section-at').addEventListener('input', updateSection);

// ------------------------------------------------------------------ talking to the server
async function getJSON(url, options) {
  const response = await fetch(url, options);
  const body = await response.json();
  if (!response.ok) {
    const error = new Error(body.error || response.statusText);
    error.status = response.status;
    throw error;
  }
  return body;
}

function post(url, value) {
  return getJSON(url, {
    method: 'POST',
    headers: { 'Content-Type': 'application/json' },
    body: value === undefined ? '' : JSON.stringify(value),
  });
}

// A change of the design; ``gesture`` names the drag it belongs to, so that the server keeps
// a whole drag as one step of the undo history.
function change(name, value, gesture = null) {
  app.pending = { ...(app.pending || {}), [name]: value };
  app.pendingGesture = gesture;
  pump();
}

// One update at a time; the values moved meanwhile go in the next one (a drag sends its
// latest position, not every pixel).
async function pump() {
  if (app.inflight || !app.pending) return;
  const body = app.pending;
  const gesture = app.pendingGesture;
  app.pending = null;
  app.inflight = true;
  const started = performance.now();
  try {
    const state = await post(gesture ? `/api/attrs?gesture=${encodeURIComponent(gesture)}` : '/api/attrs', body);
    app.lastLatencyMs = performance.now() - started;
    note(app.noteAfterChange || '');
    app.noteAfterChange = '';
    applyState(state);
  } catch (err) {
    note(err.message);
    app.errors.push(err.message);
    refresh();
  } finally {
    app.inflight = false;
    if (app.pending) pump();
  }
}

async function refresh() {
  try {
    const state = await getJSON('/api/state');
    // a poll sent before a change may be answered after it: an older state is not shown
    if (!app.state || state.version > app.state.version) applyState(state);
  } catch (err) {
    note(`the server does not answer: ${err.message}`);
  }
}

setInterval(() => { if (!app.inflight) refresh(); }, POLL_MS);

async function search(objective) {
  setBusy(true);
  try {
    applyState(await post('/api/optimize', { objective }));
  } catch (err) {
    note(err.message);
  } finally {
    setBusy(false);
  }
}

function setBusy(busy) {
  $('optimize').disabled = busy;
  $('closest').disabled = busy;
  for (const id of ['undo', 'redo', 'reset-all']) if (busy) $(id).disabled = true;
  $('stop').disabled = !busy;
  for (const input of document.querySelectorAll('#attrs input, #attrs select, #attrs button, #settings input, #settings button')) input.disabled = busy;
}

// Undo, redo and reset: the server keeps the history (every change, a drag as one step).
async function historyStep(path, body = {}) {
  try {
    applyState(await post(path, body));
    note('');
  } catch (err) {
    note(err.message);
  }
}

$('undo').addEventListener('click', () => historyStep('/api/undo'));
$('redo').addEventListener('click', () => historyStep('/api/redo'));
$('reset-all').addEventListener('click', () => historyStep('/api/reset', {}));
document.addEventListener('keydown', (event) => {
  if (!(event.ctrlKey || event.metaKey) || event.altKey) return;
  const target = event.target;
  // a text field keeps its own undo of what is being typed
  const typing = target.tagName === 'TEXTAREA' || (target.tagName === 'INPUT' && ['text', 'number', 'search'].includes(target.type));
  if (typing) return;
  const key = event.key.toLowerCase();
  if (key === 'z' && !event.shiftKey) { event.preventDefault(); historyStep('/api/undo'); }
  else if ((key === 'z' && event.shiftKey) || key === 'y') { event.preventDefault(); historyStep('/api/redo'); }
});

$('optimize').addEventListener('click', () => search('energy'));
$('closest').addEventListener('click', () => search('closest'));
$('stop').addEventListener('click', () => post('/api/cancel', {}).catch((e) => note(e.message)));
for (const radio of document.querySelectorAll('input[name=colour]')) {
  radio.addEventListener('change', () => { app.colourMode = radio.value; applyColours(); legend(); });
}
for (const id of ['show-joints', 'show-ground']) {
  $(id).addEventListener('change', () => { showForces(); legend(); });
}

// ------------------------------------------------------------------ the state on the page
function applyState(state) {
  if (app.state && state.version < app.state.version) return; // answered late: already newer
  app.state = state;
  const opened = state.grammar.package ? `${state.grammar.package.split(/[\\/]/).pop()} › ` : '';
  $('file').textContent = `${opened}${state.grammar.name} · ${state.grammar.blocks} blocks`;
  const v = state.verdict;
  const verdict = $('verdict');
  if (v) {
    verdict.textContent = !v.judged ? `unknown: the solver ended with ${v.status}` : (v.stands ? 'stands' : v.fails_as);
    verdict.className = `verdict ${v.stands ? 'stands' : 'fails'}`;
    // a proven verdict whose measure follows (the next poll brings it)
    $('measure').textContent = v.pending ? `${v.measure_name} follows…` : `${v.measure_name} = ${number(v.measure)}`;
    $('tension').textContent = v.max_tension === null || v.max_tension === undefined ? '' : `largest tension ${newtons(v.max_tension)}`;
  }
  const t = state.timings;
  const page = app.lastLatencyMs === null ? '' : ` · on screen after ${(app.lastLatencyMs / 1000).toFixed(2)} s`;
  $('timing').textContent = `update ${t.update_s.toFixed(2)} s${page}`;
  const tensionRadio = $('colour-tension');
  tensionRadio.disabled = !state.grammar.judges_blocks;
  const why = `this design is judged by ${state.grammar.judged_by}, not by block statics`;
  tensionRadio.parentElement.title = tensionRadio.disabled ? why : '';
  for (const id of ['show-joints', 'show-ground']) {
    $(id).disabled = tensionRadio.disabled;
    $(id).parentElement.title = tensionRadio.disabled ? why : '';
  }
  showError(state.error);
  showWarnings(state.warnings);
  showPanel(state.panel);
  showProgress(state.optimization);
  if (state.reload_pending) $('progress').textContent += ' · the file changed: it is re-read when the search ends';
  inspector(state);
  showSettings(state.settings);
  const searching = Boolean(state.optimization && state.optimization.running);
  $('undo').disabled = searching || !state.history.undo;
  $('redo').disabled = searching || !state.history.redo;
  $('reset-all').disabled = searching || !state.attrs.some((a) => a.user);
  if (state.model_version !== app.renderedModelVersion) loadModel();
}

// The designer's values outside their @Range (built as given), then what the rule file's load
// and derivation warned about (a .cga file's: an asset not found, an operation shapegen does
// not carry out), one line each.
function showWarnings(warnings) {
  const box = $('warnings');
  box.hidden = !warnings.length;
  const key = JSON.stringify(warnings);
  if (box.dataset.key === key) return;
  box.dataset.key = key;
  $('warnings-count').textContent = `⚠ ${warnings.length} warning${warnings.length === 1 ? '' : 's'}`;
  $('warnings-list').innerHTML = warnings.map((w) => `<li>${escape(w)}</li>`).join('');
}

function showError(error) {
  $('grammar-error').hidden = !error;
  if (error) $('grammar-error-text').textContent = error.text;
}

// The structure's own figures (a bridge's cable sizing), titled and worded by the structure.
function showPanel(p) {
  $('structure-panel').hidden = !p;
  if (!p) return;
  $('structure-panel').innerHTML = `<strong>${escape(p.title)}</strong><table>${p.rows.map(([a, b]) => `<tr><td>${escape(a)}</td><td>${escape(b)}</td></tr>`).join('')}</table>`;
}

function showProgress(o) {
  const running = Boolean(o && o.running);
  setBusy(running);
  if (!o) { $('progress').textContent = ''; return; }
  const what = o.objective === 'closest' ? 'closest' : 'optimize';
  const figures = `iteration ${o.iteration ?? 0}${o.measure !== undefined && o.measure !== null ? ` · ${number(o.measure)}` : ''}${o.seconds ? ` · ${o.seconds.toFixed(1)} s` : ''}`;
  $('progress').textContent = running ? `${what}: ${figures}…` : `${what}: ${o.message || ''} (${figures})`;
}

// The Inspector: one row per attr, in the sections of its @Group and @Order annotations
// (state.sections); hidden attrs are not shown. A row's control follows the attr's kind:
// a slider for a number with a @Range, a drop-down for an @Enum (or a @Range of strings, or the
// asset files of a @File), a colour picker for a @Color, a check box for a boolean.
const attrRows = new Map();
let gestures = 0;

function inspector(state) {
  const layout = JSON.stringify([
    state.sections,
    state.attrs.map((a) => [a.name, a.kind, a.minimum, a.maximum, a.step, a.choices, a.restricted, a.free, a.description, a.display_name, a.unit, a.ranged]),
  ]);
  if ($('attrs').dataset.layout !== layout) {
    $('attrs').dataset.layout = layout;
    $('attrs').innerHTML = '';
    attrRows.clear();
    const byName = new Map(state.attrs.map((a) => [a.name, a]));
    const sections = new Map([['', $('attrs')]]);
    for (const section of state.sections) {
      const parent = sectionFor(sections, section.group);
      for (const name of section.attrs) attrRows.set(name, makeRow(byName.get(name), parent));
    }
  }
  for (const attr of state.attrs) {
    const row = attrRows.get(attr.name);
    if (row) updateRow(row, attr, state.stability[attr.name]);
  }
}

// The element that holds a group's rows: a collapsible section in its parent group's.
function sectionFor(sections, group) {
  const key = group.join('\u0000');
  if (sections.has(key)) return sections.get(key);
  const parent = sectionFor(sections, group.slice(0, -1));
  const details = document.createElement('details');
  details.className = 'group';
  details.open = true;
  details.dataset.group = group.join(' / ');
  const summary = document.createElement('summary');
  summary.textContent = group[group.length - 1];
  details.appendChild(summary);
  parent.appendChild(details);
  sections.set(key, details);
  return details;
}

function shown(attr, value) {
  return attr.kind === 'number' ? `${number(value * scaleOf(attr))}${UNITS[attr.unit] || ''}` : String(value);
}

// @Angle, @Percent and @Distance: the unit shown after a number; a percent is shown and typed
// as 10 for the value 0.1, as CityEngine's Inspector does.
const UNITS = { angle: '°', percent: '%', distance: ' m' };
function scaleOf(attr) {
  return attr.unit === 'percent' ? 100 : 1;
}

function unitMark(attr) {
  const mark = document.createElement('span');
  mark.className = 'unit';
  mark.textContent = (UNITS[attr.unit] || '').trim();
  mark.hidden = !attr.unit;
  return mark;
}

function makeRow(attr, parent) {
  const row = document.createElement('div');
  row.className = 'attr';
  row.dataset.attr = attr.name;
  row.dataset.kind = attr.kind;
  row.title = attr.description || '';
  const searchable = attr.ranged; // a @Range's bounds: the search may vary it
  const mark = attr.free
    ? '<button class="free" title="free: the search varies it; click to fix it">free</button>'
    : (searchable ? '<button class="free off" title="fixed: the search leaves it; click to free it">fixed</button>' : '');
  row.innerHTML = `<div class="head"><span class="name"></span>${mark}<span class="user" hidden>set</span><button class="reset" hidden title="back to the rule's default">↺</button><span class="value"></span></div>`;
  row.querySelector('.name').textContent = attr.display_name || attr.name;
  row.querySelector('.reset').addEventListener('click', () => historyStep('/api/reset', { attrs: [attr.name] }));
  row.querySelector('button.free')?.addEventListener('click', () => {
    const free = app.state.settings.free.filter((n) => n !== attr.name);
    if (!attr.free) free.push(attr.name);
    setSettings({ free });
  });
  if (attr.display_name) row.querySelector('.name').title = attr.name;
  let input;
  const scale = scaleOf(attr);
  if (attr.kind === 'number' && attr.minimum !== null && !attr.choices) {
    const track = document.createElement('div');
    track.className = 'track';
    track.innerHTML = '<div class="lane" style="position:absolute;left:8px;right:8px;top:0;bottom:0"><div class="band"></div></div>';
    input = document.createElement('input');
    Object.assign(input, { type: 'range', min: attr.minimum, max: attr.maximum, step: attr.step });
    input.addEventListener('pointerdown', () => { app.dragging = attr.name; app.gesture = `drag-${++gestures}`; });
    input.addEventListener('pointerup', () => { app.dragging = null; });
    input.addEventListener('input', () => {
      row.querySelector('.value').value = Number((Number(input.value) * scale).toPrecision(6));
      change(attr.name, Number(input.value), app.dragging === attr.name ? app.gesture : null);
    });
    track.appendChild(input);
    // the exact value, typed: taken as typed (outside the range with a warning), whole for a count
    const field = document.createElement('input');
    Object.assign(field, { type: 'number', className: 'value', step: attr.step * scale, name: `${attr.name}-value` });
    field.title = attr.restricted ? `the range is ${shown(attr, attr.minimum)} to ${shown(attr, attr.maximum)}: a value typed outside it is built as given, with a warning` : 'type any value (restricted=false)';
    field.addEventListener('change', () => {
      const typed = Number(field.value) / scale;
      if (field.value.trim() === '' || !Number.isFinite(typed)) {
        note(`${attr.name} takes a number`);
        field.value = Number((Number(input.value) * scale).toPrecision(6));
        return;
      }
      const value = typedValue(attr, typed);
      // said once the change is answered (an answer clears the messages)
      app.noteAfterChange = value !== typed ? `${attr.name}: ${shown(attr, typed)} is taken as ${shown(attr, value)}` : '';
      field.value = Number((value * scale).toPrecision(12));
      input.value = value;
      change(attr.name, value);
    });
    row.querySelector('.value').replaceWith(field);
    field.after(unitMark(attr));
    row.appendChild(track);
    const status = document.createElement('div');
    status.className = 'status';
    row.appendChild(status);
  } else if (attr.kind === 'bool') {
    input = document.createElement('input');
    input.type = 'checkbox';
    input.addEventListener('change', () => change(attr.name, input.checked));
    row.querySelector('.head').appendChild(input);
  } else if (attr.kind === 'color') {
    input = document.createElement('input');
    input.type = 'color';
    input.addEventListener('change', () => change(attr.name, input.value));
    row.querySelector('.head').appendChild(input);
  } else if (attr.choices && (attr.restricted || attr.kind === 'file' || attr.kind === 'directory')) {
    input = document.createElement('select');
    fillChoices(input, attr, attr.value);
    input.addEventListener('change', () => change(attr.name, attr.kind === 'number' ? Number(input.value) : input.value));
    row.appendChild(input);
  } else {
    input = document.createElement('input');
    input.type = attr.kind === 'number' ? 'number' : 'text';
    if (attr.kind === 'array') input.readOnly = true;
    if (attr.kind === 'number') input.step = attr.whole ? '1' : 'any';
    if (attr.choices) { // an unrestricted @Enum: its values are offered, others typed
      const list = document.createElement('datalist');
      list.id = `choices-${attr.name}`;
      for (const c of attr.choices) list.appendChild(new Option(shown(attr, c), String(attr.kind === 'number' ? c * scale : c)));
      row.appendChild(list);
      input.setAttribute('list', list.id);
    }
    input.addEventListener('change', () => {
      const value = attr.kind === 'number' ? Number(input.value) / scale : input.value;
      if (attr.kind === 'number' && (input.value.trim() === '' || !Number.isFinite(value))) {
        note(`${attr.name} takes a number`);
        return;
      }
      if (attr.whole && !Number.isInteger(value)) {
        note(`${attr.name} is a count: it takes a whole number`);
        return;
      }
      change(attr.name, value);
    });
    if (attr.kind === 'number' && attr.unit) { // the field and its unit on one line
      const line = document.createElement('div');
      line.className = 'with-unit';
      line.append(input, unitMark(attr));
      row.appendChild(line);
    } else row.appendChild(input);
  }
  input.name = attr.name;
  row.input = input;
  parent.appendChild(row);
  return row;
}

// A typed number as the attr takes it: as typed, even outside its range or off its stepsize
// (a range is a hint, as on the command line: the server takes it and warns), whole for a count.
function typedValue(attr, value) {
  let v = value;
  if (attr.whole) v = Math.round(v);
  return Number(v.toPrecision(12)); // no 0.30000000000000004 from the display scale
}

// A drop-down's options: the attr's choices, and its current value if it is none of them (a
// file named in the rule but not found in the project).
function fillChoices(select, attr, value) {
  select.innerHTML = '';
  const values = attr.choices.map(String);
  if (!values.includes(String(value))) select.appendChild(new Option(shown(attr, value), String(value)));
  for (const c of attr.choices) select.appendChild(new Option(shown(attr, c), String(c)));
  select.dataset.current = String(value);
}

function updateRow(row, attr, stability) {
  const input = row.input;
  const busy = app.dragging === attr.name || (app.pending && attr.name in app.pending) || (document.activeElement === input && input.type !== 'range');
  if (!busy) {
    if (input.type === 'checkbox') input.checked = Boolean(attr.value);
    else if (input.type === 'color') input.value = String(attr.value).toLowerCase();
    else if (input.tagName === 'SELECT') {
      if (!attr.choices.map(String).includes(String(attr.value)) || input.dataset.current !== String(attr.value)) fillChoices(input, attr, attr.value);
      input.value = String(attr.value);
    } else if (attr.kind === 'array') input.value = JSON.stringify(attr.value);
    else if (input.type === 'number') input.value = Number((attr.value * scaleOf(attr)).toPrecision(12));
    else input.value = attr.value;
    const shownValue = row.querySelector('.value');
    if (shownValue.tagName !== 'INPUT') shownValue.textContent = '';
    // a search's value shown to 6 digits (one typed stays as typed: it has no more)
    else if (document.activeElement !== shownValue) shownValue.value = Number((attr.value * scaleOf(attr)).toPrecision(6));
  }
  // the designer's value is marked, with the rule's default it hides, and can be reset
  const mark = row.querySelector('.user');
  mark.hidden = !attr.user;
  row.querySelector('.reset').hidden = !attr.user;
  row.classList.toggle('set', attr.user);
  mark.title = attr.user ? `set on the page: ${shown(attr, attr.value)}; the rule's default: ${shown(attr, attr.default)}` : '';
  if (input.type !== 'range' || !attr.free) return;
  const lane = row.querySelector('.lane');
  lane.querySelectorAll('.shade, .tick').forEach((e) => e.remove());
  const status = row.querySelector('.status');
  const span = attr.maximum - attr.minimum;
  const at = (x) => `${(100 * (x - attr.minimum)) / span}%`;
  if (!stability) { status.textContent = ''; return; }
  if (stability.status === 'done') {
    for (const [lo, hi] of stability.intervals) {
      const shade = document.createElement('div');
      shade.className = 'shade';
      shade.style.left = at(lo);
      shade.style.width = `max(3px, ${(100 * (hi - lo)) / span}%)`;
      lane.appendChild(shade);
    }
    const text = stability.intervals.map(([lo, hi]) => `${shown(attr, lo)}–${shown(attr, hi)}`).join(', ');
    status.textContent = stability.intervals.length
      ? `stands for ${text} (±${shown(attr, stability.resolution)})`
      : 'stands nowhere in its range, the others held';
  } else {
    for (const [x, stands] of stability.samples || []) {
      const tick = document.createElement('div');
      tick.className = 'tick';
      tick.style.left = at(x);
      tick.style.background = stands ? '#4caf50' : '#e57373';
      lane.appendChild(tick);
    }
    status.textContent = stability.status === 'waiting' ? 'stable range: waiting…' : `stable range: scanning (${(stability.samples || []).length} designs judged)…`;
  }
}

// ------------------------------------------------------------------ formatting
function number(x) {
  if (x === null || x === undefined || Number.isNaN(x)) return '–';
  if (x === 0) return '0';
  const a = Math.abs(x);
  if (a >= 1e5 || a < 1e-3) return x.toExponential(2);
  return Number(x.toPrecision(4)).toString();
}

function newtons(x) {
  if (x === null || x === undefined) return '–';
  return Math.abs(x) >= 1e3 ? `${number(x / 1e3)} kN` : `${number(x)} N`;
}

function escape(text) {
  return text.replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' })[c]);
}

function note(text) {
  $('message').hidden = !text;
  $('message').textContent = text;
}

refresh();
