// window.penumbra: a small view of the page's state for tests (tests/web) and for people at the
// console: counts, versions, a receiver's arrays (its parts merged), projections to the screen;
// and, for measuring, a timer-driven move of an object and a timed orbit of the camera.
import * as THREE from 'three';
import { CLASS_PENUMBRA, receiverKey } from './mesh_binary.js';
import { blockingShellFaces } from './default_camera.js';
import { inView } from './placement.js';
import { transformOf } from './scene_transform.js';

// Barycentric interpolation of a receiver's irradiance at a point on its plane; null outside.
function irradianceAt(receiver, point) {
  const n = receiver.normal.map(Math.abs);
  const drop = n[0] > n[1] && n[0] > n[2] ? 0 : n[1] > n[2] ? 1 : 2;
  const [u, v] = [0, 1, 2].filter((k) => k !== drop);
  const p = receiver.positions, idx = receiver.indices, e = receiver.irradiance;
  for (let t = 0; t < idx.length; t += 3) {
    const [a, b, c] = [idx[t], idx[t + 1], idx[t + 2]];
    const ax = p[3 * a + u], ay = p[3 * a + v];
    const d = (p[3 * b + u] - ax) * (p[3 * c + v] - ay) - (p[3 * c + u] - ax) * (p[3 * b + v] - ay);
    if (d === 0) continue;
    const wb = ((point[u] - ax) * (p[3 * c + v] - ay) - (p[3 * c + u] - ax) * (point[v] - ay)) / d;
    const wc = ((p[3 * b + u] - ax) * (point[v] - ay) - (point[u] - ax) * (p[3 * b + v] - ay)) / d;
    const wa = 1 - wb - wc;
    if (wa < -1e-9 || wb < -1e-9 || wc < -1e-9) continue;
    return [0, 1, 2].map((k) => wa * e[3 * a + k] + wb * e[3 * b + k] + wc * e[3 * c + k]);
  }
  return null;
}

export function installTestHook(app) {
  // Frames drawn that showed a newer mesh version than the frame before: the shadow updates a user sees.
  let drawnVersion = null;
  let meshFramesDrawn = 0;
  app.view.onDraw(() => {
    const version = app.meshSync ? app.meshSync.version : null;
    if (version !== drawnVersion) ++meshFramesDrawn;
    drawnVersion = version;
  });
  const hook = {
    ready: false,
    state() {
      const counts = app.receivers.counts();
      return {
        ready: hook.ready, sceneId: app.state.id, version: app.meshSync ? app.meshSync.version : null, ...counts,
        editsSent: app.edits.coalescer.sent, editsReplaced: app.edits.coalescer.replaced,
        busy: app.busy(), selected: app.gizmo ? app.gizmo.selected : null, gizmoAxis: app.gizmo ? app.gizmo.controls.axis : null,
        dragging: app.gizmo ? app.gizmo.dragging : false,
        errors: [...app.banner.errors], bannerVisible: app.banner.visible(),
        renders: app.renderPanel ? app.renderPanel.renders : 0, renderVersion: app.renderPanel ? app.renderPanel.lastVersion : null,
        lastFrame: app.timings.frame, roundTrip: app.timings.roundTrip, phases: app.timings.phases || null, totals: { ...app.timings.totals }, frames: app.view.frames, meshFramesDrawn, frameCache: { ...app.view.cache.stats, active: app.view.cache.active }, pixelRatio: app.view.renderer.getPixelRatio(),
        mesh: app.meshSync ? { lastBytes: app.meshSync.lastBytes, totalBytes: app.meshSync.totalBytes, fetches: app.meshSync.fetches } : null,
        events: app.events ? app.events.events : 0, connection: app.events ? app.events.state : null,
        editHistory: app.plot.history.length,
        loading: { visible: app.loading.visible(), text: app.loading.text.textContent, controlsDisabled: app.loading.controls.disabled,
          readySeconds: app.loading.readySeconds ?? null },
        gl: app.view.gl, canvas: { width: app.view.renderer.domElement.clientWidth, height: app.view.renderer.domElement.clientHeight },
      };
    },
    receiver(object, face) {
      const r = app.receivers.receiver(receiverKey(object, face));
      return r && { sceneVersion: r.sceneVersion, vertexCount: r.vertexCount, parts: r.parts, irradiance: Array.from(r.irradiance),
        classes: Array.from(r.classes), positions: Array.from(r.positions) };
    },
    // Area (m²) of a receiver's triangles with a corner in penumbra: how wide its soft shadows are.
    penumbraArea(object, face) {
      const r = app.receivers.receiver(receiverKey(object, face));
      if (!r) return null;
      const p = r.positions, idx = r.indices;
      const corner = (i) => new THREE.Vector3(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
      let area = 0;
      for (let t = 0; t < idx.length; t += 3) {
        if (![0, 1, 2].some((k) => r.classes[idx[t + k]] === CLASS_PENUMBRA)) continue;
        const a = corner(idx[t]);
        area += corner(idx[t + 1]).sub(a).cross(corner(idx[t + 2]).sub(a)).length() / 2;
      }
      return area;
    },
    irradianceAt(object, face, point) {
      const r = app.receivers.receiver(receiverKey(object, face));
      return r ? irradianceAt(r, point) : null;
    },
    // A world point → page (client) coordinates of the canvas, for page.mouse.
    screenOf(point) {
      const rect = app.view.renderer.domElement.getBoundingClientRect();
      const p = app.view.projectToPixel(point, rect.width, rect.height);
      return { x: rect.left + p.x, y: rect.top + p.y };
    },
    // The point t gizmo units along a world axis (x|y|z) from the selected object (the
    // translate handles' pickers span 0..0.6 units; a unit is TransformControls' screen scale).
    gizmoAxisPoint(axis, t) {
      const holder = app.gizmo.holder();
      const centre = holder.getWorldPosition(new THREE.Vector3());
      const camera = app.view.camera;
      const factor = camera.isPerspectiveCamera
        ? centre.distanceTo(camera.position) * Math.min(1.9 * Math.tan(Math.PI * camera.fov / 360) / camera.zoom, 7)
        : (camera.top - camera.bottom) / camera.zoom;
      const dir = new THREE.Vector3(axis === 'x' ? 1 : 0, axis === 'y' ? 1 : 0, axis === 'z' ? 1 : 0);
      return centre.addScaledVector(dir, t * factor * app.gizmo.controls.size / 4).toArray();
    },
    // Edges of the overlay with both ends above height y, and all of them.
    overlayEdgesAbove(y) {
      let above = 0, total = 0;
      app.receivers.edgeGroup.traverse((o) => {
        if (!o.isLineSegments) return;
        const p = o.geometry.attributes.position.array;
        for (let i = 0; i < p.length; i += 6) {
          ++total;
          if (p[i + 1] > y && p[i + 4] > y) ++above;
        }
      });
      return { above, total };
    },
    // Faces of locked objects (walls, floor) between the camera and its target seen from behind.
    backFacingShellAhead() {
      const shells = [...app.objects.byId.values()].filter((h) => h.userData.locked).length;
      return { shells, blocking: blockingShellFaces(app.objects, app.view.camera.position, app.view.controls.target) };
    },
    gizmoMode() {
      return app.gizmo.controls.mode;
    },
    objectCentre(id) {
      return app.objects.objectBounds(id).getCenter(new THREE.Vector3()).toArray();
    },
    sceneCentre() {
      return app.objects.bounds.getCenter(new THREE.Vector3()).toArray();
    },
    lightCentre(id) {
      const polygon = app.objects.lightJson.get(id).polygon;
      return [0, 1, 2].map((k) => polygon.reduce((s, p) => s + p[k], 0) / polygon.length);
    },
    // Each object's gizmo place (its holder's origin), world bounds centre and whether it is locked.
    pivots() {
      return [...app.objects.byId].map(([id, holder]) => ({ id, locked: holder.userData.locked,
        pivot: holder.getWorldPosition(new THREE.Vector3()).toArray(), centre: app.objects.objectBounds(id).getCenter(new THREE.Vector3()).toArray() }));
    },
    // An object's transform, or a light's holder's ("light:ID": translate = the light's centre).
    objectTransform(id) {
      const holder = app.objects.holderOf(id);
      return holder ? transformOf(holder) : null;
    },
    // The volumes' stand-ins: transform, isovalue held, the preview drawn (its isovalue and points).
    volumes() {
      return app.objects.volumes().map(([id, holder]) => ({ id, transform: transformOf(holder),
        isovalue: app.objects.json.get(id).isovalue, previewIsovalue: holder.userData.previewIsovalue ?? null,
        previewPoints: holder.userData.previewPoints ?? 0, previewFetches: app.volumes.previews.fetches,
        box: !!holder.getObjectByName('volume-box') }));
    },
    // Selects an object, a volume or "light:ID" as a click on it would.
    select(id) {
      app.gizmo.select(id);
      return app.gizmo.selected;
    },
    lightJson(id) {
      return app.objects.lightJson.get(id) || null;
    },
    // Pixels of world points in a width × height image of the current view, by three.js.
    projectToPixels(points, width, height) {
      return points.map((p) => app.view.projectToPixel(p, width, height));
    },
    // The glossy layer's physical materials and area lights (glossy_layer.js describe()).
    physicalMaterials() {
      return app.glossy.describe();
    },
    // The server images shown so far ({version, samples, seconds}, newest last) and aborted passes.
    renderPasses() {
      const panel = app.renderPanel;
      // renders: images shown so far (passes keeps the last 64); inFlight: a pass is being fetched;
      // outcome: how the last refinement ended ('' while it runs).
      return panel ? { passes: [...panel.passes], aborted: panel.aborted, renders: panel.renders, inFlight: panel.abort !== null,
        outcome: panel.outcome } : null;
    },
    // The baked indirect light's state (baked_indirect.js).
    bakedIndirect() {
      const b = app.bakedIndirect;
      return b ? { on: b.on, version: b.version, fetches: b.fetches, aborted: b.aborted, seconds: b.seconds } : null;
    },
    // A receiver's display colours (linear, 3 per vertex) and classes, over its parts.
    displayColours(object, face) {
      const colours = [], classes = [];
      for (const { part, colours: c } of app.receivers.entries.values()) {
        if (part.object !== object || part.face !== face) continue;
        colours.push(...c);
        classes.push(...part.classes);
      }
      return { colours, classes };
    },
    cameraQuery() {
      return app.view.cameraQuery();
    },
    // The view's exposure: the automatic one, the user's offset in stops, their product.
    exposure() {
      return { auto: app.toneMap.auto, ev: app.toneMap.ev, exposure: app.toneMap.exposure };
    },
    // Puts the camera at `position` looking at `target` (as an orbit would).
    lookFrom(position, target) {
      app.view.camera.position.fromArray(position);
      app.view.controls.target.fromArray(target);
      app.view.controls.update();
    },
    // Whether a world point is in front of the camera and inside the view (placement.js inView).
    inView(point, margin = 1) {
      return inView(app.view.camera, point, margin);
    },
    // An object's world bounds {min, max} as drawn.
    objectBox(id) {
      const box = app.objects.objectBounds(id);
      return box ? { min: box.min.toArray(), max: box.max.toArray() } : null;
    },
    idle() {
      return app.idle();
    },
    // Resolves once the view has drawn a frame asked for now (what the page holds is on the screen).
    async drawFrame() {
      const frames = app.view.frames;
      app.view.requestRender();
      while (app.view.frames === frames) await new Promise((resolve) => requestAnimationFrame(resolve));
    },
    // Moves object `id` along x by `dx` metres over `seconds`, one step every `stepMs` from a timer
    // in the page (as the gizmo would, without a pointer's delivery rate), then waits for idle:
    // measures the edit pipeline alone. Returns the steps taken.
    async drive(id, dx, seconds, stepMs) {
      const from = transformOf(app.objects.byId.get(id));
      const steps = Math.max(1, Math.round(seconds * 1000 / stepMs));
      app.view.setInteracting('drag', true); // as a gizmo drag does
      for (let s = 1; s <= steps; ++s) {
        await new Promise((resolve) => setTimeout(resolve, stepMs));
        const translate = [...from.translate];
        translate[0] += dx * s / steps;
        app.edits.moveTo(id, { ...from, translate });
        app.view.requestMotionRender();
      }
      app.view.setInteracting('drag', false);
      await app.idle();
      return steps;
    },
    // Draws the view through the frame cache, then whole, and compares the two pictures (RGBA
    // bytes): {how ('cached', 'rebuilt' or 'direct'), pixels, differing (pixels with a channel more
    // than `tolerance` apart), maxDelta}. During a drag it draws what the next frame would.
    cachedFrameDifference(tolerance = 1) {
      const { renderer, scene, camera, cache } = app.view;
      const gl = renderer.getContext();
      const w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
      const read = () => {
        const pixels = new Uint8Array(4 * w * h);
        gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, pixels);
        return pixels;
      };
      const how = cache.render(scene, camera);
      const cached = read();
      renderer.render(scene, camera);
      const whole = read();
      let differing = 0, maxDelta = 0;
      const examples = []; // [x, y (from the bottom), cached RGB, whole RGB]
      for (let i = 0; i < cached.length; i += 4) {
        const d = Math.max(Math.abs(cached[i] - whole[i]), Math.abs(cached[i + 1] - whole[i + 1]), Math.abs(cached[i + 2] - whole[i + 2]));
        maxDelta = Math.max(maxDelta, d);
        if (d <= tolerance) continue;
        ++differing;
        if (examples.length < 8) examples.push([(i / 4) % w, Math.floor(i / 4 / w), [...cached.slice(i, i + 3)], [...whole.slice(i, i + 3)]]);
      }
      return { how, hotShare: cache.hotShare, pixels: w * h, width: w, height: h, differing, maxDelta, examples };
    },
    // Draws `frames` frames back to back while orbiting the camera a little (as a user would),
    // each waited for by a 1-pixel readPixels, and puts the camera back: {msPerFrame, gl}.
    timeFrames(frames) {
      const { renderer, scene, camera, controls } = app.view;
      const gl = renderer.getContext();
      const pixel = new Uint8Array(4);
      const draw = () => {
        renderer.render(scene, camera);
        gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel);
      };
      const from = camera.position.clone();
      draw(); // warm-up: shaders compiled, buffers uploaded
      const start = performance.now();
      for (let i = 1; i <= frames; ++i) {
        const offset = from.clone().sub(controls.target).applyAxisAngle(camera.up, 0.3 * i / frames);
        camera.position.copy(controls.target).add(offset);
        camera.lookAt(controls.target);
        draw();
      }
      const msPerFrame = (performance.now() - start) / frames;
      camera.position.copy(from);
      camera.lookAt(controls.target);
      app.view.requestRender();
      return { msPerFrame, gl: app.view.gl, width: renderer.domElement.width, height: renderer.domElement.height };
    },
  };
  window.penumbra = hook;
  return hook;
}
