#!/usr/bin/env node
// Unit tests of the page's binary mesh reader (web_client/src/mesh_binary.js) and its receiver
// layer (receiver_layer.js) for value parts (node:test, no browser): a part's irradiance, whole or
// a delta's value part, one channel (each value times the part's tint, rounded to f32: grey when
// the tint is (1, 1, 1)) or three, decodes to r, g, b per vertex; a layout-3 mesh is refused by
// its version; and the layer recolours a held part in place — same batch Mesh, its
// colour buffer rewritten at the part's vertices only, positions and the other parts untouched —
// while a value part the page does not hold is an error. The bytes are written here from
// docs/API.md "Binary", independently of the server's writer.
import assert from 'node:assert/strict';
import test from 'node:test';

import * as THREE from '../../web_client/node_modules/three/build/three.module.js';

import { decodeMeshBinary } from '../../web_client/src/mesh_binary.js';
import { ReceiverLayer } from '../../web_client/src/receiver_layer.js';
import { ToneMap } from '../../web_client/src/tone_map.js';

// A binary mesh of layout `layout` (docs/API.md "Binary"; layout 3 for refusing it): parts
// {object, face, chunk, version, positions, irradiance, classes, indices, and optionally channels
// 1 with tint [r, g, b], irradiance then one value per vertex}, values {object, face, chunk,
// version, channels, values, optionally tint}.
function meshBytes({ layout = 4, version, since = null, parts = [], values = [] }) {
  const names = [...new Set([...parts, ...values].map((p) => p.object))];
  const words = [];
  const u32 = (x) => words.push(['u', x]);
  const i32 = (x) => words.push(['i', x]);
  const f32 = (x) => words.push(['f', x]);
  const bytes = [];
  const vertices = parts.reduce((n, p) => n + p.positions.length / 3, 0);
  const triangles = parts.reduce((n, p) => n + p.indices.length / 3, 0);
  for (const x of ['P', 'N', 'M', 'B']) bytes.push(['b', x.charCodeAt(0)]);
  [layout, version, since === null ? 0 : 1, since || 0, names.length, parts.length, 0, vertices, triangles].forEach(u32);
  u32(values.length);
  for (const name of names) {
    u32(name.length);
    for (let k = 0; k < name.length; k += 4) u32([0, 1, 2, 3].reduce((w, j) => w + (name.charCodeAt(k + j) || 0) * 256 ** j, 0));
  }
  for (const p of parts) {
    [names.indexOf(p.object), p.face].forEach(u32);
    p.chunk.forEach(i32);
    [p.positions.length / 3, p.indices.length / 3, p.version].forEach(u32);
    [0, 1, 0].forEach(f32);
    if (layout === 4) {
      u32(p.channels || 3);
      (p.tint || [1, 1, 1]).forEach(f32);
    }
  }
  for (const v of values) {
    [names.indexOf(v.object), v.face].forEach(u32);
    v.chunk.forEach(i32);
    [v.values.length / v.channels, v.version, v.channels].forEach(u32);
    (v.tint || [1, 1, 1]).forEach(f32);
  }
  for (const p of parts) {
    p.positions.forEach(f32);
    p.irradiance.forEach(f32);
    for (let k = 0; k < p.classes.length; k += 4) u32([0, 1, 2, 3].reduce((w, j) => w + (p.classes[k + j] || 0) * 256 ** j, 0));
    p.indices.forEach(u32);
  }
  for (const v of values) v.values.forEach(f32);
  const buffer = new ArrayBuffer(4 + 4 * words.length);
  const view = new DataView(buffer);
  bytes.forEach(([, b], k) => view.setUint8(k, b));
  words.forEach(([type, x], k) => {
    const at = 4 + 4 * k;
    if (type === 'u') view.setUint32(at, x, true);
    else if (type === 'i') view.setInt32(at, x, true);
    else view.setFloat32(at, x, true);
  });
  return buffer;
}

// Two faces of the floor in chunk (0, 0): one batch. Face 0 a triangle, face 1 a quad.
const floor0 = { object: 'floor', face: 0, chunk: [0, 0], version: 0, positions: [0, 0, 0, 1, 0, 0, 0, 0, 1],
  irradiance: [1, 1, 1, 2, 2, 2, 3, 3, 3], classes: [0, 1, 2], indices: [0, 2, 1] };
const floor1 = { object: 'floor', face: 1, chunk: [0, 0], version: 0, positions: [0, 1, 0, 1, 1, 0, 1, 1, 1, 0, 1, 1],
  irradiance: [4, 4, 4, 5, 5, 5, 6, 6, 6, 7, 7, 7], classes: [0, 0, 1, 1], indices: [0, 1, 2, 0, 2, 3] };
const near = (a, b) => a.length === b.length && a.every((x, k) => Math.abs(x - b[k]) < 1e-6);

test('a value part decodes to its new irradiance, grey, tinted or coloured', () => {
  const tint = [1, 10 / 12, 8 / 12].map(Math.fround);
  const decoded = decodeMeshBinary(meshBytes({ version: 5, since: 4, values: [
    { object: 'floor', face: 1, chunk: [0, 0], version: 5, channels: 1, values: [8, 9, 10, 11] },
    { object: 'floor', face: 0, chunk: [0, 0], version: 5, channels: 3, values: [1, 2, 3, 4, 5, 6, 7, 8, 9] },
    { object: 'wall', face: 0, chunk: [1, -2], version: 5, channels: 1, tint, values: [0.1, 0, 3e7] },
  ] }));
  assert.equal(decoded.delta, true);
  assert.equal(decoded.parts.length, 0);
  assert.equal(decoded.totalVertices, 0);
  const [grey, rgb] = decoded.valueParts;
  assert.equal(grey.key, 'floor/1/0/0');
  assert.equal(grey.vertexCount, 4);
  assert.equal(grey.sceneVersion, 5);
  assert.deepEqual(Array.from(grey.irradiance), [8, 8, 8, 9, 9, 9, 10, 10, 10, 11, 11, 11]);
  assert.equal(rgb.vertexCount, 3);
  assert.deepEqual(Array.from(rgb.irradiance), [1, 2, 3, 4, 5, 6, 7, 8, 9]);
  const tinted = decoded.valueParts[2];
  assert.equal(tinted.key, 'wall/0/1/-2');
  assert.equal(tinted.channels, 1);
  // Each value (as f32) times each tint channel, the product rounded to f32.
  const want = [0.1, 0, 3e7].flatMap((v) => tint.map((t) => Math.fround(Math.fround(v) * t)));
  assert.deepEqual(Array.from(tinted.irradiance), want);
  assert.notEqual(want[1], Math.fround(0.1) * tint[1], 'the f32 product is not the double one');
});

test('a whole part\'s irradiance decodes from one channel and its tint, its other arrays after it', () => {
  const tint = [Math.fround(0.25), Math.fround(0.7), 1];
  const part = { ...floor0, channels: 1, tint, irradiance: [2, 0.3, 5] };
  const decoded = decodeMeshBinary(meshBytes({ version: 3, parts: [part, floor1] }));
  const [tinted, rgb] = decoded.parts;
  assert.equal(tinted.channels, 1);
  assert.deepEqual(tinted.tint, tint);
  assert.deepEqual(Array.from(tinted.irradiance), [2, 0.3, 5].flatMap((v) => tint.map((t) => Math.fround(Math.fround(v) * t))));
  assert.deepEqual(Array.from(tinted.positions), floor0.positions);
  assert.deepEqual(Array.from(tinted.classes), floor0.classes);
  assert.deepEqual(Array.from(tinted.indices), floor0.indices);
  assert.equal(rgb.channels, 3);
  assert.deepEqual(Array.from(rgb.irradiance), floor1.irradiance);
  assert.deepEqual(Array.from(rgb.classes), floor1.classes);
  assert.equal(decoded.totalVertices, 7);
});

test('a mesh of another layout is refused by its version, a bad channel count by name', () => {
  assert.throws(() => decodeMeshBinary(meshBytes({ layout: 3, version: 0, parts: [floor0] })), /unsupported layout version 3/);
  assert.throws(() => decodeMeshBinary(meshBytes({ version: 0, parts: [{ ...floor0, channels: 2 }] })), /part floor\/0\/0\/0 has 2 channels/);
  assert.throws(() => decodeMeshBinary(meshBytes({ version: 1, since: 0, values: [
    { object: 'floor', face: 0, chunk: [0, 0], version: 1, channels: 2, values: [1, 2, 3, 4, 5, 6] }] })), /2 channels/);
});

test('the layer recolours a held part in place and refuses values for a part it does not hold', () => {
  const scene = { objects: [{ id: 'floor', faces: [] }], lights: [{ polygon: [[0, 3, 0], [1, 3, 0], [1, 3, 1]], radiance: [5, 5, 5] }] };
  const toneMap = new ToneMap(scene, new THREE.Box3(new THREE.Vector3(0, 0, 0), new THREE.Vector3(1, 3, 1)));
  const layer = new ReceiverLayer(new THREE.Scene());
  const whole = decodeMeshBinary(meshBytes({ version: 0, parts: [floor0, floor1] }));
  toneMap.calibrate(whole.parts);
  layer.apply(whole, toneMap);
  assert.equal(layer.batches.size, 1);
  const { mesh } = layer.batches.get('floor#0,0');
  const colour = mesh.geometry.getAttribute('color');
  const positions = Array.from(mesh.geometry.getAttribute('position').array);
  const before = Array.from(colour.array);
  const offset = 3 * mesh.userData.offsets.get('floor/1/0/0');
  const otherOffset = 3 * mesh.userData.offsets.get('floor/0/0/0');
  const seenVersion = colour.version;

  let touched = null;
  layer.onColours = (keys) => { touched = keys; };
  layer.apply(decodeMeshBinary(meshBytes({ version: 1, since: 0, values: [
    { object: 'floor', face: 1, chunk: [0, 0], version: 1, channels: 1, values: [0.5, 0.25, 0, 8] }] })), toneMap);
  assert.equal(layer.batches.get('floor#0,0').mesh, mesh, 'the batch is not rebuilt');
  assert.ok(colour.version > seenVersion, 'the colour buffer is marked for upload');
  const want = toneMap.colours('floor', new Float32Array([0.5, 0.5, 0.5, 0.25, 0.25, 0.25, 0, 0, 0, 8, 8, 8]));
  assert.ok(near(colour.array.slice(offset, offset + 12), want));
  assert.ok(!near(before.slice(offset, offset + 12), want), 'the colours changed');
  assert.deepEqual(Array.from(colour.array.slice(otherOffset, otherOffset + 9)), before.slice(otherOffset, otherOffset + 9));
  assert.deepEqual(Array.from(mesh.geometry.getAttribute('position').array), positions);
  const merged = layer.receiver('floor/1');
  assert.deepEqual(Array.from(merged.irradiance), [0.5, 0.5, 0.5, 0.25, 0.25, 0.25, 0, 0, 0, 8, 8, 8]);
  assert.deepEqual(Array.from(merged.positions), floor1.positions);
  assert.equal(merged.sceneVersion, 1);
  assert.deepEqual([...touched], ['floor/1']);

  assert.throws(() => layer.apply(decodeMeshBinary(meshBytes({ version: 2, since: 1, values: [
    { object: 'floor', face: 2, chunk: [0, 0], version: 2, channels: 1, values: [1] }] })), toneMap), /does not hold/);
});
