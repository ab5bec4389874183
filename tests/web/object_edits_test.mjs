#!/usr/bin/env node
// Unit tests of web_client/src/object_edits.js (node:test, no browser): the box primitive's faces
// face outwards; a duplicate gets a fresh id and the offset; and, on seeded random edit histories,
// the reset frame applied to the edited scene gives back the source, as does the inverse frame the
// other way (so "Reset to file" and its undo are exact).
import assert from 'node:assert/strict';
import test from 'node:test';

import { boxObject, duplicateObject, freshId, materialEdits, renameEdits, resetEdits } from '../../web_client/src/object_edits.js';

// Applies a frame to scene JSON as the server does (objects only; order of the list aside).
function apply(scene, edits) {
  const objects = new Map(scene.objects.map((o) => [o.id, o]));
  for (const edit of edits) {
    if (edit.op === 'remove') assert.ok(objects.delete(edit.id), `remove of unknown ${edit.id}`);
    else if (edit.op === 'add') { assert.ok(!objects.has(edit.object.id), `add of existing ${edit.object.id}`); objects.set(edit.object.id, edit.object); }
    else if (edit.op === 'move') objects.set(edit.id, { ...objects.get(edit.id), transform: edit.transform });
  }
  return { ...scene, objects: [...objects.values()] };
}

const sorted = (scene) => JSON.stringify([...scene.objects].sort((a, b) => a.id.localeCompare(b.id)));

function rng(seed) {
  let s = seed >>> 0;
  return () => ((s = (s * 1664525 + 1013904223) >>> 0) / 2 ** 32);
}

test('a rename and a material change are one frame each whose undo gives the scene back exactly', () => {
  const scene = { objects: [boxObject('a', [0, 0, 0], [1, 1, 1], 'white'), boxObject('b', [2, 0, 0], [1, 1, 1], 'white')] };
  const renamed = renameEdits(scene.objects[0], 'crate');
  const after = apply(scene, renamed.redo);
  assert.deepEqual(after.objects.map((o) => o.id).sort(), ['b', 'crate']);
  assert.deepEqual({ ...after.objects.find((o) => o.id === 'crate'), id: 'a' }, scene.objects[0]);
  assert.equal(sorted(apply(after, renamed.undo)), sorted(scene));
  const recoloured = materialEdits(scene.objects[1], 'clay');
  const clay = apply(scene, recoloured.redo);
  assert.equal(clay.objects.find((o) => o.id === 'b').material, 'clay');
  assert.equal(sorted(apply(clay, recoloured.undo)), sorted(scene));
});

test('box faces point outwards (counter-clockwise seen from outside)', () => {
  const box = boxObject('b', [1, 2, 3], [2, 1, 0.5]);
  for (const face of box.faces) {
    const [a, b, c] = face.slice(0, 3).map((i) => box.vertices[i]);
    const u = b.map((x, k) => x - a[k]), v = c.map((x, k) => x - a[k]);
    const n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
    const centre = [0, 1, 2].map((k) => face.reduce((s, i) => s + box.vertices[i][k], 0) / face.length);
    assert.ok(n[0] * centre[0] + n[1] * centre[1] + n[2] * centre[2] > 0, `face ${face} faces inwards`);
  }
  assert.deepEqual(box.transform.translate, [1, 2, 3]);
});

test('a duplicate has a fresh id, is moved by the offset and is never static', () => {
  const scene = { objects: [{ id: 'a', static: true, vertices: [], faces: [], transform: { translate: [1, 0, 0] } }, { id: 'a_copy' }] };
  const id = freshId(scene, 'a_copy');
  assert.equal(id, 'a_copy_2');
  const copy = duplicateObject(scene.objects[0], id, [0.5, 0, -1]);
  assert.deepEqual(copy.transform.translate, [1.5, 0, -1]);
  assert.equal(copy.static, undefined);
  assert.equal(scene.objects[0].transform.translate[0], 1); // the original is untouched
});

test('reset frames give back the source and its inverse the edited scene (seeded random histories)', () => {
  for (let seed = 1; seed <= 200; ++seed) {
    const random = rng(seed);
    const box = (id) => boxObject(id, [random(), random(), random()], [1, 1, 1]);
    const source = { objects: Array.from({ length: 1 + Math.floor(random() * 6) }, (_, i) => box(`o${i}`)) };
    let scene = source;
    for (let step = 0; step < 10; ++step) {
      const ids = scene.objects.map((o) => o.id);
      const pick = ids[Math.floor(random() * ids.length)];
      const r = random();
      if (r < 0.4 && pick) scene = apply(scene, [{ op: 'move', id: pick, transform: { translate: [random(), random(), random()], rotate_deg: [0, 90 * random(), 0] } }]);
      else if (r < 0.6 && pick) scene = apply(scene, [{ op: 'remove', id: pick }]);
      else if (r < 0.8) scene = apply(scene, [{ op: 'add', object: box(freshId(scene, 'box')) }]);
      else if (pick) scene = apply(scene, [{ op: 'remove', id: pick }, { op: 'add', object: { ...box(pick), vertices: [[0, 0, 0]] } }]);
    }
    const back = apply(scene, resetEdits(scene, source));
    assert.equal(sorted(back), sorted(source), `seed ${seed}: reset`);
    assert.equal(sorted(apply(back, resetEdits(source, scene))), sorted(scene), `seed ${seed}: undo of the reset`);
  }
});

test('a volume is reset by move and set_volume, and added back by add_volume', () => {
  const smoke = { id: 'smoke', type: 'volume', file: '/data/smoke.nrrd', isovalue: 40.5, transform: { translate: [0, 1, 0] } };
  const puff = { ...smoke, id: 'puff', file: '/data/volumes/x.nrrd' };
  const source = { lights: [], objects: [smoke, puff] };
  const current = { lights: [], objects: [{ ...smoke, isovalue: 90, transform: { translate: [1, 1, 0] } }] };
  const edits = resetEdits(current, source);
  assert.deepEqual(edits, [
    { op: 'move', id: 'smoke', transform: { translate: [0, 1, 0] } },
    { op: 'set_volume', id: 'smoke', isovalue: 40.5 },
    { op: 'add_volume', volume: puff },
  ]);
  assert.deepEqual(resetEdits(source, current).map((e) => e.op), ['move', 'set_volume', 'remove']);
});
