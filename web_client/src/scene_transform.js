// Scene JSON transforms ({translate, rotate_deg, scale}: v' = T + R·(S·v), R = Rx·Ry·Rz)
// to and from three.js Object3D, whose 'XYZ' Euler order and T·R·S matrix are the same. A holder
// may have a pivot (userData.pivot, a local point: the centre of the object's vertex bounds), so
// that the gizmo sits and turns there: the holder is then placed at T + R·S·pivot and its
// children are offset by -pivot, which draws exactly the same world geometry. A holder keeps the
// transform last applied to it: read back while the holder stands where it put it, that transform
// is returned as it was (degrees through a quaternion and back are not the same numbers), so an
// edit never sends a value nobody changed.
import * as THREE from 'three';

const DEG = Math.PI / 180;

// R·S·pivot of a holder as it stands (zero without a pivot).
function pivotOffset(object3d) {
  const pivot = object3d.userData && object3d.userData.pivot;
  if (!pivot) return new THREE.Vector3();
  return pivot.clone().multiply(object3d.scale).applyQuaternion(object3d.quaternion);
}

export function applyTransform(object3d, transform = {}) {
  const t = transform.translate || [0, 0, 0];
  const r = transform.rotate_deg || [0, 0, 0];
  const s = transform.scale || [1, 1, 1];
  object3d.rotation.set(r[0] * DEG, r[1] * DEG, r[2] * DEG, 'XYZ');
  object3d.scale.set(s[0], s[1], s[2]);
  object3d.position.set(t[0], t[1], t[2]).add(pivotOffset(object3d));
  object3d.updateMatrixWorld(true);
  object3d.userData.applied = { transform: { translate: [...t], rotate_deg: [...r], scale: [...s] },
    position: object3d.position.clone(), quaternion: object3d.quaternion.clone(), scale: object3d.scale.clone() };
}

// Whether the holder stands exactly where applyTransform last put it (no drag moved it since).
function standsAsApplied(object3d) {
  const applied = object3d.userData && object3d.userData.applied;
  return !!applied && applied.position.equals(object3d.position) && applied.quaternion.equals(object3d.quaternion)
    && applied.scale.equals(object3d.scale);
}

export function transformOf(object3d) {
  if (standsAsApplied(object3d)) {
    const { translate, rotate_deg: rotate, scale } = object3d.userData.applied.transform;
    return { translate: [...translate], rotate_deg: [...rotate], scale: [...scale] };
  }
  const e = new THREE.Euler().setFromQuaternion(object3d.quaternion, 'XYZ');
  return {
    translate: object3d.position.clone().sub(pivotOffset(object3d)).toArray(),
    rotate_deg: [e.x / DEG, e.y / DEG, e.z / DEG],
    scale: object3d.scale.toArray(),
  };
}

export function sameTransform(a, b) {
  return JSON.stringify(a) === JSON.stringify(b);
}
