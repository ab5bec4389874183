// The camera of a scene that has none (an imported file): the bounds framed as core/render's
// default camera frames them (backed off until the bounding sphere fits a 45° view, at the
// elevation of its (0.6, 0.45, 1) direction), but from the first of eight sides around the scene
// from which no wall or floor (a locked object: SceneObjects) is seen from behind on the way to the
// centre, so an open box (a Cornell box) is seen through its open side, not through its back wall.
// A closed room is seen from inside, from near the least hidden side.
import * as THREE from 'three';

// Faces of locked objects crossed by the segment eye → target with the eye behind them.
export function blockingShellFaces(objects, eye, target) {
  let blocking = 0;
  for (const [id, holder] of objects.byId) {
    if (!holder.userData.locked) continue;
    const object = objects.json.get(id);
    const mesh = holder.children[0];
    mesh.updateMatrixWorld(true);
    for (const face of object.faces) {
      const points = face.map((i) => new THREE.Vector3(...object.vertices[i]).applyMatrix4(mesh.matrixWorld));
      const plane = new THREE.Plane().setFromCoplanarPoints(points[0], points[1], points[2]);
      const de = plane.distanceToPoint(eye), dt = plane.distanceToPoint(target);
      if (!(de < 0 && dt > 0)) continue;
      const hit = eye.clone().lerp(target, de / (de - dt));
      const inside = points.every((p, k) => {
        const q = points[(k + 1) % points.length];
        return new THREE.Vector3().crossVectors(q.clone().sub(p), hit.clone().sub(p)).dot(plane.normal) >= -1e-9;
      });
      if (inside) ++blocking;
    }
  }
  return blocking;
}

export function defaultCamera(bounds, objects = null) {
  const centre = bounds.getCenter(new THREE.Vector3());
  const size = bounds.getSize(new THREE.Vector3());
  const radius = Math.max(size.length() / 2, 1e-3);
  const distance = radius / Math.sin((45 / 2) * Math.PI / 180);
  const first = Math.atan2(0.6, 1);
  let best = null;
  for (let k = 0; k < 8; ++k) {
    const azimuth = first + k * Math.PI / 4;
    const direction = new THREE.Vector3(Math.sin(azimuth), 0.45 / Math.hypot(0.6, 1), Math.cos(azimuth)).normalize();
    const eye = centre.clone().addScaledVector(direction, distance);
    const blocked = objects ? blockingShellFaces(objects, eye, centre) : 0;
    if (!best || blocked < best.blocked) best = { eye, direction, blocked };
    if (blocked === 0) break;
  }
  const camera = { position: best.eye.toArray(), target: centre.toArray(), up: [0, 1, 0], projection: 'perspective',
    fov_y_deg: 45, near: distance / 100, far: distance * 3 };
  if (best.blocked === 0) return camera;
  // A closed room: from inside, near the least hidden side, at two thirds of its height.
  const half = size.clone().multiplyScalar(0.5);
  const eye = centre.clone().add(new THREE.Vector3(best.direction.x * half.x * 0.8, size.y * 0.15, best.direction.z * half.z * 0.8));
  return { ...camera, position: eye.toArray(), fov_y_deg: 60, near: radius / 200 };
}
