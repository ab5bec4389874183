#!/usr/bin/env node
// Unit tests of web_client/src/light_shape.js and the light part of object_edits.js's reset frame
// (node:test, no browser): a resized quad keeps its centre, edge directions and winding; any
// polygon scales about its centre to the asked size; intensity keeps the colour; a set_light names
// only what changed; Reset to file sets an edited light back and adds / removes lights; an added
// light's copy goes beside its source inside the bounds; add_light and remove_light invert each other.
import assert from 'node:assert/strict';
import test from 'node:test';

import { besideOffset, centroid, movedTo, quadAxes, resized, resizedQuad, setLightEdit, sizeOf, withIntensity } from '../../web_client/src/light_shape.js';
import { addLightEdits, freshId, lightCopy, removeLightEdits, resetEdits } from '../../web_client/src/object_edits.js';

const close = (a, b, eps = 1e-12) => a.every((x, k) => Math.abs(x - b[k]) < eps);
const normal = (p) => {
  const u = p[1].map((x, k) => x - p[0][k]), v = p[2].map((x, k) => x - p[0][k]);
  const n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
  const l = Math.hypot(...n);
  return n.map((x) => x / l);
};
// cubes15's light: 1.5 m square facing down; and a tilted parallelogram.
const square = [[-0.75, 2.98, -0.75], [0.75, 2.98, -0.75], [0.75, 2.98, 0.75], [-0.75, 2.98, 0.75]];
const tilted = [[0, 2, 0], [1, 2.5, 0], [1.5, 2.5, 1], [0.5, 2, 1]];

test('a resized quad keeps its centre, edge directions and facing', () => {
  for (const quad of [square, tilted]) {
    const axes = quadAxes(quad);
    const big = resizedQuad(quad, 2 * axes.width, 0.5 * axes.depth);
    const after = quadAxes(big);
    assert.ok(after, 'still a parallelogram');
    assert.ok(Math.abs(after.width - 2 * axes.width) < 1e-12 && Math.abs(after.depth - 0.5 * axes.depth) < 1e-12);
    assert.ok(close(after.u, axes.u) && close(after.v, axes.v), 'edge directions kept');
    assert.ok(close(centroid(big), centroid(quad)), 'centre kept');
    assert.ok(close(normal(big), normal(quad)), 'facing kept');
  }
  assert.equal(quadAxes([[0, 0, 0], [1, 0, 0], [0.5, 0, 1]]), null);
  assert.equal(quadAxes([[0, 0, 0], [1, 0, 0], [2, 0, 1], [0, 0, 1]]), null); // a trapezoid
});

test('any polygon scales about its centre to the asked size, and moves to a centre', () => {
  const triangle = [[0, 3, 0], [1, 3, 0], [0, 3, 1]];
  const scaled = resized(triangle, 3);
  assert.ok(Math.abs(sizeOf(scaled) - 3) < 1e-12 && close(centroid(scaled), centroid(triangle)));
  assert.ok(close(centroid(movedTo(square, [1, 2, 3])), [1, 2, 3]));
});

test('intensity scales the radiance keeping its colour; set_light names only what changed', () => {
  assert.deepEqual(withIntensity([17, 12, 4], 34), [34, 24, 8]);
  assert.deepEqual(withIntensity([0, 0, 0], 5), [5, 5, 5]);
  const light = { polygon: square, radiance: [10, 10, 10] };
  assert.deepEqual(setLightEdit('light', light, { ...light, radiance: [20, 20, 20] }), { op: 'set_light', id: 'light', radiance: [20, 20, 20] });
  const moved = movedTo(square, [0, 2.5, 0]);
  assert.deepEqual(setLightEdit('light', light, { ...light, polygon: moved }), { op: 'set_light', id: 'light', polygon: moved });
});

test('reset to file sets an edited light back, and its inverse edits it again', () => {
  const source = { objects: [], lights: [{ id: 'light', polygon: square, radiance: [10, 10, 10] }] };
  const edited = { objects: [], lights: [{ id: 'light', polygon: resizedQuad(square, 2, 2), radiance: [10, 10, 10] }] };
  assert.deepEqual(resetEdits(edited, source), [{ op: 'set_light', id: 'light', polygon: square }]);
  assert.deepEqual(resetEdits(source, edited), [{ op: 'set_light', id: 'light', polygon: edited.lights[0].polygon }]);
  assert.deepEqual(resetEdits(source, source), []);
});

test('an added copy goes beside its light, inside the bounds, never overlapping it', () => {
  const room = { min: [-3, 0, -3], max: [3, 3, 3] };
  const offset = besideOffset(square, room);
  assert.deepEqual(offset, [1.875, 0, 0]); // 1.25 × its 1.5 m width along its first edge
  const copy = lightCopy({ id: 'light', polygon: square, radiance: [1, 2, 3] }, 'light_2', offset);
  assert.ok(copy.polygon.every((p) => p.every((x, k) => x >= room.min[k] && x <= room.max[k])));
  assert.ok(Math.min(...copy.polygon.map((p) => p[0])) > Math.max(...square.map((p) => p[0])), 'beside, not over it');
  assert.deepEqual(copy.radiance, [1, 2, 3]);
  // Against the +x wall: the other way.
  const east = movedTo(square, [2, 2.98, 0]);
  assert.ok(besideOffset(east, room)[0] < 0);
  // No room either way: none.
  assert.equal(besideOffset(square, { min: [-1, 0, -1], max: [1, 3, 1] }), null);
  assert.equal(freshId({ lights: [{ id: 'light' }, { id: 'light_2' }] }, 'light', 'lights'), 'light_3');
});

test('add_light and remove_light invert each other; the removal\'s inverse carries the whole light', () => {
  const light = { id: 'lamp', polygon: square, radiance: [4, 5, 6], extra: 1 };
  const added = addLightEdits(light), removed = removeLightEdits(light);
  assert.deepEqual(added.redo, [{ op: 'add_light', light: { id: 'lamp', polygon: square, radiance: [4, 5, 6] } }]);
  assert.deepEqual(added.undo, [{ op: 'remove_light', id: 'lamp' }]);
  assert.deepEqual(removed.redo, added.undo);
  assert.deepEqual(removed.undo, added.redo);
});

test('reset to file adds removed lights back before removing added ones', () => {
  const lamp = { id: 'lamp', polygon: square, radiance: [1, 1, 1] };
  const other = { id: 'other', polygon: movedTo(square, [1, 2.98, 1]), radiance: [2, 2, 2] };
  const source = { objects: [], lights: [lamp] };
  const edited = { objects: [], lights: [other] };
  assert.deepEqual(resetEdits(edited, source), [{ op: 'add_light', light: lamp }, { op: 'remove_light', id: 'other' }]);
  assert.deepEqual(resetEdits(source, edited), [{ op: 'add_light', light: other }, { op: 'remove_light', id: 'lamp' }]);
});
