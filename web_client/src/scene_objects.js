// Three.js stand-ins for a scene JSON's objects and lights: one pickable Group per object
// (local geometry under the object's transform, drawn in its ambient colour behind the lit
// receivers, so faces that receive no light still show) and the lights' emitting polygons, each
// under a holder at its centroid that the gizmo moves, turns and scales (set_light edits).
// Each object turns about the centre of its vertex bounds (its pivot: scene_transform.js), so an
// imported object, whose vertices are in world coordinates, gets its gizmo on itself rather than
// at the origin. The room's shell (`static` objects, and thin objects spanning most of the scene
// such as an imported file's walls and floor) is locked: not picked unless unlocked.
import * as THREE from 'three';
import { centroid } from './light_shape.js';
import { applyTransform } from './scene_transform.js';
import { volumeHolder } from './volume_stand_ins.js';

export const isVolumeJson = (object) => object.type === 'volume';

// Convex polygon faces → a triangle fan geometry (counter-clockwise = front, as in the format),
// with a colour per vertex and userData.faceRanges[f] = [first vertex, count] of face f.
function polygonsGeometry(vertices, faces) {
  const positions = [];
  const faceRanges = [];
  for (const face of faces) {
    const first = positions.length / 3;
    for (let k = 1; k + 1 < face.length; ++k)
      for (const index of [face[0], face[k], face[k + 1]]) positions.push(...vertices[index]);
    faceRanges.push([first, positions.length / 3 - first]);
  }
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.Float32BufferAttribute(positions, 3));
  geometry.setAttribute('color', new THREE.Float32BufferAttribute(new Float32Array(positions.length), 3));
  geometry.userData.faceRanges = faceRanges;
  geometry.computeVertexNormals();
  return geometry;
}

// Local vertex bounds' centre.
// A light's polygon is drawn in its colour: the radiance's hue at full brightness (linear RGB,
// its largest channel 1), white for a light of no power.
export function lightColour(radiance) {
  const peak = Math.max(...radiance);
  return peak > 0 ? radiance.map((x) => Math.max(0, x) / peak) : [1, 1, 1];
}

function pivotOf(vertices) {
  const box = new THREE.Box3();
  for (const p of vertices) box.expandByPoint(new THREE.Vector3(...p));
  return box.isEmpty() ? new THREE.Vector3() : box.getCenter(new THREE.Vector3());
}

// A wall, floor or ceiling: thinner than 1% of the scene's diagonal one way, and spanning at
// least half the scene the other two.
function isShell(objectBox, sceneBox) {
  const e = objectBox.getSize(new THREE.Vector3()).toArray();
  const s = sceneBox.getSize(new THREE.Vector3()).toArray();
  const diagonal = Math.hypot(...s);
  const thin = e.findIndex((x) => x < 0.01 * diagonal);
  return thin >= 0 && e.every((x, k) => k === thin || x >= 0.5 * s[k]);
}

export class SceneObjects {
  constructor(parent) {
    this.group = new THREE.Group();
    this.group.name = 'objects';
    this.lights = new THREE.Group();
    this.lights.name = 'lights';
    parent.add(this.group, this.lights);
    this.byId = new Map();
    this.json = new Map(); // object id → its scene JSON
    this.lightJson = new Map(); // light id → its scene JSON
    this.lightHolders = new Map(); // light id → its Group (at the centroid; the gizmo moves it)
    this.bounds = new THREE.Box3();
    this.unlocked = false; // whether the locked shell may be picked
    this.volumeInfo = new Map(); // volume id → GET scene's volumes[i] (grid box, value range)
  }

  isVolume(id) {
    const holder = this.byId.get(id);
    return !!holder && !!holder.userData.volume;
  }

  // The volumes' holders by id.
  volumes() {
    return [...this.byId].filter(([, holder]) => holder.userData.volume);
  }

  // Rebuilds every stand-in from scene JSON v1. toneMapFor(id): the object's ambient colour (its
  // faces' colour until faceColour(id, face) gives one: the lit mesh's mean, see ReceiverLayer).
  build(scene, toneMapFor, faceColour = () => null) {
    this.clear();
    for (const light of scene.lights) {
      // A holder at the light's centroid (the gizmo's place), its polygon drawn relative to it.
      const holder = new THREE.Group();
      holder.name = `light:${light.id}`;
      holder.userData.lightId = light.id;
      const mesh = new THREE.Mesh(new THREE.BufferGeometry(), new THREE.MeshBasicMaterial({ color: 0xffffff, side: THREE.DoubleSide }));
      mesh.userData.lightId = light.id;
      holder.add(mesh);
      this.lights.add(holder);
      this.lightHolders.set(light.id, holder);
      this.setLight(light.id, light);
    }
    for (const object of scene.objects) {
      if (isVolumeJson(object)) {
        this.addVolume(object);
        continue;
      }
      const holder = new THREE.Group();
      holder.name = object.id;
      const pivot = pivotOf(object.vertices);
      holder.userData = { objectId: object.id, static: !!object.static, pivot };
      const material = new THREE.MeshBasicMaterial({
        vertexColors: true, side: THREE.FrontSide, polygonOffset: true, polygonOffsetFactor: 2, polygonOffsetUnits: 2,
      });
      const mesh = new THREE.Mesh(polygonsGeometry(object.vertices, object.faces), material);
      mesh.userData.ambient = toneMapFor ? toneMapFor(object.id) : new THREE.Color(0x333333);
      object.faces.forEach((_, f) => this.paintFace(mesh, f, faceColour(object.id, f)));
      mesh.userData.objectId = object.id;
      mesh.position.copy(pivot).negate();
      holder.add(mesh);
      applyTransform(holder, object.transform);
      this.group.add(holder);
      this.byId.set(object.id, holder);
      this.json.set(object.id, object);
    }
    this.bounds = this.worldBounds(scene);
    for (const holder of this.byId.values()) {
      if (holder.userData.volume) continue;
      holder.userData.locked = holder.userData.static || isShell(new THREE.Box3().setFromObject(holder.children[0]), this.bounds);
    }
    if (this.onBuilt) this.onBuilt(scene); // the glossy layer (glossy_layer.js)
  }

  // A volume's stand-in (volume_stand_ins.js); skipped when the server gave no info for it.
  addVolume(object) {
    const info = this.volumeInfo.get(object.id);
    if (!info) return;
    const holder = volumeHolder(object, info);
    applyTransform(holder, object.transform);
    this.group.add(holder);
    this.byId.set(object.id, holder);
    this.json.set(object.id, object);
  }

  // Shows or hides an object's selection outline (made on first use: most objects are never selected).
  setOutlined(id, on) {
    const holder = this.byId.get(id);
    if (!holder) return;
    let outline = holder.getObjectByName('outline');
    if (!outline && !on) return;
    if (!outline) {
      const mesh = holder.children[0];
      outline = new THREE.LineSegments(new THREE.EdgesGeometry(mesh.geometry), new THREE.LineBasicMaterial({ color: 0xe0a030 }));
      outline.name = 'outline';
      outline.position.copy(mesh.position);
      holder.add(outline);
    }
    outline.visible = on;
  }

  // New colours for every stand-in (after the tone map's calibration), arguments as build's.
  recolour(toneMapFor, faceColour) {
    for (const [id, holder] of this.byId) {
      if (holder.userData.volume) continue;
      const mesh = holder.children[0];
      mesh.userData.ambient = toneMapFor(id);
      mesh.geometry.userData.faceRanges.forEach((_, f) => this.paintFace(mesh, f, faceColour(id, f)));
    }
  }

  // A face's stand-in colour: `rgb` ([r, g, b] linear), or the object's ambient colour when null.
  paintFace(mesh, face, rgb) {
    const range = mesh.geometry.userData.faceRanges[face];
    if (!range) return;
    const colour = mesh.geometry.attributes.color;
    const c = rgb || mesh.userData.ambient.toArray();
    for (let v = range[0]; v < range[0] + range[1]; ++v) colour.setXYZ(v, c[0], c[1], c[2]);
    colour.needsUpdate = true;
  }

  setFaceColour(objectId, face, rgb) {
    const holder = this.byId.get(objectId);
    if (holder) this.paintFace(holder.children[0], face, rgb);
  }

  // The object's world bounds as drawn now.
  objectBounds(id) {
    const holder = this.byId.get(id);
    return holder ? new THREE.Box3().setFromObject(holder.children[0]) : null;
  }

  // Bounds of lights and world-space object vertices (core's Scene::bounds).
  worldBounds(scene) {
    const box = new THREE.Box3();
    for (const light of scene.lights) for (const p of light.polygon) box.expandByPoint(new THREE.Vector3(...p));
    const v = new THREE.Vector3();
    for (const object of scene.objects) {
      if (isVolumeJson(object)) continue; // as core's bounds: volumes are not in them
      const mesh = this.byId.get(object.id).children[0];
      mesh.updateMatrixWorld(true);
      for (const p of object.vertices) box.expandByPoint(v.fromArray(p).applyMatrix4(mesh.matrixWorld));
    }
    return box;
  }

  // Moves stand-ins to a scene's transforms (another client's edits), except `skipId`.
  syncTransforms(scene, skipId) {
    for (const object of scene.objects) {
      const holder = this.byId.get(object.id);
      if (holder && object.id !== skipId) applyTransform(holder, object.transform);
      if (holder && isVolumeJson(object)) this.json.set(object.id, object);
    }
  }

  sameObjects(scene) {
    return scene.objects.length === this.byId.size && scene.objects.every((o) => this.byId.has(o.id))
      && scene.lights.length === this.lightHolders.size && scene.lights.every((l) => this.lightHolders.has(l.id));
  }

  // The Group the gizmo moves for a selection id: an object's holder, or a light's ("light:ID").
  holderOf(id) {
    if (!id) return null;
    return id.startsWith('light:') ? this.lightHolders.get(id.slice(6)) || null : this.byId.get(id) || null;
  }

  // Takes light `id` to `light` ({polygon, radiance}, as in scene JSON): its holder back at
  // the new centroid, unturned and unscaled, and its polygon drawn relative to it.
  setLight(id, light) {
    const holder = this.lightHolders.get(id);
    if (!holder) return;
    const c = centroid(light.polygon);
    const local = light.polygon.map((p) => p.map((x, k) => x - c[k]));
    const mesh = holder.children[0];
    mesh.geometry.dispose();
    mesh.geometry = polygonsGeometry(local, [local.map((_, i) => i)]);
    holder.position.set(...c);
    holder.rotation.set(0, 0, 0);
    holder.scale.set(1, 1, 1);
    holder.userData.local = local;
    holder.updateMatrixWorld(true);
    mesh.material.color.setRGB(...lightColour(light.radiance));
    this.lightJson.set(id, { ...(this.lightJson.get(id) || { id }), polygon: light.polygon, radiance: light.radiance });
    if (this.onLight) this.onLight(id, this.lightJson.get(id));
  }

  // Light `id`'s polygon as its holder places it now (during a gizmo drag: moved, turned, scaled).
  lightPolygon(id) {
    const holder = this.lightHolders.get(id);
    holder.updateMatrixWorld(true);
    const v = new THREE.Vector3();
    return holder.userData.local.map((p) => v.fromArray(p).applyMatrix4(holder.matrixWorld).toArray());
  }

  // Lights to a scene's (another client's edits), except `skipId`.
  syncLights(scene, skipId) {
    for (const light of scene.lights) {
      const known = this.lightJson.get(light.id);
      if (light.id !== skipId && known && JSON.stringify([known.polygon, known.radiance]) !== JSON.stringify([light.polygon, light.radiance]))
        this.setLight(light.id, light);
    }
  }

  // The meshes a click may pick: the lights, and the objects not locked (all when unlocked).
  pickable() {
    const meshes = [...this.lightHolders.values()].map((holder) => holder.children[0]);
    for (const holder of this.byId.values()) if (this.unlocked || !holder.userData.locked) meshes.push(holder.children[0]);
    return meshes;
  }

  clear() {
    for (const group of [this.group, this.lights]) {
      group.traverse((o) => { if (o.geometry) o.geometry.dispose(); if (o.material) o.material.dispose(); });
      group.clear();
    }
    this.byId.clear();
    this.json.clear();
    this.lightJson.clear();
    this.lightHolders.clear();
  }
}
