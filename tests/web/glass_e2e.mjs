#!/usr/bin/env node
// Glass in the live view (docs/SERVER.md "Microfacet materials"), in Debian's chromium, on
// scenes/materials: the glass block reads as glass, as in the server's render: the back wall seen
// through it keeps the wall's hue and about its brightness beside the block (an opaque block shows
// its own grey). white_box's type set to dielectric in the inspector is one version on the server
// and turns the box to glass in the view (what is behind it shows through: its pixel comes near the
// wall beside it); one undo gives the material back on the server and the opaque box back in the
// view, pixel for pixel.
//
// usage: node tests/web/glass_e2e.mjs --penumbra build/penumbra [--scene scenes/materials.scene.json]
import path from 'node:path';

import { check, repo, runWithServerAndBrowser, usageOnHelp } from './harness.mjs';
import { openPage, pixelsAt, serverScene } from './page_actions.mjs';

const defaults = { penumbra: path.join(repo, 'build', 'penumbra'), scene: path.join(repo, 'scenes', 'materials.scene.json'), startupSeconds: 120 };

const distance = (a, b) => Math.hypot(...a.map((x, c) => x - b[c]));
const luminance = ([r, g, b]) => 0.2126 * r + 0.7152 * g + 0.0722 * b;

// Waits until the page is idle and has drawn a frame after it (the view shows what it holds).
async function drawn(page) {
  await page.evaluate(() => window.penumbra.idle());
  await page.evaluate(() => window.penumbra.drawFrame());
}

// Looks from `position` at `target` and gives object `id`'s rectangle on the page (its world box's
// corners projected).
async function viewOf(page, id, position, target) {
  await page.evaluate(({ position, target }) => window.penumbra.lookFrom(position, target), { position, target });
  await drawn(page);
  return page.evaluate((id) => {
    const { min, max } = window.penumbra.objectBox(id);
    const corners = [];
    for (const x of [min[0], max[0]]) for (const y of [min[1], max[1]]) for (const z of [min[2], max[2]]) corners.push([x, y, z]);
    const points = corners.map((p) => window.penumbra.screenOf(p));
    const xs = points.map((p) => p.x), ys = points.map((p) => p.y);
    return { left: Math.min(...xs), right: Math.max(...xs), top: Math.min(...ys), bottom: Math.max(...ys) };
  }, id);
}

// The scene's glass block in front of the back wall: through its upper right part the wall shows,
// and beside it (right of the block, same row) the wall itself.
async function glassBlock(page) {
  const r = await viewOf(page, 'glass_block', [0.9, 0.45, 4], [0.9, 0.45, -2]);
  const width = r.right - r.left, y = r.top + 0.25 * (r.bottom - r.top);
  const [through, beside] = await pixelsAt(page, [{ x: r.left + 0.8 * width, y }, { x: r.right + 0.1 * width, y }]);
  const hue = (p) => p[0] / Math.max(1, p[1]);
  check(beside[0] > 1.4 * beside[1] && Math.abs(hue(through) / hue(beside) - 1) < 0.15
    && Math.abs(luminance(through) / luminance(beside) - 1) < 0.25,
  'the glass block reads as glass: the back wall seen through it has the wall\'s hue and about its brightness beside it',
  JSON.stringify({ through, beside, rect: r }));
  console.log(`     through the glass block ${through}, the wall beside it ${beside}`);
}

// white_box to glass from the inspector's type, and back by one undo.
async function boxToGlass(page, base, sceneId) {
  const r = await viewOf(page, 'white_box', [0, 0.35, 0], [0.6, 0.3, -1.6]);
  const points = [{ x: (r.left + r.right) / 2, y: (r.top + r.bottom) / 2 }, { x: r.left - 0.25 * (r.right - r.left), y: (r.top + r.bottom) / 2 }];
  const [opaque, wall] = await pixelsAt(page, points);
  const before = await serverScene(base, sceneId);
  await page.evaluate(() => window.penumbra.select('white_box'));
  await page.waitForSelector('#inspector select[data-key="type"]', { timeout: 5000 });
  await page.selectOption('#inspector select[data-key="type"]', 'dielectric');
  await page.evaluate(() => window.penumbra.idle());
  await page.keyboard.press('Escape'); // no gizmo over the box
  await drawn(page);
  const after = await serverScene(base, sceneId);
  check(after.version === before.version + 1 && after.scene.materials.white.type === 'dielectric',
    'the type chosen is one version: white_box\'s material is a dielectric on the server', JSON.stringify({ version: after.version, white: after.scene.materials.white }));
  const glossy = (await page.evaluate(() => window.penumbra.physicalMaterials())).find((m) => m.id === 'white_box');
  check(glossy && glossy.transmission === 1 && glossy.thickness > 0, 'the view draws white_box as glass (transmission, refracting through its thickness)', JSON.stringify(glossy));
  const [glass] = await pixelsAt(page, points);
  console.log(`     white_box opaque ${opaque}, as glass ${glass}, the wall beside it ${wall}`);
  check(distance(glass, wall) < 0.5 * distance(opaque, wall),
    'what is behind the box shows through it: its pixel is nearer the wall beside it than the opaque box was', JSON.stringify({ opaque, glass, wall }));

  await page.keyboard.press('Control+z');
  await drawn(page);
  const undone = await serverScene(base, sceneId);
  check(JSON.stringify(undone.scene.materials.white) === JSON.stringify(before.scene.materials.white),
    'one undo gives the material back on the server', JSON.stringify(undone.scene.materials.white));
  const glossyAfter = (await page.evaluate(() => window.penumbra.physicalMaterials())).find((m) => m.id === 'white_box');
  const [back] = await pixelsAt(page, points);
  check(!glossyAfter && distance(back, opaque) <= 3, 'and the opaque box in the view, pixel for pixel', JSON.stringify({ opaque, back, glossyAfter }));
}

async function main() {
  const args = usageOnHelp(process.argv, defaults, 'node tests/web/glass_e2e.mjs --penumbra build/penumbra [--scene FILE]');
  await runWithServerAndBrowser(args, async ({ browser, url, base, sceneId }) => {
    const { page, pageErrors } = await openPage(browser, url);
    await page.waitForFunction(() => window.penumbra.physicalMaterials().some((m) => m.id === 'glass_block'), null, { timeout: 60000 });
    await glassBlock(page);
    await boxToGlass(page, base, sceneId);
    const state = await page.evaluate(() => window.penumbra.state());
    check(!state.errors.length && !state.bannerVisible && !pageErrors.length, 'no error shown or logged', JSON.stringify({ errors: state.errors, pageErrors }));
  });
}

main();
