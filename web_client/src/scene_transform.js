// Scene JSON transforms ({translate, rotate_deg, scale}: v' = T + R·(S·v), R = Rx·Ry·Rz)
// to and from three.js Object3D, whose 'XYZ' Euler order and T·R·S matrix are the same.
import * as THREE from 'three';

const DEG = Math.PI / 180;

export function applyTransform(object3d, transform = {}) {
  const t = transform.translate || [0, 0, 0];
  const r = transform.rotate_deg || [0, 0, 0];
  const s = transform.scale || [1, 1, 1];
  object3d.position.set(t[0], t[1], t[2]);
  object3d.rotation.set(r[0] * DEG, r[1] * DEG, r[2] * DEG, 'XYZ');
  object3d.scale.set(s[0], s[1], s[2]);
  object3d.updateMatrixWorld(true);
}

export function transformOf(object3d) {
  const e = new THREE.Euler().setFromQuaternion(object3d.quaternion, 'XYZ');
  return {
    translate: object3d.position.toArray(),
    rotate_deg: [e.x / DEG, e.y / DEG, e.z / DEG],
    scale: object3d.scale.toArray(),
  };
}

export function sameTransform(a, b) {
  return JSON.stringify(a) === JSON.stringify(b);
}
