// The glossy part of microfacet materials (README "The page"): for each object whose material
// physicalParameters maps, a MeshPhysicalMaterial copy of its stand-in, lit by RectAreaLights that
// match the scene's lights, drawn over the DM's vertex colours. Conductors add their specular
// reflection to the DM colours (additive blending); glass is clear, as in the server's render (its
// albedo colours only the irradiance view): its DM colours are not drawn, and it refracts what is
// behind it (three.js's transmission pass) through its thickness. The overlays and lights are
// children of the stand-ins' holders, so drags move them. Rebuilt with the stand-ins.
import * as THREE from 'three';
import { physicalParameters } from './physical_materials.js';

let areaLightsReady = null; // the LTC tables, loaded once and only for scenes that need them

function loadAreaLights() {
  areaLightsReady ||= import('three/addons/lights/RectAreaLightUniformsLib.js').then(({ RectAreaLightUniformsLib }) => RectAreaLightUniformsLib.init());
  return areaLightsReady;
}

// Per-vertex tangents along each face's first edge (core/render/microfacet_shading's frame), so
// an anisotropic α stretches the lobe along the same direction as the server's render.
function addFaceTangents(geometry, vertices, faces) {
  if (geometry.attributes.tangent) return;
  const tangents = new Float32Array(4 * geometry.attributes.position.count);
  geometry.userData.faceRanges.forEach(([first, count], f) => {
    const [a, b] = [vertices[faces[f][0]], vertices[faces[f][1]]];
    const t = new THREE.Vector3(b[0] - a[0], b[1] - a[1], b[2] - a[2]).normalize();
    for (let v = first; v < first + count; ++v) tangents.set([t.x, t.y, t.z, 1], 4 * v);
  });
  geometry.setAttribute('tangent', new THREE.BufferAttribute(tangents, 4));
}

// The distance a view ray travels through a glass stand-in, in its local units (three.js scales it
// by the holder's): the smallest side of its bounding box, so a pane is seen through its thin side.
function thicknessOf(geometry) {
  if (!geometry.boundingBox) geometry.computeBoundingBox();
  const size = geometry.boundingBox.getSize(new THREE.Vector3());
  return Math.min(size.x, size.y, size.z);
}

function physicalMaterial(p, thickness) {
  const glass = p.transmission > 0;
  const material = new THREE.MeshPhysicalMaterial({
    color: new THREE.Color(...p.color), metalness: p.metalness, roughness: p.roughness, ior: p.ior,
    transmission: p.transmission, thickness: glass ? thickness : 0, anisotropy: p.anisotropy, anisotropyRotation: p.anisotropyRotation,
    side: THREE.FrontSide, depthWrite: false, polygonOffset: true, polygonOffsetFactor: -1, polygonOffsetUnits: -1,
  });
  if (!glass) Object.assign(material, { blending: THREE.AdditiveBlending, transparent: true });
  material.userData.parameters = p;
  return material;
}

export class GlossyLayer {
  constructor(objects, receivers) {
    Object.assign(this, { objects, receivers });
    this.overlays = new Map(); // object id → Mesh with the physical material
    this.areaLights = new Map(); // light id → RectAreaLight
    this.exposure = 1;
    this.builds = 0;
    this.building = null; // the build under way (its promise), or null
  }

  // After SceneObjects.build(scene): overlays for the glossy objects, area lights for the lights.
  // Returns at once; resolves once they are in place (after the LTC tables load, on first use).
  build(scene) {
    const task = this.rebuild(scene).finally(() => { if (this.building === task) this.building = null; });
    this.building = task;
    return task;
  }

  // Resolves once no build is under way (App.idle: what the view shows follows the scene).
  async idle() {
    while (this.building) await this.building.catch(() => {});
  }

  async rebuild(scene) {
    const build = ++this.builds;
    this.clear();
    const materials = scene.materials || {};
    const glossy = scene.objects.filter((o) => o.type !== 'volume').map((o) => [o, physicalParameters(materials[o.material])]).filter(([, p]) => p);
    this.receivers.setObjectMaterials(new Map());
    if (!glossy.length) return;
    await loadAreaLights();
    if (build !== this.builds) return; // built again meanwhile
    const hiddenDm = new THREE.MeshBasicMaterial({ visible: false });
    const dmMaterials = new Map();
    for (const [object, parameters] of glossy) {
      const holder = this.objects.byId.get(object.id);
      if (!holder) continue;
      const standIn = holder.children[0];
      addFaceTangents(standIn.geometry, object.vertices, object.faces);
      const overlay = new THREE.Mesh(standIn.geometry, physicalMaterial(parameters, thicknessOf(standIn.geometry)));
      overlay.name = 'glossy';
      overlay.position.copy(standIn.position);
      overlay.raycast = () => {}; // picking hits the stand-in
      holder.add(overlay);
      this.overlays.set(object.id, overlay);
      if (parameters.transmission > 0) {
        // Neither its stand-in nor its DM colours: the transmission pass would see them, not what is behind.
        standIn.material.visible = false;
        dmMaterials.set(object.id, hiddenDm);
      }
    }
    this.receivers.setObjectMaterials(dmMaterials);
    for (const light of scene.lights) this.setLight(light.id, light);
  }

  // A RectAreaLight in light `id`'s holder, matching its polygon (local to the holder) and radiance:
  // width along the first edge, the polygon's area, facing its emitting front.
  setLight(id, light) {
    const holder = this.objects.lightHolders.get(id);
    if (!this.overlays.size || !holder || !holder.userData.local) return;
    let area = this.areaLights.get(id);
    if (!area || area.parent !== holder) {
      area = new THREE.RectAreaLight(0xffffff, 1, 1, 1);
      area.name = 'area-light';
      holder.add(area);
      this.areaLights.set(id, area);
    }
    const p = holder.userData.local.map((q) => new THREE.Vector3(...q));
    const x = p[1].clone().sub(p[0]);
    const normal = x.clone().cross(p[2].clone().sub(p[0])).normalize();
    let doubled = 0;
    for (let k = 1; k + 1 < p.length; ++k) doubled += p[k].clone().sub(p[0]).cross(p[k + 1].clone().sub(p[0])).dot(normal);
    area.width = x.length();
    area.height = doubled / 2 / area.width;
    const z = normal.clone().negate(); // a RectAreaLight shines along its local -z
    x.normalize();
    area.quaternion.setFromRotationMatrix(new THREE.Matrix4().makeBasis(x, z.clone().cross(x), z));
    area.position.set(0, 0, 0);
    area.userData.radiance = light.radiance;
    this.applyIntensity(area);
  }

  // The tone map's exposure (ToneMap.exposure), so highlights share the DM colours' scale.
  setExposure(exposure) {
    this.exposure = exposure;
    for (const area of this.areaLights.values()) this.applyIntensity(area);
  }

  applyIntensity(area) {
    const L = area.userData.radiance || [0, 0, 0];
    const peak = Math.max(...L);
    area.color.setRGB(...(peak > 0 ? L.map((c) => c / peak) : [0, 0, 0]), THREE.LinearSRGBColorSpace);
    area.intensity = this.exposure * peak;
  }

  // What the test hook reports: each overlay's parameters as three.js holds them.
  describe() {
    return [...this.overlays].map(([id, mesh]) => {
      const m = mesh.material;
      return { id, kind: m.type, type: m.userData.parameters.type, metalness: m.metalness, roughness: m.roughness,
        transmission: m.transmission, ior: m.ior, thickness: m.thickness, anisotropy: m.anisotropy, color: m.color.toArray(),
        additive: m.blending === THREE.AdditiveBlending, parent: mesh.parent ? mesh.parent.name : null };
    }).concat([...this.areaLights].map(([id, a]) => ({ id, kind: a.type, width: a.width, height: a.height, intensity: a.intensity })));
  }

  clear() {
    for (const overlay of this.overlays.values()) {
      overlay.material.dispose();
      if (overlay.parent) overlay.parent.remove(overlay);
    }
    for (const area of this.areaLights.values()) if (area.parent) area.parent.remove(area);
    this.overlays.clear();
    this.areaLights.clear();
  }
}
