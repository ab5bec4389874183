// The 3D view: renderer (antialiased unless the GL is a software rasteriser), scene, a camera
// made from the scene's camera (perspective or orthographic, as core/raycast/camera_projection.h
// reads it), OrbitControls around its target, and the camera as /image query parameters so the
// server renders exactly this view.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { defaultCamera } from './default_camera.js';
import { FrameCache } from './frame_cache.js';
import { focusEye } from './placement.js';

export class SceneView {
  // antialias: 'auto' (on unless the GL is software), 'on' or 'off'. dragScale: the pixel
  // ratio a software GL draws at while the user drags or orbits ('auto': 0.25). frameCache: whether
  // a drag's frames go through the frame cache (frame_cache.js; never when antialiased).
  constructor(container, { antialias = 'auto', dragScale = 'auto', frameCache = true } = {}) {
    this.container = container;
    // gl_context.js made the context while the modules loaded, for the page's antialias choice.
    const early = window.penumbraGL;
    const { canvas, context, gl } = early && early.antialias === antialias && early.canvas.width === container.clientWidth
      && early.canvas.height === container.clientHeight ? early : window.makeWebGLContext(antialias, container);
    window.penumbraGL = null;
    this.gl = gl;
    const probe = gl;
    // A software rasteriser's frame time grows with the pixels drawn (SwiftShader, 150 cubes
    // at 940×800: 59 ms a frame, 31 ms at half resolution); while something moves, a quarter of
    // the resolution keeps the shadows up with the pointer, and full resolution returns when it
    // stops (mouse drag on 150 cubes, 2 shared cores, A/B interleaved, shadow updates drawn a
    // second: 17.7–18.1 at half resolution, 18.8–21.0 at a quarter; 0.35 was no better than 0.5).
    this.gl.dragScale = dragScale === 'auto' ? (probe.software ? 0.25 : 1) : Math.min(Math.max(Number(dragScale) || 1, 0.25), 1);
    this.interactions = new Set();
    this.renderer = new THREE.WebGLRenderer(context ? { canvas, context } : { antialias: this.gl.antialias });
    this.renderer.setPixelRatio(1);
    this.renderer.outputColorSpace = THREE.SRGBColorSpace;
    this.cache = new FrameCache(this.renderer); // a drag's frames: what changed over a picture of the rest
    this.cacheDrags = frameCache && !this.gl.antialias;
    container.appendChild(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0x000000);
    this.camera = null;
    this.controls = null;
    this.listeners = [];
    this.renderPending = false;
    this.holdTimer = null;
    this.motionPending = false; // a motion frame asked for in the event being handled
    this.motionHold = () => 0; // ms a moved object's frame may wait for the shadow update on its way
    this.frames = 0;
    this.drawListeners = [];
    this.onCameraChange(() => this.requestRender());
    window.addEventListener('resize', () => this.resize());
  }

  // sceneCamera: the scene JSON's camera, or undefined (then a default camera framing `bounds`,
  // from a side where the walls among `objects` do not hide the inside: default_camera.js).
  setCamera(sceneCamera, bounds, objects = null) {
    const c = sceneCamera ? { ...defaultCamera(bounds), ...sceneCamera } : defaultCamera(bounds, objects);
    this.home = c;
    const aspect = this.aspect();
    if (c.projection === 'orthographic') {
      const h = (c.height || 2) / 2;
      this.camera = new THREE.OrthographicCamera(-aspect * h, aspect * h, h, -h, c.near, c.far);
      this.orthoHeight = c.height || 2;
    } else {
      this.camera = new THREE.PerspectiveCamera(c.fov_y_deg, aspect, c.near, c.far);
    }
    this.camera.up.fromArray(c.up);
    this.camera.position.fromArray(c.position);
    this.camera.lookAt(new THREE.Vector3(...c.target));
    if (this.controls) this.controls.dispose();
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.target.fromArray(c.target);
    this.floorY = bounds && !bounds.isEmpty() ? bounds.min.y : -Infinity;
    // Not quite straight down: the server refuses a view direction parallel to `up` (the page's /image).
    this.controls.minPolarAngle = 0.01;
    this.limitOrbit();
    this.controls.update();
    this.controls.addEventListener('change', () => {
      this.keepAboveFloor();
      this.limitOrbit();
      this.listeners.forEach((f) => f());
    });
    this.controls.addEventListener('start', () => this.setInteracting('orbit', true));
    this.controls.addEventListener('end', () => this.setInteracting('orbit', false));
    this.resize();
  }

  // Back to the camera the view started with (the scene's, else the default one).
  goHome() {
    const c = this.home;
    this.camera.up.fromArray(c.up);
    this.camera.position.fromArray(c.position);
    this.controls.target.fromArray(c.target);
    this.camera.zoom = 1;
    this.camera.updateProjectionMatrix();
    this.limitOrbit();
    this.controls.update();
    this.listeners.forEach((f) => f());
  }

  // Orbiting stops where the camera would go under the floor (the room is never seen from below):
  // the largest polar angle (from straight up) at which the eye, at its distance, is above the floor.
  limitOrbit() {
    const r = this.camera.position.distanceTo(this.controls.target);
    const c = (this.floorY + 1e-3 - this.controls.target.y) / Math.max(r, 1e-9);
    this.controls.maxPolarAngle = c <= -1 ? Math.PI : c >= 1 ? this.controls.minPolarAngle : Math.max(Math.acos(c), this.controls.minPolarAngle);
  }

  // A pan or dolly that took the camera under the floor: camera and target lifted together.
  keepAboveFloor() {
    const below = this.floorY + 1e-3 - this.camera.position.y;
    if (!(below > 0)) return;
    this.camera.position.y += below;
    this.controls.target.y += below;
  }

  // Turns to `box` (THREE.Box3) and backs off along the current view direction until its bounding
  // sphere fits the view (F: the selection, frame all: the scene). With `room` (a Box3) the
  // camera stays inside it, on the side of the selection the room is (placement.js focusEye).
  frame(box, room = null) {
    if (!box || box.isEmpty()) return;
    const centre = box.getCenter(new THREE.Vector3());
    const radius = Math.max(box.getSize(new THREE.Vector3()).length() / 2, 1e-3);
    const direction = this.camera.position.clone().sub(this.controls.target).normalize();
    if (!room && direction.y < 0) direction.y = -direction.y; // the whole scene from above, not from under its floor
    if (this.camera.isPerspectiveCamera) {
      const halfFov = Math.min(this.camera.fov, this.camera.fov * this.aspect()) * Math.PI / 360;
      this.camera.zoom = 1;
      const distance = 1.1 * radius / Math.sin(halfFov);
      this.camera.position.copy(room ? focusEye(centre, direction, distance, room) : centre.clone().addScaledVector(direction, distance));
      this.camera.far = Math.max(this.camera.far, 4 * radius + this.camera.position.distanceTo(centre));
    } else {
      this.camera.zoom = Math.min(this.camera.top - this.camera.bottom, this.camera.right - this.camera.left) / (2.2 * radius);
      this.camera.position.copy(centre).addScaledVector(direction, this.camera.position.distanceTo(this.controls.target));
    }
    this.controls.target.copy(centre);
    this.camera.updateProjectionMatrix();
    this.limitOrbit();
    this.controls.update();
    this.listeners.forEach((f) => f());
  }

  // Something (`what`: 'orbit', 'drag') starts or stops moving: the drawing resolution follows
  // (gl.dragScale while anything moves, else full), and a drag's frames go through the frame cache
  // (which starts again whenever the camera moves: a press on the gizmo also starts an 'orbit').
  setInteracting(what, active) {
    if (active) this.interactions.add(what);
    else this.interactions.delete(what);
    const cached = this.cacheDrags && this.interactions.has('drag');
    if (cached && !this.cache.active) this.cache.begin();
    else if (!cached) this.cache.end();
    const ratio = this.interactions.size ? this.gl.dragScale : 1;
    if (this.renderer.getPixelRatio() === ratio) return;
    this.renderer.setPixelRatio(ratio);
    this.renderer.setSize(this.container.clientWidth, this.container.clientHeight);
    this.requestRender();
  }

  // listener() after each frame drawn.
  onDraw(listener) {
    this.drawListeners.push(listener);
  }

  onCameraChange(listener) {
    this.listeners.push(listener);
  }

  aspect() {
    const { clientWidth: w, clientHeight: h } = this.container;
    return w > 0 && h > 0 ? w / h : 1;
  }

  resize() {
    const { clientWidth: w, clientHeight: h } = this.container;
    const size = this.renderer.getSize(new THREE.Vector2());
    if (size.x !== w || size.y !== h) this.renderer.setSize(w, h);
    if (!this.camera) return;
    const aspect = this.aspect();
    if (this.camera.isPerspectiveCamera) {
      this.camera.aspect = aspect;
    } else {
      const half = this.orthoHeight / 2;
      Object.assign(this.camera, { left: -aspect * half, right: aspect * half, top: half, bottom: -half });
    }
    this.camera.updateProjectionMatrix();
    this.listeners.forEach((f) => f());
  }

  // The current view as /image query parameters (docs/API.md "GET .../image").
  cameraQuery() {
    const c = this.camera;
    const list = (v) => v.toArray().map((x) => x.toPrecision(17)).join(',');
    const query = { position: list(c.position), target: list(this.controls.target), up: list(c.up),
      near: String(c.near), far: String(c.far) };
    if (c.isPerspectiveCamera) {
      // three.js divides the frustum's top by zoom: the same as a narrower field of view.
      const fov = c.zoom === 1 ? c.fov : 2 * Math.atan(Math.tan(c.fov * Math.PI / 360) / c.zoom) * 180 / Math.PI;
      Object.assign(query, { projection: 'perspective', fov_y_deg: String(fov) });
    }
    else {
      Object.assign(query, { projection: 'orthographic', ortho_height: String((c.top - c.bottom) / c.zoom) });
    }
    return query;
  }

  // A world point → continuous pixel coordinates of a width × height image (y down, pixel
  // centres at +0.5), through three.js's Vector3.project.
  projectToPixel(point, width, height) {
    const ndc = new THREE.Vector3(...point).project(this.camera);
    return { x: (ndc.x + 1) / 2 * width, y: (1 - ndc.y) / 2 * height, z: ndc.z };
  }

  // Draws on the next animation frame, once however often it is asked: the page draws only
  // when something changed (camera, mesh, gizmo), which keeps a software-rendered browser idle.
  requestRender() {
    clearTimeout(this.holdTimer);
    this.holdTimer = null;
    if (this.renderPending) return;
    this.renderPending = true;
    requestAnimationFrame(() => {
      this.renderPending = false;
      this.cache.render(this.scene, this.camera);
      ++this.frames;
      this.drawListeners.forEach((f) => f());
    });
  }

  // A frame for an object the user moved: drawn at once, unless a shadow update is on its way
  // (motionHold() > 0 ms), then drawn with that update, or after that long if it is late. On a
  // software GL a frame costs tens of milliseconds of the CPU the server shares, so a frame that
  // showed only the moved stand-in would delay the next one that shows its shadow.
  requestMotionRender() {
    // Decided once the current event is handled: the gizmo reports a move before the move's edit
    // is queued, and a frame drawn then would show the cube without its new shadow.
    if (this.motionPending) return;
    this.motionPending = true;
    queueMicrotask(() => {
      this.motionPending = false;
      this.holdForShadows();
    });
  }

  holdForShadows() {
    const hold = this.motionHold();
    if (!(hold > 0)) return this.requestRender();
    if (this.renderPending || this.holdTimer !== null) return;
    this.holdTimer = setTimeout(() => this.requestRender(), hold);
  }
}
