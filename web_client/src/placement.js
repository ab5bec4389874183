// Where the camera and new things go (issue 37): the room is the scene's bounds (its walls,
// floor, ceiling and lights); a focused camera stays inside it, looking from the room's side; a
// new object or volume goes on the floor at a free spot in view; a duplicate beside its original
// where nothing else is; a new light beside its source where the view sees it.
import * as THREE from 'three';
import { besideOffset, centroid } from './light_shape.js';

const FREE_GAP = 0.05; // metres between a placed object and its neighbours

// The room shrunk by a small margin on each axis that has room for one (a flat axis stays flat).
export function innerRoom(room) {
  const size = room.getSize(new THREE.Vector3());
  const margin = 0.02 * Math.min(...size.toArray().filter((x) => x > 1e-6), Infinity);
  const inner = room.clone();
  for (const k of ['x', 'y', 'z']) {
    if (size[k] <= 4 * margin) continue;
    inner.min[k] += margin;
    inner.max[k] -= margin;
  }
  return inner;
}

// The camera for a focus on `centre` from `distance` away along `direction` (unit), kept in the
// room: an axis along which it would leave the room turns to the side with more room (a ceiling
// light is seen from below), then the eye is clamped inside the room.
export function focusEye(centre, direction, distance, room) {
  const inner = innerRoom(room);
  const dir = direction.clone();
  for (const k of ['x', 'y', 'z']) {
    const p = centre[k] + dir[k] * distance;
    const out = p > inner.max[k] || p < inner.min[k];
    const roomAhead = dir[k] > 0 ? inner.max[k] - centre[k] : centre[k] - inner.min[k];
    const roomBehind = dir[k] > 0 ? centre[k] - inner.min[k] : inner.max[k] - centre[k];
    if (out && roomBehind > roomAhead) dir[k] = -dir[k];
  }
  const eye = centre.clone().addScaledVector(dir, distance).clamp(inner.min, inner.max);
  // An eye clamped onto the centre (the selection fills the room's edge) sees nothing: keep the unclamped one.
  return eye.distanceTo(centre) > 1e-3 * distance ? eye : centre.clone().addScaledVector(dir, distance);
}

// Whether `point` is in front of the camera and within `margin` (0..1) of the view's middle.
export function inView(camera, point, margin = 0.85) {
  const ndc = new THREE.Vector3(...point).project(camera);
  return ndc.z > -1 && ndc.z < 1 && Math.abs(ndc.x) <= margin && Math.abs(ndc.y) <= margin;
}

// Boxes of the objects a new one must not overlap: every unlocked object's (walls and floors are
// where things stand, not obstacles).
function obstacles(objects, exceptId = null) {
  return [...objects.byId].filter(([id, holder]) => id !== exceptId && !holder.userData.locked)
    .map(([id]) => objects.objectBounds(id)).filter((box) => box && !box.isEmpty());
}

const overlaps = (box, others) => others.some((o) => box.clone().expandByScalar(FREE_GAP - 1e-6).intersectsBox(o));

// The centre of a `size` (Vector3) box standing on the room's floor: among a grid of floor spots,
// the nearest to the view's target of those in view and free, else of those in view, else the
// target's spot clamped into the room.
export function floorSpot(objects, view, size) {
  const room = objects.bounds;
  const y = room.min.y + size.y / 2 + 1e-3;
  const target = view.controls.target;
  const lo = room.min.clone().addScaledVector(size, 0.5);
  const hi = room.max.clone().addScaledVector(size, -0.5);
  const clampAxis = (v, k) => (lo[k] <= hi[k] ? Math.min(Math.max(v, lo[k]), hi[k]) : (room.min[k] + room.max[k]) / 2);
  const fallback = [clampAxis(target.x, 'x'), y, clampAxis(target.z, 'z')];
  const others = obstacles(objects);
  const N = 12;
  let best = null;
  for (let i = 0; i <= N; ++i) {
    for (let j = 0; j <= N; ++j) {
      const spot = [clampAxis(lo.x + (hi.x - lo.x) * i / N, 'x'), y, clampAxis(lo.z + (hi.z - lo.z) * j / N, 'z')];
      if (!inView(view.camera, spot)) continue;
      const box = new THREE.Box3().setFromCenterAndSize(new THREE.Vector3(...spot), size);
      const rank = (overlaps(box, others) ? 1e9 : 0) + Math.hypot(spot[0] - target.x, spot[2] - target.z);
      if (!best || rank < best.rank) best = { spot, rank };
    }
  }
  return best ? best.spot : fallback;
}

// A duplicate's offset from its original (box: the original's world bounds): a step of its own
// width (plus a gap) along ±x, ±z or a diagonal, one to three steps out: the first whose box stays
// inside the room and overlaps no other object; null if there is none.
export function freeOffset(objects, box) {
  const size = box.getSize(new THREE.Vector3());
  const room = objects.bounds;
  const others = obstacles(objects).filter((o) => !o.equals(box));
  const steps = [[1, 0], [-1, 0], [0, 1], [0, -1], [1, 1], [-1, 1], [1, -1], [-1, -1]];
  for (let k = 1; k <= 3; ++k) {
    for (const [sx, sz] of steps) {
      const offset = new THREE.Vector3(sx * k * (size.x + FREE_GAP), 0, sz * k * (size.z + FREE_GAP));
      const moved = box.clone().translate(offset);
      const inside = moved.min.x >= room.min.x && moved.max.x <= room.max.x && moved.min.z >= room.min.z && moved.max.z <= room.max.z;
      if (inside && !overlaps(moved, [box, ...others])) return offset.toArray();
    }
  }
  return null;
}

// A new light's offset from `polygon` (its source): beside it (light_shape.js besideOffset, one
// to three steps out) inside `box` ({min, max} arrays), not over another light (`lights`:
// polygons): the first whose centre the view sees, else the first that fits at all; null if none.
export function lightOffset(polygon, box, lights, camera) {
  const boundsOf = (points) => new THREE.Box3().setFromPoints(points.map((p) => new THREE.Vector3(...p)));
  const taken = lights.map(boundsOf);
  const centre = centroid(polygon);
  const free = (offset) => {
    const area = boundsOf(polygon.map((p) => p.map((x, i) => x + offset[i]))).expandByScalar(-1e-6);
    return !taken.some((t) => t.intersectsBox(area));
  };
  return besideOffset(polygon, box, (offset) => free(offset) && inView(camera, centre.map((x, i) => x + offset[i])))
    || besideOffset(polygon, box, free);
}
