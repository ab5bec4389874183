// A light's shape and power as the inspector shows them (docs/SCENE_FORMAT.md lights): its centre,
// a quad's width and depth (along its first and last edge) or any polygon's size (twice the
// farthest corner's distance from the centre), and its intensity (the radiance's largest channel).
// Pure functions of light JSON; each edit returns a new polygon or radiance for a set_light;
// besideOffset places an added copy of a light.

const sub = (a, b) => a.map((x, k) => x - b[k]);
const add = (a, b) => a.map((x, k) => x + b[k]);
const mul = (a, s) => a.map((x) => x * s);
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const norm = (a) => Math.sqrt(dot(a, a));

export function centroid(polygon) {
  return [0, 1, 2].map((k) => polygon.reduce((s, p) => s + p[k], 0) / polygon.length);
}

// The polygon moved so that its centroid is `centre`.
export function movedTo(polygon, centre) {
  const by = sub(centre, centroid(polygon));
  return polygon.map((p) => add(p, by));
}

// A quad whose opposite edges are parallel (a rectangle or parallelogram): its two edge
// directions and lengths; null for any other polygon.
export function quadAxes(polygon) {
  if (polygon.length !== 4) return null;
  const u = sub(polygon[1], polygon[0]), v = sub(polygon[3], polygon[0]);
  const w = sub(polygon[2], polygon[3]), z = sub(polygon[2], polygon[1]);
  const width = norm(u), depth = norm(v);
  if (!(width > 0 && depth > 0) || norm(sub(u, w)) > 1e-9 * width || norm(sub(v, z)) > 1e-9 * depth) return null;
  return { u: mul(u, 1 / width), v: mul(v, 1 / depth), width, depth };
}

// Twice the largest distance of a corner from the centroid.
export function sizeOf(polygon) {
  const c = centroid(polygon);
  return 2 * Math.max(...polygon.map((p) => norm(sub(p, c))));
}

// A quad resized to `width` × `depth` about its centroid (its edge directions kept): its corners
// are c ∓ U/2 ∓ V/2 in order, U and V its first and last edge.
export function resizedQuad(polygon, width, depth) {
  const axes = quadAxes(polygon);
  if (!axes) throw new Error('not a parallelogram light');
  const c = centroid(polygon);
  const hu = mul(axes.u, width / 2), hv = mul(axes.v, depth / 2);
  return [[-1, -1], [1, -1], [1, 1], [-1, 1]].map(([a, b]) => add(c, add(mul(hu, a), mul(hv, b))));
}

// Any polygon scaled about its centroid so that sizeOf() gives `size`.
export function resized(polygon, size) {
  const c = centroid(polygon);
  const s = size / sizeOf(polygon);
  return polygon.map((p) => add(c, mul(sub(p, c), s)));
}

export function intensityOf(radiance) {
  return Math.max(...radiance);
}

// The radiance scaled so that its largest channel is `intensity` (its colour kept; a black
// light becomes white of that intensity).
export function withIntensity(radiance, intensity) {
  const now = intensityOf(radiance);
  return now > 0 ? radiance.map((x) => x * intensity / now) : [intensity, intensity, intensity];
}

// The set_light edit taking a light to `light` ({polygon, radiance}), with only what changed.
export function setLightEdit(id, from, to) {
  const edit = { op: 'set_light', id };
  if (JSON.stringify(from.polygon) !== JSON.stringify(to.polygon)) edit.polygon = to.polygon;
  if (JSON.stringify(from.radiance) !== JSON.stringify(to.radiance)) edit.radiance = to.radiance;
  return edit;
}

// An offset moving the polygon beside itself — along its first edge or its last, either way, by
// 1.25 × its extent that way, then twice and three times that — with every corner inside `box`
// ({min, max}: [x, y, z]) and accept(offset) true; null if none fits. A copy there neither
// overlaps its source nor leaves the scene's bounds.
export function besideOffset(polygon, box, accept = () => true) {
  const directions = [sub(polygon[1], polygon[0]), sub(polygon[polygon.length - 1], polygon[0])];
  for (let steps = 1; steps <= 3; ++steps) {
    for (const d of directions.flatMap((d) => [d, mul(d, -1)])) {
      const unit = mul(d, 1 / norm(d));
      const along = polygon.map((p) => dot(p, unit));
      const offset = mul(unit, steps * 1.25 * (Math.max(...along) - Math.min(...along)));
      const inside = polygon.every((p) => add(p, offset).every((x, k) => x >= box.min[k] && x <= box.max[k]));
      if (inside && accept(offset)) return offset;
    }
  }
  return null;
}
