// A 3D Tiles 1.1 tileset of a shapegen city, drawn with three.js (served locally, nothing
// fetched from elsewhere). Every tile's content is loaded (a city is small enough); its glTF
// is turned z-up as 3D Tiles says, placed by the tiles' transforms, then brought back into the
// root's east-north-up frame and turned y-up for three.js.
import * as THREE from "three";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";
import { GLTFLoader } from "three/addons/loaders/GLTFLoader.js";

const state = {
  tilesTotal: 0, tilesLoaded: 0, meshes: 0, buildings: [], errors: [], done: false,
};
window.shapegenTiles = state;

const Y_UP_TO_Z_UP = new THREE.Matrix4().makeRotationX(Math.PI / 2); // (x, y, z) -> (x, -z, y)
const Z_UP_TO_Y_UP = new THREE.Matrix4().makeRotationX(-Math.PI / 2);

const view = document.getElementById("view");
const status = document.getElementById("status");
const renderer = new THREE.WebGLRenderer({ antialias: true });
renderer.setPixelRatio(window.devicePixelRatio);
renderer.setSize(view.clientWidth, view.clientHeight);
view.appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0xeef1f4);
scene.add(new THREE.HemisphereLight(0xffffff, 0x8899aa, 1.6));
scene.add(new THREE.AmbientLight(0xffffff, 0.8)); // no face in full shadow
const sun = new THREE.DirectionalLight(0xffffff, 1.6);
sun.position.set(-0.5, 1.0, 0.3);
scene.add(sun);
const camera = new THREE.PerspectiveCamera(45, view.clientWidth / view.clientHeight, 0.5, 1e5);
const controls = new OrbitControls(camera, renderer.domElement);
controls.addEventListener("change", draw);
window.addEventListener("resize", () => {
  camera.aspect = view.clientWidth / view.clientHeight;
  camera.updateProjectionMatrix();
  renderer.setSize(view.clientWidth, view.clientHeight);
  draw();
});

function draw() { renderer.render(scene, camera); }

function matrixOf(tile) {
  return tile.transform ? new THREE.Matrix4().fromArray(tile.transform) : new THREE.Matrix4();
}

// [{uri, matrix}] of every tile with content, its transform the product of its ancestors'.
function contents(tile, parent, found) {
  const world = parent.clone().multiply(matrixOf(tile));
  if (tile.content && tile.content.uri) found.push({ uri: tile.content.uri, world });
  for (const child of tile.children || []) contents(child, world, found);
  return found;
}

async function load() {
  const base = new URL("tiles/", window.location.href);
  const response = await fetch(new URL("tileset.json", base));
  if (!response.ok) throw new Error(`tiles/tileset.json: HTTP ${response.status}`);
  const tileset = await response.json();
  const rootInverse = matrixOf(tileset.root).invert();
  const found = contents(tileset.root, new THREE.Matrix4(), []);
  state.tilesTotal = found.length;
  const loader = new GLTFLoader();
  await Promise.all(found.map(async ({ uri, world }) => {
    const gltf = await loader.loadAsync(new URL(uri, base).href);
    // glTF y-up -> tile z-up -> ECEF -> the root's ENU -> three.js y-up
    const display = Z_UP_TO_Y_UP.clone().multiply(rootInverse).multiply(world)
      .multiply(Y_UP_TO_Z_UP);
    gltf.scene.applyMatrix4(display);
    gltf.scene.traverse((node) => {
      if (node.isMesh) {
        state.meshes += 1;
        state.buildings.push(node.name || node.parent.name);
        node.material.side = THREE.DoubleSide;
      }
    });
    scene.add(gltf.scene);
    state.tilesLoaded += 1;
    status.textContent = `${state.tilesLoaded} of ${state.tilesTotal} tiles`;
  }));
  frame();
  status.textContent = `${state.buildings.length} buildings in ${state.tilesLoaded} tiles`;
  state.done = true;
}

function frame() {
  const box = new THREE.Box3().setFromObject(scene);
  if (box.isEmpty()) return;
  const centre = box.getCenter(new THREE.Vector3());
  const radius = box.getSize(new THREE.Vector3()).length() / 2;
  camera.position.copy(centre).add(new THREE.Vector3(0.6, 0.8, 0.9).multiplyScalar(radius * 1.3));
  camera.far = radius * 20;
  camera.updateProjectionMatrix();
  controls.target.copy(centre);
  controls.update();
  draw();
}

load().catch((error) => {
  state.errors.push(String(error));
  status.textContent = `could not load the tiles: ${error}`;
  console.error(error);
  state.done = true;
});
