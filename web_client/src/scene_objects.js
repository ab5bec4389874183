// Three.js stand-ins for a scene JSON's objects and lights: one pickable Group per object
// (local geometry under the object's transform, drawn in its ambient colour behind the lit
// receivers, so faces that receive no light still show) and the lights' emitting polygons.
import * as THREE from 'three';
import { applyTransform } from './scene_transform.js';

// Convex polygon faces → a triangle fan geometry (counter-clockwise = front, as in the format).
function polygonsGeometry(vertices, faces) {
  const positions = [];
  for (const face of faces)
    for (let k = 1; k + 1 < face.length; ++k)
      for (const index of [face[0], face[k], face[k + 1]]) positions.push(...vertices[index]);
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.Float32BufferAttribute(positions, 3));
  geometry.computeVertexNormals();
  return geometry;
}

export class SceneObjects {
  constructor(parent) {
    this.group = new THREE.Group();
    this.group.name = 'objects';
    this.lights = new THREE.Group();
    this.lights.name = 'lights';
    parent.add(this.group, this.lights);
    this.byId = new Map();
    this.bounds = new THREE.Box3();
  }

  // Rebuilds every stand-in from scene JSON v1.
  build(scene, toneMapFor) {
    this.clear();
    for (const light of scene.lights) {
      const geometry = polygonsGeometry(light.polygon, [light.polygon.map((_, i) => i)]);
      const mesh = new THREE.Mesh(geometry, new THREE.MeshBasicMaterial({ color: 0xffffff, side: THREE.FrontSide }));
      mesh.name = `light:${light.id}`;
      this.lights.add(mesh);
    }
    for (const object of scene.objects) {
      const holder = new THREE.Group();
      holder.name = object.id;
      holder.userData = { objectId: object.id, static: !!object.static };
      const material = new THREE.MeshBasicMaterial({
        color: toneMapFor ? toneMapFor(object.id) : 0x333333,
        side: THREE.FrontSide, polygonOffset: true, polygonOffsetFactor: 2, polygonOffsetUnits: 2,
      });
      const mesh = new THREE.Mesh(polygonsGeometry(object.vertices, object.faces), material);
      mesh.userData.objectId = object.id;
      holder.add(mesh);
      const outline = new THREE.LineSegments(new THREE.EdgesGeometry(mesh.geometry),
        new THREE.LineBasicMaterial({ color: 0xe0a030 }));
      outline.visible = false;
      outline.name = 'outline';
      holder.add(outline);
      applyTransform(holder, object.transform);
      this.group.add(holder);
      this.byId.set(object.id, holder);
    }
    this.bounds = this.worldBounds(scene);
  }

  // Bounds of lights and world-space object vertices (core's Scene::bounds).
  worldBounds(scene) {
    const box = new THREE.Box3();
    for (const light of scene.lights) for (const p of light.polygon) box.expandByPoint(new THREE.Vector3(...p));
    const v = new THREE.Vector3();
    for (const object of scene.objects) {
      const holder = this.byId.get(object.id);
      for (const p of object.vertices) box.expandByPoint(v.fromArray(p).applyMatrix4(holder.matrixWorld));
    }
    return box;
  }

  // Moves stand-ins to a scene's transforms (another client's edits), except `skipId`.
  syncTransforms(scene, skipId) {
    for (const object of scene.objects) {
      const holder = this.byId.get(object.id);
      if (holder && object.id !== skipId) applyTransform(holder, object.transform);
    }
  }

  sameObjects(scene) {
    return scene.objects.length === this.byId.size && scene.objects.every((o) => this.byId.has(o.id));
  }

  // The movable objects' meshes, for picking.
  pickable() {
    const meshes = [];
    for (const holder of this.byId.values()) if (!holder.userData.static) meshes.push(holder.children[0]);
    return meshes;
  }

  clear() {
    for (const group of [this.group, this.lights]) {
      group.traverse((o) => { if (o.geometry) o.geometry.dispose(); if (o.material) o.material.dispose(); });
      group.clear();
    }
    this.byId.clear();
  }
}
