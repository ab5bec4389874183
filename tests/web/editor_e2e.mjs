#!/usr/bin/env node
// The page as an editor (README "The page"), in Debian's chromium with real keys and clicks: add a
// box (B), duplicate (Ctrl+D), delete (Delete) and undo them; typed transforms; scale mode (R) and
// snapping; typed values sent exactly, fields at full precision on focus and following a drag;
// focus (F), frame all (A), camera home (H); the "?" sheet; a light selected (its edits:
// light_e2e.mjs); downloads of the scene JSON and GLB; reset to the file; an imported OBJ's pivots
// at their objects' centres, its walls locked and its default camera on its open side; the scene
// list and deleting a scene from it.
//
// usage: node tests/web/editor_e2e.mjs --penumbra build/penumbra [--scene scenes/cubes15.scene.json]
import fs from 'node:fs';
import path from 'node:path';

import { check, repo, runWithServerAndBrowser, sleep, usageOnHelp } from './harness.mjs';
import { clickObject, dragXHandle, openPage, serverScene } from './page_actions.mjs';

const defaults = { penumbra: path.join(repo, 'build', 'penumbra'), scene: path.join(repo, 'scenes', 'cubes15.scene.json'), startupSeconds: 120 };
const close = (a, b, eps = 1e-6) => a.length === b.length && a.every((x, k) => Math.abs(x - b[k]) < eps);
const ids = async (base, sceneId) => (await serverScene(base, sceneId)).scene.objects.map((o) => o.id);
const state = (page) => page.evaluate(() => window.penumbra.state());
const idle = (page) => page.evaluate(() => window.penumbra.idle());

async function press(page, key) {
  await page.keyboard.press(key);
  await sleep(80);
  await idle(page);
}

async function structural(page, base, sceneId) {
  await press(page, 'b');
  const afterAdd = await ids(base, sceneId);
  check(afterAdd.includes('box') && (await state(page)).selected === 'box', 'B adds a box on the server and selects it', JSON.stringify(afterAdd));
  await press(page, 'Control+d');
  const afterDuplicate = await ids(base, sceneId);
  check(afterDuplicate.includes('box_copy') && (await state(page)).selected === 'box_copy', 'Ctrl+D duplicates the selection', JSON.stringify(afterDuplicate));
  await press(page, 'Delete');
  check(!(await ids(base, sceneId)).includes('box_copy') && (await state(page)).selected === null, 'Delete removes the selection');
  await press(page, 'Control+z');
  check((await ids(base, sceneId)).includes('box_copy'), 'undo brings the deleted object back');
  await press(page, 'Control+z');
  await press(page, 'Control+z');
  const back = await ids(base, sceneId);
  check(!back.includes('box') && !back.includes('box_copy'), 'two more undos remove the duplicate and the box', JSON.stringify(back));
  await press(page, 'Control+Shift+z');
  check((await ids(base, sceneId)).includes('box'), 'redo adds the box again');
  await press(page, 'Control+z');
}

// The floor (static) is locked until "unlock walls and floors" is ticked.
async function locked(page) {
  const clickFloor = async () => {
    const screen = await page.evaluate(() => window.penumbra.screenOf([-0.3, 0, 0.5]));
    await page.mouse.click(screen.x, screen.y);
    await sleep(100);
    return (await state(page)).selected;
  };
  const before = await clickFloor();
  await page.check('#unlock-shell');
  const unlocked = await clickFloor();
  await page.uncheck('#unlock-shell');
  check(before === null && unlocked === 'floor' && (await state(page)).selected === null,
    'the floor is locked (a click selects nothing) until unlocked', JSON.stringify({ before, unlocked }));
  // The outliner: a click on an item selects it; the floor's item is locked.
  await page.click('.outliner-box summary');
  await page.click('#outliner li[data-id="cube_7"]');
  const picked = (await state(page)).selected;
  const floorLocked = await page.evaluate(() => document.querySelector('#outliner li[data-id="floor"]').classList.contains('locked'));
  check(picked === 'cube_7' && floorLocked, 'the outliner selects cube_7; its floor item is locked', JSON.stringify({ picked, floorLocked }));
  await press(page, 'Escape');
}

async function inspector(page, base, sceneId) {
  check((await clickObject(page, 'cube_3')) === 'cube_3', 'a click selects cube_3');
  const field = page.locator('#inspector input[data-key="translate.0"]');
  await field.fill('-1.25');
  await field.press('Enter');
  await idle(page);
  const moved = (await serverScene(base, sceneId)).scene.objects.find((o) => o.id === 'cube_3').transform;
  check(Math.abs(moved.translate[0] + 1.25) < 1e-9, 'a typed x moves the object on the server', JSON.stringify(moved.translate));
  // The history survives a reload: undo there puts the cube back, redo moves it again.
  await page.reload({ waitUntil: 'domcontentloaded' });
  await page.waitForFunction(() => window.penumbra && window.penumbra.state().ready, null, { timeout: 60000 });
  const undoEnabled = await page.evaluate(() => !document.getElementById('undo').disabled);
  await press(page, 'Control+z');
  const undone = (await serverScene(base, sceneId)).scene.objects.find((o) => o.id === 'cube_3').transform.translate[0];
  await press(page, 'Control+Shift+z');
  const redone = (await serverScene(base, sceneId)).scene.objects.find((o) => o.id === 'cube_3').transform.translate[0];
  check(undoEnabled && Math.abs(undone - 1.672914011131045) < 1e-9 && Math.abs(redone + 1.25) < 1e-9,
    'the undo history is kept across a reload', JSON.stringify({ undoEnabled, undone, redone }));
  check((await clickObject(page, 'cube_3')) === 'cube_3', 'a click selects cube_3 again');
  await press(page, 'r');
  check((await page.evaluate(() => window.penumbra.gizmoMode())) === 'scale', 'R switches the gizmo to scale');
  await press(page, 'w');
  await page.check('#snap');
  await dragXHandle(page, 0.37, 8, 40);
  await idle(page);
  const snapped = (await serverScene(base, sceneId)).scene.objects.find((o) => o.id === 'cube_3').transform.translate[0];
  check(Math.abs(snapped / 0.1 - Math.round(snapped / 0.1)) < 1e-6 && Math.abs(snapped + 1.25) > 0.05,
    'with snap on a drag lands on the 0.1 m grid', String(snapped));
  await page.uncheck('#snap');
}

// A typed field changes that value only, exactly as typed (issue 37: the other fields went back
// rounded to 4 decimals, 0.2265625 as 0.2266, and rotations through a quaternion); a focused field
// shows the whole number; the fields follow a drag while it goes.
async function exactFields(page, base, sceneId) {
  const id = 'cube_4';
  const transform = async () => (await serverScene(base, sceneId)).scene.objects.find((o) => o.id === id).transform;
  check((await clickObject(page, id)) === id, `a click selects ${id}`);
  const before = await transform();
  const field = (key) => page.locator(`#inspector input[data-key="${key}"]`);
  await field('translate.0').fill('-1.123456789012345');
  await field('translate.0').press('Enter');
  await idle(page);
  const after = await transform();
  const expected = { ...before, translate: [-1.123456789012345, ...before.translate.slice(1)] };
  check(JSON.stringify(after) === JSON.stringify(expected), 'a typed x reaches the server exactly as typed, every other value unchanged',
    JSON.stringify({ before, after }));
  const shown = await field('translate.2').inputValue();
  await field('translate.2').focus();
  const focused = await field('translate.2').inputValue();
  await field('translate.2').blur();
  await idle(page);
  check(Number(focused) === before.translate[2] && shown !== focused && JSON.stringify(await transform()) === JSON.stringify(after),
    'a focused field shows the whole number; leaving it untyped sends nothing', JSON.stringify({ shown, focused }));
  const startX = await field('translate.0').inputValue();
  let midway = null;
  await press(page, 'w');
  await dragXHandle(page, 0.5, 8, 60, async () => { midway = await field('translate.0').inputValue(); });
  await idle(page);
  const dropped = (await transform()).translate[0];
  check(midway !== null && Number(midway) > Number(startX) + 0.05 && Math.abs(Number(await field('translate.0').inputValue()) - dropped) < 1e-4,
    'the fields follow a drag while it goes, and show the server\'s value after it', JSON.stringify({ startX, midway, dropped }));
  await press(page, 'Control+z');
  await press(page, 'Control+z');
  check(JSON.stringify(await transform()) === JSON.stringify(before), 'two undos give the file\'s transform back exactly', JSON.stringify(await transform()));
  await press(page, 'Escape');
}

async function camera(page) {
  const target = () => page.evaluate(() => window.penumbra.cameraQuery().target.split(',').map(Number));
  await press(page, 'f');
  const centre = await page.evaluate(() => window.penumbra.objectCentre('cube_3'));
  check(close(await target(), centre, 1e-6), 'F turns the camera to the selection\'s centre', `${await target()} vs ${centre}`);
  await press(page, 'a');
  const all = await page.evaluate(() => window.penumbra.sceneCentre());
  check(close(await target(), all, 1e-6), 'A frames the whole scene', `${await target()} vs ${all}`);
  await press(page, 'h');
  const home = await page.evaluate(() => window.penumbra.cameraQuery());
  check(home.position.split(',').map(Number).every((x, k) => Math.abs(x - [0, 1.6, 4.493416490252569][k]) < 1e-9), 'H puts the scene\'s camera back', home.position);
  await press(page, '?');
  const help = await page.evaluate(() => ({ shown: getComputedStyle(document.getElementById('help')).display !== 'none', rows: document.querySelectorAll('#help tr').length }));
  await press(page, 'Escape');
  const closed = await page.evaluate(() => getComputedStyle(document.getElementById('help')).display === 'none');
  check(help.shown && help.rows >= 8 && closed, '? shows the shortcut sheet, Esc closes it', JSON.stringify(help));
}

async function light(page) {
  await press(page, 'a'); // the scene's camera leaves the ceiling's light just out of view
  const centre = await page.evaluate(() => window.penumbra.lightCentre('light'));
  const screen = await page.evaluate((p) => window.penumbra.screenOf(p), centre);
  await page.mouse.click(screen.x, screen.y);
  await sleep(100);
  const text = await page.evaluate(() => document.getElementById('inspector').textContent);
  check((await state(page)).selected === 'light:light' && /radiance/.test(text) && /intensity/.test(text),
    'a click on the light selects it; the inspector shows it (its edits: light_e2e.mjs)', text);
  await press(page, 'Escape');
}

async function downloads(page, base, sceneId) {
  const save = async (button) => {
    const [download] = await Promise.all([page.waitForEvent('download', { timeout: 20000 }), page.click(button)]);
    return { name: download.suggestedFilename(), bytes: fs.readFileSync(await download.path()) };
  };
  const json = await save('#download-json');
  const scene = JSON.parse(json.bytes.toString());
  const served = (await serverScene(base, sceneId)).scene;
  check(/\.scene\.json$/.test(json.name) && JSON.stringify(scene) === JSON.stringify(served), 'Scene JSON downloads the served scene', json.name);
  const glb = await save('#download-glb');
  check(/\.glb$/.test(glb.name) && glb.bytes.subarray(0, 4).toString() === 'glTF', 'GLB downloads a binary glTF', `${glb.name} ${glb.bytes.length} bytes`);
}

async function reset(page, base, sceneId, original) {
  await page.click('#reset-scene');
  await sleep(100);
  await idle(page);
  const now = (await serverScene(base, sceneId)).scene;
  const same = JSON.stringify(now.objects) === JSON.stringify(original.objects);
  check(same, 'Reset to file brings every object back to the file\'s place');
}

async function imported(browser, base, sceneId) {
  const data = path.join(repo, 'tests', 'interchange', 'data');
  const form = new FormData();
  form.append('file', new Blob([fs.readFileSync(path.join(data, 'cornell_mm.obj'))]), 'cornell_mm.obj');
  form.append('mtl', new Blob([fs.readFileSync(path.join(data, 'cornell_mm.mtl'))]), 'cornell_mm.mtl');
  const created = await (await fetch(`${base}/api/scenes?scale=0.001`, { method: 'POST', body: form })).json();
  const { page } = await openPage(browser, `${base}/?scene=${created.id}`);
  const r = await page.evaluate(() => window.penumbra.pivots());
  const offCentre = r.filter((o) => !o.locked && Math.hypot(...o.pivot.map((x, k) => x - o.centre[k])) > 1e-6);
  const walls = r.filter((o) => o.locked).length;
  check(offCentre.length === 0 && r.some((o) => !o.locked), 'an imported object turns about its own centre (gizmo on it, not at the origin)', JSON.stringify(offCentre));
  check(walls >= 4 && walls < r.length, 'an imported room\'s walls and floor are locked, its blocks are not', JSON.stringify(r.map((o) => [o.id, o.locked])));
  const view = await page.evaluate(() => window.penumbra.backFacingShellAhead());
  check(view.shells > 0 && view.blocking === 0, 'an imported room without a camera is seen from its open side (no wall\'s back in the way)', JSON.stringify(view));
  // The scene list: both scenes; delete this one (after the confirm) from it.
  const listed = await page.evaluate(() => [...document.querySelectorAll('#scene-list li')].map((li) => li.dataset.scene));
  check(listed.includes(sceneId) && listed.includes(created.id), 'the scene list shows the server\'s scenes', JSON.stringify(listed));
  page.once('dialog', (dialog) => dialog.accept());
  await Promise.all([page.waitForURL((url) => url.searchParams.get('scene') === sceneId, { timeout: 20000 }),
    page.click(`#scene-list li[data-scene="${created.id}"] button[data-action="delete"]`)]);
  const left = (await (await fetch(`${base}/api/scenes`)).json()).scenes.map((s) => s.id);
  check(!left.includes(created.id), 'Delete in the list removes the scene from the server and opens another', JSON.stringify(left));
  await page.close();
}

async function main() {
  const args = usageOnHelp(process.argv, defaults, 'node tests/web/editor_e2e.mjs --penumbra build/penumbra [--scene FILE]');
  await runWithServerAndBrowser(args, async ({ browser, url, base, sceneId }) => {
    const original = (await serverScene(base, sceneId)).scene;
    const { page, pageErrors } = await openPage(browser, url);
    await structural(page, base, sceneId);
    await locked(page);
    await inspector(page, base, sceneId);
    await camera(page);
    await exactFields(page, base, sceneId);
    await light(page);
    await downloads(page, base, sceneId);
    await reset(page, base, sceneId, original);
    const final = await state(page);
    check(!final.bannerVisible && pageErrors.length === 0, 'no error shown or logged', JSON.stringify([final.errors, pageErrors]));
    await imported(browser, base, sceneId);
  });
}

main();
