// The page's mapping of scene materials onto MeshPhysicalMaterial parameters (node:test, no browser).
import assert from 'node:assert/strict';
import test from 'node:test';

import { conductorF0, hasPhysicalMaterials, physicalParameters, roughnessOf } from '../../web_client/src/physical_materials.js';

const close = (a, b, eps = 1e-9) => assert.ok(Math.abs(a - b) <= eps, `${a} vs ${b}`);

test('diffuse and rough diffuse stay the DM colours alone', () => {
  assert.equal(physicalParameters({ albedo: [0.5, 0.5, 0.5] }), null);
  assert.equal(physicalParameters({ type: 'rough_diffuse', roughness: 1 }), null);
  assert.equal(physicalParameters(undefined), null);
});

test('a conductor is metal with its Fresnel F0 as colour and r = sqrt(alpha)', () => {
  const p = physicalParameters({ type: 'conductor', roughness: 0.12, eta: [1.5, 1.5, 1.5], k: [3, 3, 3] });
  assert.equal(p.metalness, 1);
  assert.equal(p.transmission, 0);
  close(p.roughness, Math.sqrt(0.12));
  close(p.color[0], (0.25 + 9) / (6.25 + 9));
  assert.equal(p.anisotropy, 0);
  // Default: aluminium, alpha 0.5.
  const al = physicalParameters({ type: 'conductor' });
  close(al.color[0], conductorF0([1.657], [9.224])[0]);
  close(al.roughness, Math.sqrt(0.5));
});

test('anisotropic alpha: roughness from the smaller, anisotropy stretches the tangent to the larger', () => {
  const r = roughnessOf([0.35, 0.04]);
  close(r.roughness, 0.2);
  const alphaT = 0.04 + (1 - 0.04) * r.anisotropy ** 2; // three.js: mix(r², 1, a²)
  close(alphaT, 0.35);
  assert.equal(r.anisotropyRotation, 0);
  assert.equal(roughnessOf([0.04, 0.35]).anisotropyRotation, Math.PI / 2);
  close(roughnessOf(2).roughness, 1); // alpha past three.js's range: clamped
});

test('a dielectric transmits with its ior (clamped to three.js range)', () => {
  const p = physicalParameters({ type: 'dielectric', roughness: 0.02, ior: 1.5 });
  assert.deepEqual([p.metalness, p.transmission, p.ior], [0, 1, 1.5]);
  close(p.roughness, Math.sqrt(0.02));
  assert.equal(physicalParameters({ type: 'dielectric', ior: 3 }).ior, 2.333);
  assert.equal(physicalParameters({ type: 'dielectric', ior: 0.7 }).ior, 1);
});

test('a scene has physical materials when an object names a glossy one', () => {
  const scene = { materials: { m: { type: 'conductor' }, d: { albedo: [1, 1, 1] } }, objects: [{ id: 'a', material: 'd' }] };
  assert.equal(hasPhysicalMaterials(scene), false);
  scene.objects.push({ id: 'b', material: 'm' });
  assert.equal(hasPhysicalMaterials(scene), true);
  assert.equal(hasPhysicalMaterials({ objects: [{ id: 'c' }] }), false);
});
