#!/usr/bin/env node
// Unit tests of web_client/src/material_edits.js (node:test, no browser): a type change keeps only
// the keys the new type takes (the server refuses the others); an object alone in its material
// changes it in place, one sharing it (or in the default) gets its own copy under a fresh name, and
// each undo frame takes the scene back exactly (seeded random scenes and changes).
import assert from 'node:assert/strict';
import test from 'node:test';

import { MATERIAL_TYPES, albedoHex, changedMaterial, hexAlbedo, objectMaterialEdits } from '../../web_client/src/material_edits.js';

// Applies a frame to scene JSON as the server does (materials and objects; list order aside).
function apply(scene, edits) {
  const out = { materials: { ...scene.materials }, objects: new Map(scene.objects.map((o) => [o.id, o])) };
  for (const edit of edits) {
    if (edit.op === 'set_material') out.materials[edit.id] = edit.material;
    else if (edit.op === 'remove') assert.ok(out.objects.delete(edit.id));
    else if (edit.op === 'add') out.objects.set(edit.object.id, edit.object);
    else assert.fail(`unexpected op ${edit.op}`);
  }
  return { materials: out.materials, objects: [...out.objects.values()] };
}

const byId = (scene) => JSON.stringify([...scene.objects].sort((a, b) => (a.id < b.id ? -1 : 1)));

test('a new type keeps only its keys', () => {
  const gold = { type: 'conductor', roughness: 0.3, eta: [1, 1, 1], k: [2, 2, 2], albedo: [0.9, 0.7, 0.3] };
  assert.deepEqual(changedMaterial(gold, { type: 'diffuse' }), { albedo: [0.9, 0.7, 0.3] });
  assert.deepEqual(changedMaterial(gold, { type: 'dielectric' }), { albedo: [0.9, 0.7, 0.3], type: 'dielectric', roughness: 0.3 });
  assert.deepEqual(changedMaterial({ albedo: [1, 0, 0] }, { albedo: [0, 1, 0] }), { albedo: [0, 1, 0] });
  assert.deepEqual(hexAlbedo(albedoHex([0.8, 0, 1])), [0.8, 0, 1]);
});

test('in place when alone, a copy when shared; undo is exact', () => {
  let seed = 7;
  const random = () => { seed = (seed * 16807) % 2147483647; return seed / 2147483647; };
  for (let round = 0; round < 200; ++round) {
    const names = ['a', 'b', 'c'].slice(0, 1 + Math.floor(3 * random()));
    const materials = Object.fromEntries(names.map((n) => [n, { albedo: [random(), random(), random()] }]));
    const objects = Array.from({ length: 1 + Math.floor(4 * random()) }, (_, i) => {
      const pick = Math.floor((names.length + 1) * random());
      return { id: `box_${i}`, vertices: [], faces: [], ...(pick < names.length ? { material: names[pick] } : {}) };
    });
    const scene = { materials, objects };
    const object = objects[Math.floor(objects.length * random())];
    const change = random() < 0.5 ? { albedo: [random(), random(), random()] } : { type: MATERIAL_TYPES[1 + Math.floor(3 * random())] };
    const edits = objectMaterialEdits(scene, object, change);
    assert.ok(edits, 'a change makes a frame');
    const after = apply(scene, edits.redo);
    const name = object.material || '';
    const alone = name && objects.filter((o) => (o.material || '') === name).length === 1;
    const mine = after.objects.find((o) => o.id === object.id).material;
    if (alone) {
      assert.equal(mine, name);
      assert.equal(edits.redo.length, 1);
    } else {
      assert.ok(!(mine in materials), 'a fresh material');
      if (name) assert.deepEqual(after.materials[name], materials[name], 'the shared one is unchanged');
    }
    assert.deepEqual(after.materials[mine], changedMaterial(materials[name] || { albedo: [0.8, 0.8, 0.8] }, change));
    const undone = apply(after, edits.undo);
    assert.equal(byId(undone), byId(scene));
    for (const n of names) assert.deepEqual(undone.materials[n], materials[n]);
  }
});
