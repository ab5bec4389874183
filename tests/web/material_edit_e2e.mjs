#!/usr/bin/env node
// A material's colour and type edited in the inspector (README "The page"), in Debian's chromium, on
// scenes/materials: white_box's colour picked is one `set_material` (one version, no shadow work:
// no receiver changed, no rebuild), the server holds the new albedo, the page's mesh on the box
// turns red and one undo gives both back; a material two objects share is left to the other one: the
// edited object gets its own copy (here with a new type), and undo puts it back in the shared one.
//
// usage: node tests/web/material_edit_e2e.mjs --penumbra build/penumbra [--scene scenes/materials.scene.json]
import path from 'node:path';

import { check, repo, runWithServerAndBrowser, sleep, usageOnHelp } from './harness.mjs';
import { openPage, serverScene } from './page_actions.mjs';

const defaults = { penumbra: path.join(repo, 'build', 'penumbra'), scene: path.join(repo, 'scenes', 'materials.scene.json'), startupSeconds: 120 };
const RED = '#cc2200';

async function settle(page) {
  await sleep(80);
  await page.evaluate(() => window.penumbra.idle());
}

// The page's mean displayed red and green over an object's lit mesh.
async function meanRedGreen(page, object) {
  return page.evaluate((id) => {
    let r = 0, g = 0;
    for (let face = 0; face < 6; ++face) {
      const { colours } = window.penumbra.displayColours(id, face);
      for (let i = 0; i < colours.length; i += 3) { r += colours[i]; g += colours[i + 1]; }
    }
    return { r, g };
  }, object);
}

// Another client's material edit (a POST from outside the page): the page's mesh takes the new
// colour once it follows the version, and the old one when the other client sets it back.
async function anotherClients(page, base, sceneId, colours) {
  const setWhite = async (albedo) => {
    const res = await fetch(`${base}/api/scenes/${sceneId}/edits`, { method: 'POST', headers: { 'Content-Type': 'application/json' },
      body: JSON.stringify({ edits: [{ op: 'set_material', id: 'white', material: { albedo } }] }) });
    const version = (await res.json()).version;
    await page.waitForFunction((v) => window.penumbra.state().version >= v, version, { timeout: 20000 });
    await settle(page);
  };
  const white = (await serverScene(base, sceneId)).scene.materials.white.albedo;
  await setWhite([0.8, 0.1, 0]);
  const red = await meanRedGreen(page, 'white_box');
  await setWhite(white);
  const back = await meanRedGreen(page, 'white_box');
  check(red.g / red.r < 0.3 * (colours.g / colours.r) && Math.abs(back.g - colours.g) < 1e-3 * colours.g,
    'another client\'s material edit recolours the box in the view, and its undoing colours it back', JSON.stringify({ colours, red, back }));
}

async function inspect(page, id) {
  await page.evaluate((sid) => window.penumbra.select(sid), id);
  await page.waitForSelector('#inspector input[data-key="albedo"]', { timeout: 5000 });
}

async function setColour(page, hex) {
  await page.$eval('#inspector input[data-key="albedo"]', (input, value) => {
    input.value = value;
    input.dispatchEvent(new Event('change'));
  }, hex);
  await settle(page);
}

async function ownMaterial(page, base, sceneId) {
  const before = await serverScene(base, sceneId);
  await page.keyboard.press('Escape');
  await inspect(page, 'gold_box');
  await page.selectOption('#inspector select[data-key="material"]', 'white');
  await settle(page);
  await inspect(page, 'white_box');
  const matte = await meanRedGreen(page, 'white_box');
  await page.selectOption('#inspector select[data-key="type"]', 'conductor');
  await settle(page);
  const metal = await meanRedGreen(page, 'white_box');
  check(Math.abs(metal.r / matte.r - 0.25) < 0.01, 'a metal is drawn at a quarter of its colour (its reflection on top, as the server renders it)',
    JSON.stringify({ matte, metal }));
  const after = await serverScene(base, sceneId);
  const object = (s, id) => s.scene.objects.find((o) => o.id === id);
  const own = object(after, 'white_box').material;
  check(own && own !== 'white' && after.scene.materials[own].type === 'conductor' && object(after, 'gold_box').material === 'white'
    && JSON.stringify(after.scene.materials.white) === JSON.stringify(before.scene.materials.white),
  'a type chosen for an object whose material is shared gives it its own copy; the shared one is unchanged',
  JSON.stringify({ own, material: after.scene.materials[own], white: after.scene.materials.white }));
  await page.keyboard.press('Control+z');
  await settle(page);
  const undone = await serverScene(base, sceneId);
  check(object(undone, 'white_box').material === 'white', 'one undo puts the object back in the shared material',
    String(object(undone, 'white_box').material));
}

async function main() {
  const args = usageOnHelp(process.argv, defaults, 'node tests/web/material_edit_e2e.mjs --penumbra build/penumbra [--scene FILE]');
  await runWithServerAndBrowser(args, async ({ browser, url, base, sceneId }) => {
    const { page, pageErrors } = await openPage(browser, url);
    await inspect(page, 'white_box');
    const shown = await page.inputValue('#inspector input[data-key="albedo"]');
    check(shown === '#cccccc', 'the inspector shows the material\'s colour', shown);
    const before = await serverScene(base, sceneId);
    const colours = await meanRedGreen(page, 'white_box');
    await setColour(page, RED);
    const after = await serverScene(base, sceneId);
    const albedo = after.scene.materials.white.albedo;
    const expected = [0xcc / 255, 0x22 / 255, 0];
    check(after.version === before.version + 1 && albedo.every((x, c) => x === expected[c]),
      'a picked colour is one version with the material\'s new albedo', JSON.stringify({ albedo, version: after.version }));
    const frame = (await (await fetch(`${base}/api/scenes/${sceneId}/stats`)).json()).last_frame;
    check(frame && !frame.full_rebuild && frame.tree_rebuilds === 0 && frame.changed_receivers_count === 0,
      'a new colour does no shadow work (no receiver changed, no rebuild)', JSON.stringify(frame && { f: frame.full_rebuild, t: frame.tree_rebuilds, c: frame.changed_receivers_count }));
    const red = await meanRedGreen(page, 'white_box');
    check(colours.r > 0 && red.g / red.r < 0.3 * (colours.g / colours.r) && Math.abs(red.r / colours.r - 1) < 1e-3,
      'the box\'s mesh turns red in the view', JSON.stringify({ colours, red }));
    await page.keyboard.press('Control+z');
    await settle(page);
    const undone = await serverScene(base, sceneId);
    const back = await meanRedGreen(page, 'white_box');
    check(JSON.stringify(undone.scene.materials.white) === JSON.stringify(before.scene.materials.white)
      && Math.abs(back.r - colours.r) < 1e-3 * colours.r && Math.abs(back.g - colours.g) < 1e-3 * colours.g,
    'one undo gives the colour back on the server and in the view', JSON.stringify({ white: undone.scene.materials.white, back }));
    await anotherClients(page, base, sceneId, colours);
    await ownMaterial(page, base, sceneId);
    check(pageErrors.length === 0, 'nothing is logged as an error', JSON.stringify(pageErrors));
  });
}

main();
