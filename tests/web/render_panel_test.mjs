// The server render's refinement (web_client/src/render_panel*.js): the samples of each pass up to
// the server's bound, and the noise estimate that says when the passes have converged — never
// below the newer pass's true noise, and not far above it — on seeded synthetic images.
import assert from 'node:assert/strict';
import test from 'node:test';

import { sampleSchedule } from '../../web_client/src/render_panel.js';
import { CONVERGED_LEVELS, RATIO, noiseLevels } from '../../web_client/src/render_panel_noise.js';
import { seeded } from './seeded_random.mjs';


function gaussian(random) {
  return Math.sqrt(-2 * Math.log(1 - random())) * Math.cos(2 * Math.PI * random());
}

// An RGBA image: a smooth picture plus independent noise of `sigma` levels per channel.
function noisy(random, pixels, sigma) {
  const out = new Uint8ClampedArray(4 * pixels);
  for (let p = 0; p < pixels; ++p) {
    for (let c = 0; c < 3; ++c) out[4 * p + c] = 128 + 60 * Math.sin(p / 97 + c) + sigma * gaussian(random);
    out[4 * p + 3] = 255;
  }
  return out;
}

test('passes grow by RATIO up to the server bound of samples × pixels', () => {
  assert.deepEqual(sampleSchedule(320 * 262), [1, 4, 16, 64, 200]);
  assert.deepEqual(sampleSchedule(64 * 64), [1, 4, 16, 64, 256]);
  assert.deepEqual(sampleSchedule(4096 * 4096), [1]);
  for (const pixels of [1, 1000, 320 * 240, 1e6]) {
    const schedule = sampleSchedule(pixels);
    assert.ok(schedule.at(-1) * pixels <= 2 ** 24 || schedule.at(-1) === 1);
    schedule.slice(1, -1).forEach((s, i) => assert.equal(s, schedule[i] * RATIO));
  }
});

test('the noise estimate bounds the newer pass\'s noise from above, within 1.5×', () => {
  const random = seeded(20261129);
  for (let trial = 0; trial < 20; ++trial) {
    const sigma = 1 + 10 * random(); // the older pass's noise, levels
    const older = noisy(random, 20000, sigma);
    const newer = noisy(random, 20000, sigma / Math.sqrt(RATIO));
    const estimate = noiseLevels(older, newer);
    const truth = sigma / Math.sqrt(RATIO);
    assert.ok(estimate >= 0.95 * truth && estimate <= 1.5 * truth, `sigma ${sigma}: ${estimate} vs ${truth}`);
  }
  const same = noisy(seeded(1), 1000, 3);
  assert.equal(noiseLevels(same, same), 0);
  assert.ok(0 < CONVERGED_LEVELS);
  assert.equal(noiseLevels(same, same.slice(4)), null);
});
