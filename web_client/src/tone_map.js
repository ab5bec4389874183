// Irradiance → display colour, with the server renderer's exposure idea (core/render/renderer.h):
// radiance = albedo/π · (E + ambient), ambient = 10% of the lights' power spread over the
// surface of the scene's bounding box (so faces no light reaches are not black); automatic exposure
// = 1 / the 99th percentile of the surfaces' largest radiance channel, taken over the mesh's
// vertices (not the pixels) when the scene loads or its lights change (look_setting.js keeps it per
// scene), not while objects move; the user's offset in stops (ev) scales it. A metal (conductor)
// has no diffuse reflection: its DM colours are drawn at METAL_DIFFUSE of its albedo, under the
// glossy layer's reflection, so it reads dark and shiny as in the server's render. Colours are
// linear; the renderer's sRGB output encodes them like the server's PNG.
import * as THREE from 'three';

const AMBIENT_FRACTION = 0.1;
const PERCENTILE = 0.99;
export const METAL_DIFFUSE = 0.25;

function polygonArea(polygon) {
  const n = new THREE.Vector3();
  const a = new THREE.Vector3(), b = new THREE.Vector3();
  for (let k = 0; k < polygon.length; ++k) {
    a.fromArray(polygon[k]);
    b.fromArray(polygon[(k + 1) % polygon.length]);
    n.add(new THREE.Vector3().crossVectors(a, b));
  }
  return n.length() / 2;
}

export class ToneMap {
  // scene: scene JSON v1; bounds: THREE.Box3 of lights and world-space faces (as core's Scene::bounds).
  constructor(scene, bounds) {
    this.bounds = bounds;
    this.setLights(scene.lights);
    this.learnObjects(scene);
    this.auto = 1;
    this.ev = 0;
    this.calibrated = false;
  }

  // The exposure the colours use: the automatic one, times 2^ev.
  get exposure() {
    return this.auto * 2 ** this.ev;
  }

  // The ambient term from the lights' power (again after they changed).
  setLights(lights) {
    const power = [0, 0, 0];
    for (const light of lights) {
      const area = polygonArea(light.polygon);
      for (let c = 0; c < 3; ++c) power[c] += Math.PI * light.radiance[c] * area;
    }
    const e = this.bounds.getSize(new THREE.Vector3());
    const surface = 2 * (e.x * e.y + e.y * e.z + e.z * e.x);
    this.ambient = power.map((p) => (surface > 0 ? AMBIENT_FRACTION * p / surface : 0));
  }

  // The objects' albedos (again after objects were added); the exposure stays as calibrated.
  learnObjects(scene) {
    this.albedo = new Map();
    this.calibrationAlbedo = new Map(); // a metal's own albedo: its dimmed colour does not raise the exposure
    for (const object of scene.objects) {
      const material = object.material && scene.materials ? scene.materials[object.material] : null;
      const albedo = (material && material.albedo) || [0.8, 0.8, 0.8];
      this.albedo.set(object.id, material && material.type === 'conductor' ? albedo.map((a) => METAL_DIFFUSE * a) : albedo);
      this.calibrationAlbedo.set(object.id, albedo);
    }
  }

  // Sets the automatic exposure from the mesh's parts ({object, irradiance: Float32Array}).
  // (A chunk-border vertex counts once per part holding it: too few to move the percentile.)
  calibrate(parts) {
    this.calibrated = true;
    const values = [];
    for (const r of parts) {
      const albedo = this.calibrationAlbedo.get(r.object) || [0.8, 0.8, 0.8];
      for (let i = 0; i < r.irradiance.length; i += 3) {
        let m = 0;
        for (let c = 0; c < 3; ++c) m = Math.max(m, albedo[c] / Math.PI * (r.irradiance[i + c] + this.ambient[c]));
        values.push(m);
      }
    }
    if (!values.length) return;
    values.sort((a, b) => a - b);
    const v = values[Math.min(values.length - 1, Math.floor(PERCENTILE * values.length))];
    if (v > 0) this.auto = 1 / v;
  }

  albedoOf(objectId) {
    return this.albedo.get(objectId) || [0.8, 0.8, 0.8];
  }

  // Linear display colours (Float32Array, 3 per vertex, clamped to [0, 1]). indirect (same
  // length, the baked bounced light) replaces the flat ambient term, as GI does in the server's image.
  colours(objectId, irradiance, indirect = null) {
    const albedo = this.albedoOf(objectId);
    const out = new Float32Array(irradiance.length);
    for (let i = 0; i < irradiance.length; i += 3)
      for (let c = 0; c < 3; ++c) {
        const extra = indirect ? indirect[i + c] : this.ambient[c];
        out[i + c] = Math.min(1, this.exposure * albedo[c] / Math.PI * (irradiance[i + c] + extra));
      }
    return out;
  }

  // The colour of a face that receives no light (ambient only), as three.js Color.
  ambientColour(objectId) {
    const albedo = this.albedoOf(objectId);
    return new THREE.Color(...albedo.map((a, c) => Math.min(1, this.exposure * a / Math.PI * this.ambient[c])));
  }
}
