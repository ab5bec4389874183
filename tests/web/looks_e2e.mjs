#!/usr/bin/env node
// Clean pixels (README "The page"): the page's view is compared with the server's render of the
// same camera and size (GET /image): a "speck" is a page pixel darker by more than 40 (of 255) than
// at least 6 of its 8 neighbours where the server's pixel is not that dark (so the scene's own thin
// shadows and dark edges do not count). Before the stand-ins took their lit mesh's mean colour,
// cubes15's view had ~40 of them (cracks of the lit mesh showing the dark stand-in behind). Also:
// the edges overlay leaves out the umbra-to-lit edges of the strip above the light's plane (the
// blue zig-zag along the walls' tops); a coloured light's polygon is drawn in its colour. (editor_e2e.mjs checks the default camera of an imported file.)
//
// usage: node tests/web/looks_e2e.mjs --penumbra build/penumbra [--scene scenes/cubes15.scene.json] [--specks 10]
import path from 'node:path';

import { check, repo, runWithServerAndBrowser, sleep, usageOnHelp } from './harness.mjs';
import { openPage, pixelsAt } from './page_actions.mjs';

const defaults = { penumbra: path.join(repo, 'build', 'penumbra'), scene: path.join(repo, 'scenes', 'cubes15.scene.json'), specks: 10,
  startupSeconds: 120 };

// In the page: the two PNGs decoded; the specks of `page` that `server` does not have.
function countSpecks({ pageB64, serverB64, contrast }) {
  const decode = async (b64) => {
    const img = new Image();
    img.src = `data:image/png;base64,${b64}`;
    await img.decode();
    const canvas = document.createElement('canvas');
    Object.assign(canvas, { width: img.width, height: img.height });
    const ctx = canvas.getContext('2d');
    ctx.drawImage(img, 0, 0);
    const d = ctx.getImageData(0, 0, img.width, img.height).data;
    const lum = new Float32Array(img.width * img.height);
    for (let i = 0; i < lum.length; ++i) lum[i] = 0.2126 * d[4 * i] + 0.7152 * d[4 * i + 1] + 0.0722 * d[4 * i + 2];
    return { w: img.width, h: img.height, lum };
  };
  return Promise.all([decode(pageB64), decode(serverB64)]).then(([p, s]) => {
    if (p.w !== s.w || p.h !== s.h) return { error: `sizes differ: ${p.w}×${p.h} vs ${s.w}×${s.h}` };
    const specks = [];
    for (let y = 1; y < p.h - 1; ++y) {
      for (let x = 1; x < p.w - 1; ++x) {
        const i = y * p.w + x, v = p.lum[i];
        let brighter = 0;
        for (let dy = -1; dy <= 1; ++dy) for (let dx = -1; dx <= 1; ++dx) if ((dx || dy) && p.lum[i + dy * p.w + dx] > v + contrast) ++brighter;
        if (brighter >= 6 && s.lum[i] > v + contrast) specks.push([x, y]);
      }
    }
    return { specks: specks.length, examples: specks.slice(0, 8), size: [p.w, p.h] };
  });
}

async function specks(page, sceneId, limit) {
  await page.evaluate(() => window.penumbra.idle());
  await sleep(300);
  const rect = await page.evaluate(() => document.querySelector('#viewport canvas').getBoundingClientRect().toJSON());
  const shot = await page.screenshot({ clip: rect });
  const serverB64 = await page.evaluate(async ({ sceneId, width, height }) => {
    const params = new URLSearchParams({ width, height, ...window.penumbra.cameraQuery() });
    const bytes = new Uint8Array(await (await fetch(`/api/scenes/${sceneId}/image?${params}`)).arrayBuffer());
    let text = '';
    for (let i = 0; i < bytes.length; i += 0x8000) text += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
    return btoa(text);
  }, { sceneId, width: Math.round(rect.width), height: Math.round(rect.height) });
  const r = await page.evaluate(countSpecks, { pageB64: shot.toString('base64'), serverB64, contrast: 40 });
  check(!r.error && r.specks <= limit, `the page's view has at most ${limit} dark specks the server's render of the same camera has not`, JSON.stringify(r));
  console.log(`     specks: ${r.specks} in ${r.size}`);
}

// The overlay's edges on the walls above the light's plane (where no light reaches).
async function wallTops(page) {
  await page.check('#toggle-edges');
  const r = await page.evaluate(() => window.penumbra.overlayEdgesAbove(2.985));
  await page.uncheck('#toggle-edges');
  check(r.total > 0 && r.above === 0, 'the edges overlay draws nothing in the unlit strip above the light\'s plane', JSON.stringify(r));
}

// A coloured light is drawn in its colour (issue 37: the polygon stayed white): the light's radiance
// set to orange through the API, the page follows, and the pixel at the light's centre is orange.
async function lightColour(page, base, sceneId) {
  const light = (await (await fetch(`${base}/api/scenes/${sceneId}`)).json()).scene.lights[0];
  const radiance = [light.radiance[0], 0.5 * light.radiance[0], 0.1 * light.radiance[0]];
  const version = (await page.evaluate(() => window.penumbra.state().version)) + 1;
  await fetch(`${base}/api/scenes/${sceneId}/edits`, { method: 'POST', headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify({ edits: [{ op: 'set_light', id: light.id, radiance }] }) });
  await page.waitForFunction((v) => window.penumbra.state().version >= v, version, { timeout: 30000 }).catch(() => {});
  await page.keyboard.press('a'); // the whole scene, the ceiling's light in view
  await sleep(300);
  const at = await page.evaluate((id) => window.penumbra.screenOf(window.penumbra.lightCentre(id)), light.id);
  const [[r, g, b]] = await pixelsAt(page, [at]);
  check(r > 200 && g > 0.5 * r && g < 0.85 * r && b < 0.5 * r, 'a coloured light\'s polygon is drawn in its colour (orange)', JSON.stringify({ r, g, b }));
}

async function main() {
  const args = usageOnHelp(process.argv, defaults, 'node tests/web/looks_e2e.mjs --penumbra build/penumbra [--scene FILE] [--specks N]');
  await runWithServerAndBrowser(args, async ({ browser, url, base, sceneId }) => {
    const { page } = await openPage(browser, url);
    await specks(page, sceneId, args.specks);
    await wallTops(page);
    await lightColour(page, base, sceneId);
  });
}

main();
