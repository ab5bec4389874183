#!/usr/bin/env node
// The view's look (README "The page"), in Debian's chromium: the automatic exposure is kept per
// scene, so after another client moved an object a reload shows the same exposure (it used to be
// taken again from the moved mesh); the user's offset (the exposure slider, in stops) doubles the
// colours per stop and survives a reload; a light made 4× brighter takes the automatic exposure
// again (a quarter) instead of blowing the room to white; the legend says what the colours are;
// PNG downloads the server's render at the view's size, or at a chosen one.
//
// usage: node tests/web/exposure_e2e.mjs --penumbra build/penumbra [--scene scenes/cornell.scene.json]
import fs from 'node:fs';
import path from 'node:path';

import { check, repo, runWithServerAndBrowser, sleep, usageOnHelp } from './harness.mjs';
import { openPage, serverScene } from './page_actions.mjs';

const defaults = { penumbra: path.join(repo, 'build', 'penumbra'), scene: path.join(repo, 'scenes', 'cornell.scene.json'), startupSeconds: 120 };

const exposure = (page) => page.evaluate(() => window.penumbra.exposure());
async function settle(page) {
  await sleep(150);
  await page.evaluate(() => window.penumbra.idle());
}
async function postFrame(base, sceneId, edits) {
  const response = await fetch(`${base}/api/scenes/${sceneId}/edits`, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify({ edits }) });
  if (!response.ok) throw new Error(`POST edits: ${response.status} ${await response.text()}`);
  return response.json();
}
async function waitVersion(page, version) {
  await page.waitForFunction((v) => window.penumbra.state().version >= v, version, { timeout: 30000 });
  await settle(page);
}
async function reload(page) {
  await page.reload({ waitUntil: 'domcontentloaded' });
  await page.waitForFunction(() => window.penumbra && window.penumbra.state().ready, null, { timeout: 60000 });
  await settle(page);
}
// The floor's displayed colours summed (its first face).
const floorSum = (page) => page.evaluate(() => window.penumbra.displayColours('floor', 0).colours.reduce((a, b) => a + b, 0));

// PNG width and height from its IHDR chunk.
const pngSize = (bytes) => [bytes.readUInt32BE(16), bytes.readUInt32BE(20)];

async function downloadPng(page, size) {
  await page.selectOption('#png-size', size);
  const [download] = await Promise.all([page.waitForEvent('download', { timeout: 60000 }), page.click('#download-png')]);
  return pngSize(fs.readFileSync(await download.path()));
}

async function main() {
  const args = usageOnHelp(process.argv, defaults, 'node tests/web/exposure_e2e.mjs --penumbra build/penumbra [--scene FILE]');
  await runWithServerAndBrowser(args, async ({ browser, url, base, sceneId }) => {
    const { page, pageErrors } = await openPage(browser, url);
    await settle(page);
    const first = await exposure(page);
    const legend = await page.textContent('#look-legend');
    check(/ambient/.test(legend) && /not black/.test(legend) && /exposure/.test(legend), 'the legend says what the colours are (ambient: no black faces)', legend);

    // A light 4× brighter: the automatic exposure is taken again (a quarter), the look stays.
    const scene = (await serverScene(base, sceneId)).scene;
    const before = await floorSum(page);
    const light = scene.lights[0];
    const brighter = await postFrame(base, sceneId, [{ op: 'set_light', id: light.id, radiance: light.radiance.map((x) => 4 * x) }]);
    await waitVersion(page, brighter.version);
    const after = await exposure(page);
    const look = await floorSum(page);
    check(Math.abs(after.auto * 4 / first.auto - 1) < 1e-6 && Math.abs(look / before - 1) < 1e-3,
      'a 4× brighter light takes the exposure again: a quarter, the floor as bright as before', JSON.stringify({ first, after, before, look }));

    // Another client moves the tall block: a reload keeps the scene's exposure.
    const block = scene.objects.find((o) => o.id === 'tall_block');
    const moved = { ...(block.transform || {}), translate: [...((block.transform || {}).translate || [0, 0, 0])] };
    moved.translate[0] += 0.1;
    const { version } = await postFrame(base, sceneId, [{ op: 'move', id: 'tall_block', transform: moved }]);
    await waitVersion(page, version);
    await reload(page);
    const again = await exposure(page);
    check(again.auto === after.auto && again.ev === 0, 'after an edit and a reload the automatic exposure is the same', JSON.stringify({ after, again }));

    // One stop up: the colours double (below white) and the setting survives a reload.
    const dim = await floorSum(page);
    await page.$eval('#exposure', (input) => { input.value = '1'; input.dispatchEvent(new Event('input')); });
    await settle(page);
    const up = await exposure(page);
    const bright = await floorSum(page);
    check(up.ev === 1 && up.exposure === 2 * up.auto && bright > 1.5 * dim, 'one stop up doubles the exposure and brightens the floor',
      JSON.stringify({ up, dim, bright }));
    await reload(page);
    const kept = await exposure(page);
    const slider = await page.inputValue('#exposure');
    check(kept.ev === 1 && kept.auto === after.auto && slider === '1' && /\+1\.00 EV/.test(await page.textContent('#exposure-value')),
      'the offset is kept for the scene after a reload', JSON.stringify({ kept, slider }));
    await page.click('#exposure-auto');
    await settle(page);
    check((await exposure(page)).ev === 0, 'Auto puts the offset back to 0');

    // PNG: the server's render at the view's size, or the one chosen.
    const view = await page.evaluate(() => { const c = document.querySelector('#viewport canvas'); return [c.width, c.height]; });
    const viewPng = await downloadPng(page, 'view');
    check(viewPng[0] === view[0] && viewPng[1] === view[1], 'PNG at the view\'s size (not the thumbnail)', JSON.stringify({ view, viewPng }));
    const hd = await downloadPng(page, '1280x720');
    check(hd[0] === 1280 && hd[1] === 720, 'PNG at a chosen size', JSON.stringify(hd));
    check(pageErrors.length === 0, 'nothing is logged as an error', JSON.stringify(pageErrors));
  });
}

main();
