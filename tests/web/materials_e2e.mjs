#!/usr/bin/env node
// Microfacet materials in the page (README "The page"), in Debian's chromium: scenes/materials
// shows its polished floor, brushed gold box and glass block with three.js's MeshPhysicalMaterial
// (metalness, roughness, anisotropy, transmission, ior from the scene's material keys) lit by a
// RectAreaLight matching the scene's light, over the DM's vertex colours; the server render panel
// refines in passes of 1, 4 and 16 samples; dragging the gold box moves it on the server, the
// floor's DM mesh follows and the panel refines again for the new version; a new camera while
// passes run aborts them and refines for the new view; nothing is shown or logged as an error.
//
// usage: node tests/web/materials_e2e.mjs --penumbra build/penumbra [--scene scenes/materials.scene.json]
import path from 'node:path';

import { check, repo, runWithServerAndBrowser, sleep, usageOnHelp } from './harness.mjs';
import { clickObject, dragXHandle, openPage, serverScene } from './page_actions.mjs';

const defaults = { penumbra: path.join(repo, 'build', 'penumbra'), scene: path.join(repo, 'scenes', 'materials.scene.json'), startupSeconds: 120 };
const SAMPLES = [1, 4, 16];
const near = (a, b, eps = 1e-6) => Math.abs(a - b) <= eps;
const state = (page) => page.evaluate(() => window.penumbra.state());
const passes = (page) => page.evaluate(() => window.penumbra.renderPasses());

// Waits until the panel has shown a whole refinement for `version`: passes of 1, 4, 16 samples
// and on (× 4) in order, each with more samples, until one says it converged or reached the
// server's limit. With `rendersAfter`: only images shown after that many renders count (a new
// view's passes).
async function refinedAt(page, version, seconds = 120, rendersAfter = 0) {
  const deadline = Date.now() + seconds * 1000;
  for (;;) {
    const { passes: shown, renders, outcome } = await passes(page);
    const start = shown.findLastIndex((p) => p.samples === 1);
    const run = start < 0 ? [] : shown.slice(start);
    if (renders - rendersAfter >= run.length && run.length >= SAMPLES.length && outcome
        && run.every((p, i) => p.version === version && (i < SAMPLES.length ? p.samples === SAMPLES[i] : p.samples > run[i - 1].samples))) return run;
    if (Date.now() > deadline) return null;
    await sleep(200);
  }
}

function checkMaterials(described) {
  const byId = Object.fromEntries(described.map((d) => [d.id, d]));
  const floor = byId.floor, gold = byId.gold_box, glass = byId.glass_block, lamp = byId.lamp;
  check(floor && floor.kind === 'MeshPhysicalMaterial' && floor.metalness === 1 && near(floor.roughness, Math.sqrt(0.12))
    && near(floor.color[0], (0.25 + 9) / (6.25 + 9)) && floor.additive && floor.transmission === 0,
  'the polished floor is a physical metal (F0 from eta/k, roughness √α) added over its DM colours', JSON.stringify(floor));
  check(gold && gold.metalness === 1 && near(gold.roughness, 0.2) && gold.anisotropy > 0.5 && gold.color[0] > gold.color[2]
    && gold.parent === 'gold_box', 'the brushed gold box is anisotropic gold, in the box\'s holder (drags move it)', JSON.stringify(gold));
  check(glass && glass.transmission === 1 && near(glass.ior, 1.5) && glass.metalness === 0 && !glass.additive,
    'the glass block transmits with ior 1.5', JSON.stringify(glass));
  check(!byId.white_box && !byId.back_wall, 'diffuse objects keep the DM colours alone');
  check(lamp && lamp.kind === 'RectAreaLight' && near(lamp.width, 1.2) && near(lamp.height, 0.8) && lamp.intensity > 0,
    'the scene\'s light is a RectAreaLight of its size', JSON.stringify(lamp));
}

async function main() {
  const args = usageOnHelp(process.argv, defaults, 'node tests/web/materials_e2e.mjs --penumbra build/penumbra [--scene FILE]');
  await runWithServerAndBrowser(args, async ({ browser, url, base, sceneId }) => {
    const { page, pageErrors } = await openPage(browser, url);
    await page.waitForFunction(() => window.penumbra.physicalMaterials().length >= 4, null, { timeout: 60000 });
    checkMaterials(await page.evaluate(() => window.penumbra.physicalMaterials()));
    const floorBefore = await page.evaluate(() => window.penumbra.receiver('floor', 0));
    check(floorBefore && floorBefore.vertexCount > 0, 'the floor\'s DM mesh is held (its colours drawn under the gloss)');

    const first = await refinedAt(page, 0);
    check(first !== null, 'the server render refines in passes of 1, 4, 16 samples and on until converged or at the limit', JSON.stringify((await passes(page)).passes));

    check(await clickObject(page, 'gold_box') === 'gold_box', 'a click selects the gold box');
    const from = (await serverScene(base, sceneId)).scene.objects.find((o) => o.id === 'gold_box').transform.translate;
    await dragXHandle(page, 0.5, 12, 60);
    await page.evaluate(() => window.penumbra.idle());
    const after = await serverScene(base, sceneId);
    const to = after.scene.objects.find((o) => o.id === 'gold_box').transform.translate;
    check(after.version > 0 && to[0] > from[0] + 0.2, 'the drag moved the gold box on the server', JSON.stringify({ from, to, version: after.version }));
    const floorAfter = await page.evaluate(() => window.penumbra.receiver('floor', 0));
    check((await state(page)).version === after.version && floorAfter.sceneVersion > 0,
      'the page holds the new version and the floor\'s DM mesh followed', JSON.stringify({ page: (await state(page)).version, floor: floorAfter.sceneVersion }));
    const refined = await refinedAt(page, after.version);
    check(refined !== null, 'the server render refines again for the new version', JSON.stringify((await passes(page)).passes.slice(-4)));

    // A new view while the passes run: they are aborted and the new view refines.
    const abortedBefore = (await passes(page)).aborted;
    await page.keyboard.press('Escape');
    await page.keyboard.press('a');
    // Waits (not a fixed sleep: a loaded machine is slow) until the new view's passes are
    // being fetched, then changes the view again while they run.
    const waitUntil = Date.now() + 60000;
    while (!(await passes(page)).inFlight && Date.now() < waitUntil) await sleep(20);
    const rendersBefore = (await passes(page)).renders;
    await page.keyboard.press('h');
    const again = await refinedAt(page, after.version, 120, rendersBefore);
    check(again !== null && (await passes(page)).aborted > abortedBefore, 'a new camera aborts the passes left and refines the new view',
      JSON.stringify(await passes(page)));
    const final = await state(page);
    check(!final.errors.length && !final.bannerVisible && !pageErrors.length, 'no error shown or logged', JSON.stringify({ errors: final.errors, pageErrors }));
  });
}

main();
