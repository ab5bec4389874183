// The primitives the page adds: box, sphere, cylinder, cone and plane as scene JSON objects of
// planar convex faces, counter-clockwise seen from outside (the format's front side), centred on
// their origin and `size` metres across. The engine casts each as one object, however many faces.
import { boxObject } from './object_edits.js';

export const PRIMITIVES = ['box', 'sphere', 'cylinder', 'cone', 'plane'];
const SIDES = 16; // around a cylinder or cone: 16 faces keep their shadows round at a low DM cost
const RINGS = 6; // a sphere's latitude bands (of SIDES / 4 * 3 = 12 longitudes)

const ring = (n, radius, y) => Array.from({ length: n }, (_, k) => {
  const a = (2 * Math.PI * k) / n;
  return [radius * Math.cos(a), y, -radius * Math.sin(a)]; // counter-clockwise seen from above (+y)
});

// A UV sphere: quads between latitude rings (isosceles trapezoids: planar), triangles at the poles.
function sphere(r) {
  const n = 12;
  const vertices = [[0, r, 0]];
  for (let i = 1; i < RINGS; ++i) {
    const phi = (Math.PI * i) / RINGS;
    vertices.push(...ring(n, r * Math.sin(phi), r * Math.cos(phi)));
  }
  const bottom = vertices.push([0, -r, 0]) - 1;
  const at = (i, k) => 1 + (i - 1) * n + (k % n); // ring i (1..RINGS-1), longitude k
  const faces = [];
  for (let k = 0; k < n; ++k) {
    faces.push([0, at(1, k), at(1, k + 1)]);
    for (let i = 1; i < RINGS - 1; ++i) faces.push([at(i, k), at(i + 1, k), at(i + 1, k + 1), at(i, k + 1)]);
    faces.push([at(RINGS - 1, k), bottom, at(RINGS - 1, k + 1)]);
  }
  return { vertices, faces };
}

// A cylinder (top radius = bottom radius) or a cone (top radius 0: an apex).
function tube(r, h, topRadius) {
  const bottom = ring(SIDES, r, -h / 2);
  const top = topRadius > 0 ? ring(SIDES, topRadius, h / 2) : [[0, h / 2, 0]];
  const vertices = [...bottom, ...top];
  const faces = [];
  for (let k = 0; k < SIDES; ++k) {
    const next = (k + 1) % SIDES;
    faces.push(topRadius > 0 ? [k, next, SIDES + next, SIDES + k] : [k, next, SIDES]);
  }
  faces.push(Array.from({ length: SIDES }, (_, k) => SIDES - 1 - k)); // the base, facing down
  if (topRadius > 0) faces.push(Array.from({ length: SIDES }, (_, k) => SIDES + k)); // the top, facing up
  return { vertices, faces };
}

// One quad facing up (+y): a sheet that casts a shadow from above.
function plane(s) {
  const h = s / 2;
  return { vertices: [[-h, 0, -h], [-h, 0, h], [h, 0, h], [h, 0, -h]], faces: [[0, 1, 2, 3]] };
}

// The bounding size (x, y, z) of a primitive `size` metres across.
export function primitiveSize(kind, size) {
  return kind === 'plane' ? [size, 0, size] : [size, size, size];
}

// Scene JSON for primitive `kind` with `id`, placed at `at`, in `material` (optional).
export function primitiveObject(kind, id, at, size, material) {
  if (kind === 'box') return boxObject(id, at, [size, size, size], material);
  const shapes = { sphere: () => sphere(size / 2), cylinder: () => tube(size / 2, size, size / 2), cone: () => tube(size / 2, size, 0),
    plane: () => plane(size) };
  if (!shapes[kind]) throw new Error(`unknown primitive '${kind}' (${PRIMITIVES.join(', ')})`);
  const object = { id, ...shapes[kind](), transform: { translate: [...at], rotate_deg: [0, 0, 0], scale: [1, 1, 1] } };
  if (material) object.material = material;
  return object;
}
