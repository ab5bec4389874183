#!/usr/bin/env node
// Bounced light in the page (README "The page"), in Debian's chromium, on the Cornell room: the
// image panel's GI toggle (off at first) asks the server for gi=sensors, says it is rendering with
// a seconds counter while the image is on its way, and shows the sensors placed and the GI time; the "bounced light on the mesh" toggle fetches mesh?indirect=1 and the
// mesh's shadows get brighter; after an edit the bake follows the new version; no error shown.
//
// usage: node tests/web/gi_e2e.mjs --penumbra build/penumbra [--scene scenes/cornell.scene.json]
import path from 'node:path';

import { check, repo, runWithServerAndBrowser, sleep, until, usageOnHelp } from './harness.mjs';
import { openPage, serverScene } from './page_actions.mjs';

const defaults = { penumbra: path.join(repo, 'build', 'penumbra'), scene: path.join(repo, 'scenes', 'cornell.scene.json'), startupSeconds: 120 };
const passes = async (page) => (await page.evaluate(() => window.penumbra.renderPasses())).passes;
const baked = (page) => page.evaluate(() => window.penumbra.bakedIndirect());

// The mean display colour (sum of channels) of the floor's vertices in umbra: where only the
// ambient term, or the bounced light, shows.
async function umbraBrightness(page) {
  const { colours, classes } = await page.evaluate(() => window.penumbra.displayColours('floor', 0));
  let sum = 0, n = 0;
  classes.forEach((c, v) => { if (c === 2) { sum += colours[3 * v] + colours[3 * v + 1] + colours[3 * v + 2]; ++n; } });
  return { mean: n ? sum / n : null, n };
}

async function main() {
  const args = usageOnHelp(process.argv, defaults, 'node tests/web/gi_e2e.mjs --penumbra build/penumbra [--scene FILE]');
  await runWithServerAndBrowser(args, async ({ browser, url, base, sceneId }) => {
    const { page, pageErrors } = await openPage(browser, url);
    const images = [], indirectMeshes = [];
    page.on('request', (request) => {
      if (request.url().includes('/image?')) images.push(request.url());
      if (request.url().includes('/mesh?') && request.url().includes('indirect=1')) indirectMeshes.push(request.url());
    });
    check(await until(async () => (await passes(page)).length > 0), 'the server render is shown');
    check(!(await page.isChecked('#toggle-gi')) && !(await page.isChecked('#toggle-indirect')), 'both GI toggles are off at first');
    check(images.every((u) => !u.includes('gi=')), 'without GI the image request has no gi parameter', images.join('\n'));

    // The GI render is held back 2 s on its way: meanwhile the panel says it is rendering, and counts.
    await page.route(/\/image\?.*gi=sensors/, async (route) => { await sleep(2000); await route.continue(); });
    await page.check('#toggle-gi');
    const working = await until(async () => {
      const text = await page.textContent('#render-progress');
      const m = text.match(/^rendering with GI \(sensors\)… (\d+\.\d) s$/);
      return m && Number(m[1]) >= 1 && text;
    }, 10);
    check(working !== null, 'while a GI render runs the panel says so and counts its seconds', await page.textContent('#render-progress'));
    const withGi = await until(async () => (await passes(page)).find((p) => p.giSensors > 0));
    await page.unroute(/\/image\?.*gi=sensors/);
    check(await page.textContent('#render-progress') === '', 'the counter goes when the image comes', await page.textContent('#render-progress'));
    check(withGi !== null && images.some((u) => new URL(u).searchParams.get('gi') === 'sensors'),
      'the GI toggle asks for gi=sensors', JSON.stringify({ passes: await passes(page), images }));
    const info = await page.textContent('#render-info');
    check(withGi && info.includes(`GI: ${withGi.giSensors} sensors`) && /sensors in \d+ ms/.test(info),
      'the panel shows the sensors placed and the GI time', info);

    const before = await umbraBrightness(page);
    check(before.n > 0, 'the floor has vertices in umbra', JSON.stringify(before));
    await page.check('#toggle-indirect');
    const first = await until(async () => { const b = await baked(page); return b.version !== null && b; });
    check(first && first.version === 0 && indirectMeshes.length > 0, 'the toggle fetches mesh?indirect=1 for the held version',
      JSON.stringify({ first, indirectMeshes }));
    const after = await umbraBrightness(page);
    console.log(`     floor umbra, mean colour: ambient ${before.mean.toFixed(4)}, baked bounce ${after.mean.toFixed(4)} (${after.n} vertices); bake ${(first.seconds * 1000).toFixed(0)} ms`);
    check(after.mean > before.mean * 1.05, 'baked bounced light makes the floor brighter in its shadows', JSON.stringify({ before, after }));

    // An edit: the bake follows the new version.
    const scene = (await serverScene(base, sceneId)).scene;
    const block = scene.objects.find((o) => o.id === 'short_block').transform;
    const translate = [block.translate[0] + 0.05, block.translate[1], block.translate[2]];
    const response = await fetch(`${base}/api/scenes/${sceneId}/edits`, { method: 'POST', headers: { 'Content-Type': 'application/json' },
      body: JSON.stringify({ edits: [{ op: 'move', id: 'short_block', transform: { ...block, translate } }] }) });
    const { version } = await response.json();
    const followed = await until(async () => { const b = await baked(page); return b.version === version && b; });
    check(followed !== null, 'after an edit the bake follows the new version', JSON.stringify({ version, baked: await baked(page) }));

    await page.uncheck('#toggle-indirect');
    const off = await umbraBrightness(page);
    check((await baked(page)).version === null && Math.abs(off.mean - before.mean) < 0.02,
      'turned off, the shadows show the ambient term again', JSON.stringify({ before, off }));
    const final = await page.evaluate(() => window.penumbra.state());
    check(!final.errors.length && !final.bannerVisible && !pageErrors.length, 'no error shown or logged', JSON.stringify({ errors: final.errors, pageErrors }));
  });
}

main();
