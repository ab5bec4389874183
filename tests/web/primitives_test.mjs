// The page's primitives (web_client/src/primitives.js) as scene JSON: every face planar and convex
// with its front (counter-clockwise) side outward, the object `size` across, closed shapes closed.
import assert from 'node:assert/strict';
import test from 'node:test';

import { PRIMITIVES, primitiveObject, primitiveSize } from '../../web_client/src/primitives.js';

const sub = (a, b) => a.map((x, k) => x - b[k]);
const dot = (a, b) => a.reduce((s, x, k) => s + x * b[k], 0);
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
// Newell's normal: its length is twice the polygon's area.
const newell = (p) => p.reduce((n, a, i) => {
  const b = p[(i + 1) % p.length];
  return [n[0] + (a[1] - b[1]) * (a[2] + b[2]), n[1] + (a[2] - b[2]) * (a[0] + b[0]), n[2] + (a[0] - b[0]) * (a[1] + b[1])];
}, [0, 0, 0]);

for (const kind of PRIMITIVES) {
  test(`${kind}: planar convex faces, front side outward, ${kind === 'plane' ? 'facing up' : 'closed'}`, () => {
    const size = 0.8;
    const object = primitiveObject(kind, kind, [1, 2, 3], size, 'white');
    assert.equal(object.id, kind);
    assert.equal(object.material, 'white');
    assert.deepEqual(object.transform.translate, [1, 2, 3]);
    const extent = [0, 1, 2].map((k) => Math.max(...object.vertices.map((v) => v[k])) - Math.min(...object.vertices.map((v) => v[k])));
    primitiveSize(kind, size).forEach((s, k) => assert.ok(Math.abs(extent[k] - s) < 1e-9, `${kind} extent ${extent}`));
    const edges = new Map();
    for (const face of object.faces) {
      const p = face.map((i) => object.vertices[i]);
      const n = newell(p);
      const unit = n.map((x) => x / Math.hypot(...n));
      for (const q of p) assert.ok(Math.abs(dot(sub(q, p[0]), unit)) < 1e-9, `${kind}: face ${face} is not planar`);
      p.forEach((a, i) => {
        const turn = cross(sub(p[(i + 1) % p.length], a), sub(p[(i + 2) % p.length], p[(i + 1) % p.length]));
        assert.ok(dot(turn, unit) > 0, `${kind}: face ${face} is not convex counter-clockwise`);
      });
      const centre = [0, 1, 2].map((k) => p.reduce((s, v) => s + v[k], 0) / p.length);
      if (kind === 'plane') assert.ok(unit[1] > 0.999, 'the plane faces up');
      else assert.ok(dot(unit, centre) > 0, `${kind}: face ${face} faces inward`);
      face.forEach((a, i) => edges.set(`${a},${face[(i + 1) % face.length]}`, true));
    }
    // Closed and consistently wound: every edge is walked once each way.
    if (kind !== 'plane') for (const key of edges.keys()) assert.ok(edges.has(key.split(',').reverse().join(',')), `${kind}: edge ${key} is open`);
  });
}

test('an unknown primitive is refused by name', () => {
  assert.throws(() => primitiveObject('torus', 't', [0, 0, 0], 1), /unknown primitive 'torus'/);
});
