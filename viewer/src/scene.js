// The three.js side: renderer, camera and controls, the map mesh, and rendering on demand (a
// frame only when something changed, which keeps an idle page at zero CPU).
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { HATCH_PERIOD_PX, UNKNOWN_HATCH_RGB } from './colormaps.js';

// Colours are sRGB bytes end to end (the legend's CSS, the vertex colours, the overlays'
// materials): no linear-space conversion, so the screen shows exactly the legend's colours.
THREE.ColorManagement.enabled = false;

/**
 * The map's material: unlit vertex colours (shading is baked in, layers.js), plus diagonal
 * screen-space stripes on faces whose `hatch` attribute is set (unknown faces).
 */
function mapMaterial() {
  const material = new THREE.MeshBasicMaterial({ vertexColors: true, side: THREE.DoubleSide });
  const stripe = UNKNOWN_HATCH_RGB.map((c) => (c / 255).toFixed(4)).join(', ');
  const half = (HATCH_PERIOD_PX / 2).toFixed(1);
  material.onBeforeCompile = (shader) => {
    shader.vertexShader = shader.vertexShader
      .replace('void main() {', 'attribute float hatch;\nvarying float vHatch;\nvoid main() {\n  vHatch = hatch;');
    shader.fragmentShader = shader.fragmentShader
      .replace('void main() {', 'varying float vHatch;\nvoid main() {')
      .replace('#include <opaque_fragment>', `if (vHatch > 0.5 && mod(floor((gl_FragCoord.x + gl_FragCoord.y) / ${half}), 2.0) < 1.0) {
    outgoingLight = vec3(${stripe});
  }
  #include <opaque_fragment>`);
  };
  return material;
}

export class MapScene {
  constructor(canvas) {
    this.canvas = canvas;
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: false });
    this.renderer.outputColorSpace = THREE.LinearSRGBColorSpace;
    this.renderer.setClearColor(0x1e2228);
    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(50, 1, 0.01, 1000);
    this.controls = new OrbitControls(this.camera, canvas);
    this.controls.addEventListener('change', () => this.requestRender());
    // While the user drags, render at half resolution: software rendering is fill-bound.
    this.pixelRatio = Math.min(2, window.devicePixelRatio || 1);
    this.renderer.setPixelRatio(this.pixelRatio);
    this.controls.addEventListener('start', () => this.setPixelRatio(0.5 * this.pixelRatio));
    this.controls.addEventListener('end', () => this.setPixelRatio(this.pixelRatio));
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x404040, 1.6));
    this.sun = new THREE.DirectionalLight(0xffffff, 1.4);
    this.scene.add(this.sun);
    this.overlays = new THREE.Group();
    this.scene.add(this.overlays);
    // Shading is baked into the colours (layers.js): the cheapest fragment shader, which is what
    // keeps large maps interactive in software rendering.
    this.material = mapMaterial();
    this.mesh = null;
    this.tiles = new Map();  // a tiled map's meshes by tile name (addTile)
    this.frames = 0;
    this.pending = false;
    new ResizeObserver(() => this.resize()).observe(canvas);
    this.resize();
  }

  setPixelRatio(ratio) {
    this.renderer.setPixelRatio(ratio);
    this.resize();
  }

  resize() {
    const { clientWidth: w, clientHeight: h } = this.canvas;
    if (w === 0 || h === 0) return;
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.requestRender();
  }

  requestRender() {
    if (this.pending) return;
    this.pending = true;
    requestAnimationFrame(() => { this.pending = false; this.renderNow(); });
  }

  renderNow() {
    this.renderer.render(this.scene, this.camera);
    ++this.frames;
  }

  /**
   * Sets the world's up vector (map_frame.yaml) and places the camera to see `radius` around
   * `centre` (scene coordinates, default the origin).
   */
  frame(up, radius, centre = [0, 0, 0]) {
    const u = new THREE.Vector3(...up).normalize();
    this.camera.up.copy(u);
    const side = Math.abs(u.x) < 0.9 ? new THREE.Vector3(1, 0, 0) : new THREE.Vector3(0, 1, 0);
    side.sub(u.clone().multiplyScalar(side.dot(u))).normalize();
    const r = Math.max(radius, 1e-3);
    const c = new THREE.Vector3(...centre);
    this.camera.position.copy(u.clone().multiplyScalar(1.5 * r).add(side.multiplyScalar(-1.1 * r)).add(c));
    this.camera.near = r / 1000;
    this.camera.far = r * 50;
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(c);
    this.controls.update();
    this.sun.position.copy(u.clone().multiplyScalar(2 * r).add(new THREE.Vector3(r, 0.5 * r, 0)));
    this.requestRender();
  }

  /** Moves the camera and its target together so that the target is at `point` (scene coordinates). */
  moveTargetTo(point) {
    const delta = new THREE.Vector3(...point).sub(this.controls.target);
    this.camera.position.add(delta);
    this.controls.target.add(delta);
    this.controls.update();
    this.requestRender();
  }

  /** Replaces the map mesh by a worker-built one; returns its colour and hatch buffers to fill. */
  setMesh(data) {
    if (this.mesh) {
      this.scene.remove(this.mesh);
      this.mesh.geometry.dispose();
    }
    const { mesh, buffers } = this.buildMesh(data);
    this.mesh = mesh;
    this.scene.add(mesh);
    this.requestRender();
    return buffers;
  }

  /** Adds (or replaces) tile `name` of a tiled map; returns its colour and hatch buffers to fill. */
  addTile(name, data) {
    this.removeTile(name);
    const { mesh, buffers } = this.buildMesh(data);
    this.tiles.set(name, mesh);
    this.scene.add(mesh);
    this.requestRender();
    return buffers;
  }

  removeTile(name) {
    const mesh = this.tiles.get(name);
    if (!mesh) return;
    this.scene.remove(mesh);
    mesh.geometry.dispose();
    this.tiles.delete(name);
    this.requestRender();
  }

  buildMesh(data) {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(data.positions, 3));
    const colours = new Uint8Array(data.positions.length);
    geometry.setAttribute('color', new THREE.BufferAttribute(colours, 3, true));
    const hatch = new Uint8Array(data.positions.length / 3);
    geometry.setAttribute('hatch', new THREE.BufferAttribute(hatch, 1, true));
    geometry.computeBoundingSphere();
    const mesh = new THREE.Mesh(geometry, this.material);
    mesh.userData = data;
    return { mesh, buffers: { colours, hatch } };
  }

  /** The colours of the map mesh (or of tile `name`) were filled in. */
  coloursChanged(name) {
    const mesh = name === undefined ? this.mesh : this.tiles.get(name);
    if (!mesh) return;
    mesh.geometry.attributes.color.needsUpdate = true;
    mesh.geometry.attributes.hatch.needsUpdate = true;
    this.requestRender();
  }

  /** Measured faces come first: hiding Steiner faces draws only them (every mesh shown). */
  showSteiner(show) {
    for (const mesh of [this.mesh, ...this.tiles.values()]) {
      if (!mesh) continue;
      const data = mesh.userData;
      mesh.geometry.setDrawRange(0, 3 * (show ? data.faces : data.measured));
    }
    this.requestRender();
  }

  /**
   * Renders continuously for `seconds`, turning the camera; resolves {fps, frames, seconds}.
   * `finish` waits for each frame on the CPU (SwiftShader otherwise queues work and the count lies);
   * `dragging` renders at the reduced resolution used while the user drags.
   */
  measureFps(seconds, finish = true, dragging = false) {
    if (dragging) this.setPixelRatio(0.5 * this.pixelRatio);
    return new Promise((resolve) => {
      const start = performance.now();
      let frames = 0;
      const tick = () => {
        const elapsed = performance.now() - start;
        if (elapsed >= 1000 * seconds) {
          if (dragging) this.setPixelRatio(this.pixelRatio);
          resolve({ fps: (1000 * frames) / elapsed, frames, seconds: elapsed / 1000 });
          return;
        }
        this.controls.object.position.applyAxisAngle(this.camera.up, 0.01);
        this.controls.update();
        this.renderNow();
        if (finish) this.renderer.getContext().finish();
        ++frames;
        requestAnimationFrame(tick);
      };
      requestAnimationFrame(tick);
    });
  }
}
