// The lit discontinuity mesh in three.js: parts (one display chunk of one receiver: world-space
// positions, vertex colours from the tone map) replaced one at a time as deltas arrive (or, for a
// part whose irradiance alone changed, recoloured in place in its batch's colour buffer), drawn in
// batches (one Mesh for the parts of one object with the same chunk index, e.g. a room's floor and
// wall blocks there), and an optional overlay of the mesh's edges coloured by vertex class
// (see discontinuityEdges). A receiver is read back as one merged view of its parts.
import * as THREE from 'three';
import { CLASS_LIT, CLASS_PENUMBRA, CLASS_UMBRA } from './mesh_binary.js';

const EDGE_COLOURS = {
  [CLASS_PENUMBRA]: new THREE.Color(0xff9020),
  [CLASS_UMBRA]: new THREE.Color(0x3060ff),
};

// The overlay: the mesh's triangle edges (each once) that touch a penumbra vertex or join two
// classes, coloured by the darker end (umbra blue over penumbra orange). Lit–lit and umbra–umbra
// edges (the triangulation inside fully lit or fully dark regions) and umbra–lit ones (the light's
// plane, see below) are left out, so what remains
// is the penumbrae the mesh resolved, filled with their discontinuity edges, and the umbrae's borders.
export function discontinuityEdges(part) {
  const { positions, classes, indices } = part;
  const seen = new Set();
  const points = [];
  const colours = [];
  const n = classes.length;
  for (let t = 0; t < indices.length; t += 3) {
    for (let k = 0; k < 3; ++k) {
      const a = indices[t + k];
      const b = indices[t + (k + 1) % 3];
      const key = a < b ? a * n + b : b * n + a;
      if (seen.has(key)) continue;
      seen.add(key);
      const cls = Math.max(classes[a], classes[b]);
      if (classes[a] === classes[b] && classes[a] !== CLASS_PENUMBRA) continue;
      // Umbra straight to lit, with no penumbra between: not a shadow's edge but the light's
      // plane (above it nothing is lit), whose thin strip's triangulation drew a zig-zag band.
      if (cls === CLASS_UMBRA && Math.min(classes[a], classes[b]) === CLASS_LIT) continue;
      const colour = EDGE_COLOURS[Math.min(cls, CLASS_UMBRA)];
      for (const v of [a, b]) {
        points.push(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]);
        colours.push(colour.r, colour.g, colour.b);
      }
    }
  }
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.Float32BufferAttribute(points, 3));
  geometry.setAttribute('color', new THREE.Float32BufferAttribute(colours, 3));
  return geometry;
}

// One receiver as a single mesh: its parts' arrays concatenated (in chunk order), indices offset;
// sceneVersion is the newest of its parts'. Border vertices repeat, as they do in the parts.
function mergeParts(parts) {
  parts.sort((a, b) => a.chunk[1] - b.chunk[1] || a.chunk[0] - b.chunk[0]);
  let v = 0, t = 0;
  for (const p of parts) { v += p.vertexCount; t += p.triangleCount; }
  const merged = {
    object: parts[0].object, face: parts[0].face, key: parts[0].receiverKey, normal: parts[0].normal,
    vertexCount: v, triangleCount: t, parts: parts.length, sceneVersion: Math.max(...parts.map((p) => p.sceneVersion)),
    positions: new Float32Array(3 * v), irradiance: new Float32Array(3 * v), classes: new Uint8Array(v), indices: new Uint32Array(3 * t),
  };
  let vertexBase = 0, indexBase = 0;
  for (const p of parts) {
    merged.positions.set(p.positions, 3 * vertexBase);
    merged.irradiance.set(p.irradiance, 3 * vertexBase);
    merged.classes.set(p.classes, vertexBase);
    for (let i = 0; i < p.indices.length; ++i) merged.indices[indexBase + i] = p.indices[i] + vertexBase;
    vertexBase += p.vertexCount;
    indexBase += p.indices.length;
  }
  return merged;
}

// A batch: one object's parts with one chunk index. A software GL pays per draw call, and a
// batch is one (150 cubes: 715 parts in 468 batches); a changed part rebuilds only its batch.
const batchKey = (part) => `${part.object}#${part.chunk[0]},${part.chunk[1]}`;

// One Mesh of `entries` ({part, colours}): positions, colours and indices concatenated.
function batchMesh(entries, material) {
  let v = 0, t = 0;
  for (const { part } of entries) { v += part.vertexCount; t += part.indices.length; }
  const positions = new Float32Array(3 * v), colours = new Float32Array(3 * v), indices = new Uint32Array(t);
  let vertexBase = 0, indexBase = 0;
  const offsets = new Map(); // part key → its first vertex in the batch
  for (const { part, colours: c } of entries) {
    offsets.set(part.key, vertexBase);
    positions.set(part.positions, 3 * vertexBase);
    colours.set(c, 3 * vertexBase);
    for (let i = 0; i < part.indices.length; ++i) indices[indexBase + i] = part.indices[i] + vertexBase;
    vertexBase += part.vertexCount;
    indexBase += part.indices.length;
  }
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  geometry.setAttribute('color', new THREE.BufferAttribute(colours, 3));
  geometry.setIndex(new THREE.BufferAttribute(indices, 1));
  geometry.computeBoundingSphere();
  const mesh = new THREE.Mesh(geometry, material);
  mesh.userData.offsets = offsets;
  return mesh;
}

// A part's display colours from the tone map, with their sum ([r, g, b]): its receiver's mean
// colour is then a sum over its parts, not over their vertices (the floor's 30 000) each delta.
function colourEntry(entry, toneMap, indirect) {
  const { part } = entry;
  const c = toneMap.colours(part.object, part.irradiance, indirect);
  const sum = [0, 0, 0];
  for (let i = 0; i < c.length; i += 3) { sum[0] += c[i]; sum[1] += c[i + 1]; sum[2] += c[i + 2]; }
  entry.colours = c;
  entry.colourSum = sum;
  return entry;
}

export class ReceiverLayer {
  constructor(parent) {
    this.group = new THREE.Group();
    this.group.name = 'receivers';
    this.edgeGroup = new THREE.Group();
    this.edgeGroup.name = 'edges';
    this.edgeGroup.visible = false;
    parent.add(this.group, this.edgeGroup);
    this.material = new THREE.MeshBasicMaterial({ vertexColors: true, side: THREE.FrontSide });
    this.objectMaterials = new Map(); // object id → its batches' material instead (glass: glossy_layer.js)
    this.edgeMaterial = new THREE.LineBasicMaterial({ vertexColors: true, depthTest: true });
    this.entries = new Map(); // part key → {part, colours, colourSum, edges}
    this.batches = new Map(); // batch key → {keys: Set of part keys, mesh}
    this.stale = new Set(); // batch keys whose mesh no longer matches their parts
    this.byReceiver = new Map(); // receiver key → Set of part keys (never empty)
    this.merged = new Map(); // receiver key → merged view, until one of its parts changes
    this.indirect = null; // part key → {indirect, vertexCount, version} baked (baked_indirect.js), or null
    this.vertices = 0;
    this.triangles = 0;
  }

  // Replaces the listed parts, recolours the value parts and drops the removed ones (decoded
  // binary mesh); a whole (non-delta) mesh replaces everything.
  apply(decoded, toneMap) {
    if (!decoded.delta) this.clear();
    const valueParts = decoded.valueParts || [];
    const touched = new Set([...decoded.removedParts, ...decoded.parts, ...valueParts].map((p) => p.receiverKey).filter(Boolean));
    for (const removed of decoded.removedParts) this.remove(removed.key);
    for (const part of decoded.parts) {
      this.remove(part.key);
      const entry = colourEntry({ part, edges: null }, toneMap, this.indirectOf(part));
      if (this.edgeGroup.visible) this.addEdges(entry);
      this.entries.set(part.key, entry);
      const batch = batchKey(part);
      if (!this.batches.has(batch)) this.batches.set(batch, { keys: new Set(), mesh: null });
      this.batches.get(batch).keys.add(part.key);
      this.stale.add(batch);
      if (!this.byReceiver.has(part.receiverKey)) this.byReceiver.set(part.receiverKey, new Set());
      this.byReceiver.get(part.receiverKey).add(part.key);
      this.merged.delete(part.receiverKey);
      this.vertices += part.vertexCount;
      this.triangles += part.triangleCount;
    }
    for (const values of valueParts) this.recolour(values, toneMap);
    this.rebuildStale();
    if (this.onColours) this.onColours(decoded.delta ? touched : null);
  }

  // A held part's new irradiance (a value part: same triangulation): its colours written into its
  // batch's colour buffer in place, unless the batch is rebuilt anyway.
  recolour(values, toneMap) {
    const entry = this.entries.get(values.key);
    if (!entry || entry.part.vertexCount !== values.vertexCount)
      throw new Error(`binary mesh: values for part ${values.key} (${values.vertexCount} vertices), which the page does not hold`);
    entry.part = { ...entry.part, irradiance: values.irradiance, sceneVersion: values.sceneVersion };
    colourEntry(entry, toneMap, this.indirectOf(entry.part));
    this.merged.delete(entry.part.receiverKey);
    const key = batchKey(entry.part);
    const mesh = this.batches.get(key).mesh;
    if (this.stale.has(key) || !mesh) return;
    const colour = mesh.geometry.getAttribute('color');
    colour.array.set(entry.colours, 3 * mesh.userData.offsets.get(values.key));
    colour.needsUpdate = true;
  }

  // The baked indirect light of a part, when the bake is of this part's data (a part changed since
  // shows the ambient term until the next bake arrives).
  indirectOf(part) {
    const baked = this.indirect && this.indirect.get(part.key);
    return baked && baked.vertexCount === part.vertexCount && part.sceneVersion <= baked.version ? baked.indirect : null;
  }

  // New baked indirect light (null: none), every part recoloured with it.
  setIndirect(indirect, toneMap) {
    this.indirect = indirect;
    this.recolourAll(toneMap);
  }

  // Every part's colours again (new albedos or exposure: the irradiance is as held).
  recolourAll(toneMap) {
    for (const entry of this.entries.values()) {
      colourEntry(entry, toneMap, this.indirectOf(entry.part));
      this.stale.add(batchKey(entry.part));
    }
    this.rebuildStale();
    if (this.onColours) this.onColours(null);
  }

  // The mean display colour of a receiver's vertices ([r, g, b] linear), or null when none is held:
  // the colour of its stand-in behind the lit mesh, so that where the mesh leaves a one-pixel crack
  // (parts and faces meeting at vertices that lie on the other's edges) the face's own tone shows
  // rather than a dark speck.
  // Every held receiver's mean colour (as meanColour), in one pass: receiver key → [r, g, b].
  meanColours() {
    const sums = new Map();
    for (const { part, colours: c, colourSum } of this.entries.values()) {
      let s = sums.get(part.receiverKey);
      if (!s) sums.set(part.receiverKey, (s = [0, 0, 0, 0]));
      s[0] += colourSum[0]; s[1] += colourSum[1]; s[2] += colourSum[2];
      s[3] += c.length / 3;
    }
    const means = new Map();
    for (const [key, s] of sums) if (s[3]) means.set(key, [s[0] / s[3], s[1] / s[3], s[2] / s[3]]);
    return means;
  }

  meanColour(key) {
    const keys = this.byReceiver.get(key);
    if (!keys) return null;
    const sum = [0, 0, 0];
    let n = 0;
    for (const k of keys) {
      const { colours: c, colourSum } = this.entries.get(k);
      sum[0] += colourSum[0]; sum[1] += colourSum[1]; sum[2] += colourSum[2];
      n += c.length / 3;
    }
    return n ? sum.map((x) => x / n) : null;
  }

  // A new Mesh for each batch whose parts changed; none for a batch left empty.
  rebuildStale() {
    for (const key of this.stale) {
      const batch = this.batches.get(key);
      if (batch.mesh) {
        this.group.remove(batch.mesh);
        batch.mesh.geometry.dispose();
        batch.mesh = null;
      }
      if (batch.keys.size === 0) {
        this.batches.delete(key);
        continue;
      }
      const entries = [...batch.keys].map((k) => this.entries.get(k));
      batch.mesh = batchMesh(entries, this.materialOf(entries[0].part.object));
      batch.mesh.name = key;
      this.group.add(batch.mesh);
    }
    this.stale.clear();
  }

  materialOf(objectId) {
    return this.objectMaterials.get(objectId) || this.material;
  }

  // Other materials for some objects' batches (object id → material; the rest keep the DM's own).
  setObjectMaterials(materials) {
    this.objectMaterials = materials;
    for (const batch of this.batches.values()) {
      if (!batch.mesh || !batch.keys.size) continue;
      batch.mesh.material = this.materialOf(this.entries.get(batch.keys.values().next().value).part.object);
    }
  }

  addEdges(entry) {
    entry.edges = new THREE.LineSegments(discontinuityEdges(entry.part), this.edgeMaterial);
    this.edgeGroup.add(entry.edges);
  }

  setEdgesVisible(visible) {
    this.edgeGroup.visible = visible;
    if (visible) for (const entry of this.entries.values()) if (!entry.edges) this.addEdges(entry);
  }

  remove(key) {
    const entry = this.entries.get(key);
    if (!entry) return;
    const batch = batchKey(entry.part);
    this.batches.get(batch).keys.delete(key);
    this.stale.add(batch);
    if (entry.edges) {
      this.edgeGroup.remove(entry.edges);
      entry.edges.geometry.dispose();
    }
    this.entries.delete(key);
    const { receiverKey, vertexCount, triangleCount } = entry.part;
    const keys = this.byReceiver.get(receiverKey);
    keys.delete(key);
    if (keys.size === 0) this.byReceiver.delete(receiverKey);
    this.merged.delete(receiverKey);
    this.vertices -= vertexCount;
    this.triangles -= triangleCount;
  }

  clear() {
    for (const key of [...this.entries.keys()]) this.remove(key);
    this.rebuildStale();
  }

  // Every part held (for the tone map's calibration).
  parts() {
    return [...this.entries.values()].map((entry) => entry.part);
  }

  // The receiver (object/face key) as one merged mesh, or null when no part of it is held.
  receiver(key) {
    const keys = this.byReceiver.get(key);
    if (!keys) return null;
    if (!this.merged.has(key)) this.merged.set(key, mergeParts([...keys].map((k) => this.entries.get(k).part)));
    return this.merged.get(key);
  }

  counts() {
    return { receivers: this.byReceiver.size, parts: this.entries.size, batches: this.batches.size, vertices: this.vertices, triangles: this.triangles };
  }
}
