// The lit discontinuity mesh in three.js: one Mesh per receiver (world-space positions,
// vertex colours from the tone map), replaced one receiver at a time as deltas arrive, and an
// optional overlay of the mesh's edges coloured by vertex class (see discontinuityEdges).
import * as THREE from 'three';
import { CLASS_PENUMBRA, CLASS_UMBRA } from './mesh_binary.js';

const EDGE_COLOURS = {
  [CLASS_PENUMBRA]: new THREE.Color(0xff9020),
  [CLASS_UMBRA]: new THREE.Color(0x3060ff),
};

// The overlay: the mesh's triangle edges (each once) that touch a penumbra vertex or join two
// classes, coloured by the darker end (umbra blue over penumbra orange). Lit–lit and umbra–umbra
// edges (the triangulation inside fully lit or fully dark regions) are left out, so what remains
// is the penumbrae the mesh resolved, filled with their discontinuity edges, and the umbrae's borders.
export function discontinuityEdges(receiver) {
  const { positions, classes, indices } = receiver;
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

export class ReceiverLayer {
  constructor(parent) {
    this.group = new THREE.Group();
    this.group.name = 'receivers';
    this.edgeGroup = new THREE.Group();
    this.edgeGroup.name = 'edges';
    this.edgeGroup.visible = false;
    parent.add(this.group, this.edgeGroup);
    this.material = new THREE.MeshBasicMaterial({ vertexColors: true, side: THREE.FrontSide });
    this.edgeMaterial = new THREE.LineBasicMaterial({ vertexColors: true, depthTest: true });
    this.entries = new Map(); // key → {receiver, mesh, edges}
  }

  // Replaces the listed receivers and drops the removed ones (decoded binary mesh).
  apply(decoded, toneMap) {
    if (!decoded.delta) this.clear();
    for (const removed of decoded.removedReceivers) this.remove(removed.key);
    for (const receiver of decoded.receivers) {
      this.remove(receiver.key);
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute('position', new THREE.BufferAttribute(receiver.positions, 3));
      geometry.setAttribute('color', new THREE.BufferAttribute(toneMap.colours(receiver.object, receiver.irradiance), 3));
      geometry.setIndex(new THREE.BufferAttribute(receiver.indices, 1));
      geometry.computeBoundingSphere();
      const mesh = new THREE.Mesh(geometry, this.material);
      mesh.name = receiver.key;
      mesh.userData.objectId = receiver.object;
      this.group.add(mesh);
      const entry = { receiver, mesh, edges: null };
      if (this.edgeGroup.visible) this.addEdges(entry);
      this.entries.set(receiver.key, entry);
    }
  }

  addEdges(entry) {
    entry.edges = new THREE.LineSegments(discontinuityEdges(entry.receiver), this.edgeMaterial);
    this.edgeGroup.add(entry.edges);
  }

  setEdgesVisible(visible) {
    this.edgeGroup.visible = visible;
    if (visible) for (const entry of this.entries.values()) if (!entry.edges) this.addEdges(entry);
  }

  remove(key) {
    const entry = this.entries.get(key);
    if (!entry) return;
    this.group.remove(entry.mesh);
    entry.mesh.geometry.dispose();
    if (entry.edges) {
      this.edgeGroup.remove(entry.edges);
      entry.edges.geometry.dispose();
    }
    this.entries.delete(key);
  }

  clear() {
    for (const key of [...this.entries.keys()]) this.remove(key);
  }

  receiver(key) {
    const entry = this.entries.get(key);
    return entry ? entry.receiver : null;
  }

  counts() {
    let vertices = 0, triangles = 0;
    for (const { receiver } of this.entries.values()) {
      vertices += receiver.vertexCount;
      triangles += receiver.triangleCount;
    }
    return { receivers: this.entries.size, vertices, triangles };
  }
}
