#!/usr/bin/env node
// Camera and placement (issue 37 item 5), in Debian's chromium with real keys and mouse: F on the
// ceiling light keeps the camera in the room, below the light; orbiting never takes the camera
// under the floor, nor does "Frame all" after it; "+ Light" puts the copy where the view sees it;
// "+ Box" puts the box in view where no other object is; Duplicate puts the copy beside its
// original, touching nothing; a loaded volume lands inside the room and in view even when the
// view's target is at the room's edge.
//
// usage: node tests/web/placement_e2e.mjs --penumbra build/penumbra [--scene scenes/cubes15.scene.json]
import path from 'node:path';

import { check, repo, runWithServerAndBrowser, sleep, usageOnHelp } from './harness.mjs';
import { clickObject, openPage, serverScene } from './page_actions.mjs';

const defaults = { penumbra: path.join(repo, 'build', 'penumbra'), scene: path.join(repo, 'scenes', 'cubes15.scene.json'), startupSeconds: 120 };
const state = (page) => page.evaluate(() => window.penumbra.state());
const idle = (page) => page.evaluate(() => window.penumbra.idle());
const eye = async (page) => (await page.evaluate(() => window.penumbra.cameraQuery())).position.split(',').map(Number);
const target = async (page) => (await page.evaluate(() => window.penumbra.cameraQuery())).target.split(',').map(Number);
// cubes15's room: walls at ±4.7434…, floor at 0, ceiling at 3.
const ROOM = { min: [-4.743416490252569, 0, -4.743416490252569], max: [4.743416490252569, 3, 4.743416490252569] };
const inRoom = (p) => p.every((x, k) => x >= ROOM.min[k] - 1e-9 && x <= ROOM.max[k] + 1e-9);
const boxesOverlap = (a, b) => [0, 1, 2].every((k) => a.min[k] < b.max[k] - 1e-9 && b.min[k] < a.max[k] - 1e-9);

async function press(page, key) {
  await page.keyboard.press(key);
  await sleep(80);
  await idle(page);
}

async function clickButton(page, id) {
  await page.click(`#${id}`);
  await sleep(80);
  await idle(page);
}

// The unlocked objects' boxes other than `id`'s, and whether `id`'s overlaps any.
async function overlapping(page, id) {
  const ids = await page.evaluate(() => window.penumbra.pivots().filter((p) => !p.locked).map((p) => p.id));
  const own = await page.evaluate((id) => window.penumbra.objectBox(id), id);
  const hits = [];
  for (const other of ids) {
    if (other === id) continue;
    if (boxesOverlap(own, await page.evaluate((o) => window.penumbra.objectBox(o), other))) hits.push(other);
  }
  return hits;
}

async function focusOnLight(page) {
  await page.evaluate(() => window.penumbra.select('light:light'));
  await press(page, 'f');
  const at = await eye(page);
  const light = await page.evaluate(() => window.penumbra.lightCentre('light'));
  check(inRoom(at) && at[1] < light[1] - 0.1, 'F on the ceiling light puts the camera inside the room, below the light',
    JSON.stringify({ eye: at, light }));
  check((await target(page)).every((x, k) => Math.abs(x - light[k]) < 1e-6) && await page.evaluate((p) => window.penumbra.inView(p), light),
    'and it looks at the light, which is in view', JSON.stringify(await target(page)));
  await press(page, 'Escape');
  await press(page, 'h');
}

// Drags on the floor near the left wall (locked: the drag orbits) up, down and up, 600 px each
// (up turns the camera down); the lowest eye.
async function orbit(page) {
  const canvas = await page.locator('#viewport canvas').boundingBox();
  const start = { x: canvas.x + canvas.width * 0.08, y: canvas.y + canvas.height * 0.9 };
  let lowest = Infinity;
  for (const dy of [-600, 600, -600]) {
    await page.mouse.move(start.x, start.y);
    await page.mouse.down();
    for (let s = 1; s <= 10; ++s) {
      await page.mouse.move(start.x, start.y + dy * s / 10);
      await sleep(30);
      lowest = Math.min(lowest, (await eye(page))[1]);
    }
    await page.mouse.up();
  }
  check(lowest >= ROOM.min[1], 'orbiting up and down never takes the camera under the floor', String(lowest));
  await press(page, 'a');
  const all = await eye(page);
  const centre = await page.evaluate(() => window.penumbra.sceneCentre());
  check(all[1] >= centre[1] - 1e-9, '"Frame all" after the orbit looks at the room from above its middle, not from below', JSON.stringify({ all, centre }));
  await press(page, 'h');
}

async function newLight(page, base, sceneId) {
  await press(page, 'Escape');
  await clickButton(page, 'add-light');
  const lights = (await serverScene(base, sceneId)).scene.lights;
  const centre = lights.length === 2 ? await page.evaluate(() => window.penumbra.lightCentre('light_2')) : null;
  check(centre && await page.evaluate((p) => window.penumbra.inView(p), centre), '"+ Light" puts the new light where the view sees it',
    JSON.stringify({ centre, lights: lights.map((l) => l.id) }));
  await press(page, 'Control+z');
}

async function newBoxAndDuplicate(page, base, sceneId) {
  await press(page, 'Escape');
  await press(page, 'b');
  const box = await page.evaluate(() => window.penumbra.objectCentre('box'));
  const boxHits = await overlapping(page, 'box');
  check(await page.evaluate((p) => window.penumbra.inView(p), box) && boxHits.length === 0,
    'B puts the new box in view, touching no other object', JSON.stringify({ box, boxHits }));
  check((await clickObject(page, 'cube_3')) === 'cube_3', 'a click selects cube_3');
  await press(page, 'Control+d');
  const ids = (await serverScene(base, sceneId)).scene.objects.map((o) => o.id);
  const hits = ids.includes('cube_3_copy') ? await overlapping(page, 'cube_3_copy') : ['(no copy)'];
  const copy = ids.includes('cube_3_copy') ? await page.evaluate(() => window.penumbra.objectBox('cube_3_copy')) : null;
  check(hits.length === 0 && copy && inRoom(copy.min) && inRoom(copy.max), 'Duplicate puts the copy in the room, touching neither its original nor anything else',
    JSON.stringify({ hits, copy }));
  await press(page, 'Control+z');
  await press(page, 'Control+z');
}

// The view's target on the room's south edge, looking there from the north: a volume loaded
// under the target would stand half outside the room.
async function loadedVolume(page) {
  await page.evaluate(() => window.penumbra.lookFrom([0, 1.6, -4], [0, 0.5, 4.7]));
  await page.setInputFiles('#volume-file', path.join(repo, 'scenes', 'volumes', 'smoke64.nrrd'));
  const loaded = await page.waitForFunction(() => window.penumbra.volumes().length > 0, null, { timeout: 120000 }).then(() => true, () => false);
  await idle(page);
  const volume = loaded ? (await page.evaluate(() => window.penumbra.volumes()))[0] : null;
  const box = volume ? await page.evaluate((id) => window.penumbra.objectBox(id), volume.id) : null;
  const centre = box ? box.min.map((x, k) => (x + box.max[k]) / 2) : null;
  check(box && inRoom(box.min) && inRoom(box.max) && await page.evaluate((p) => window.penumbra.inView(p), centre),
    'a loaded volume lands inside the room and in view', JSON.stringify({ box }));
}

async function main() {
  const args = usageOnHelp(process.argv, defaults,
    'node tests/web/placement_e2e.mjs --penumbra build/penumbra [--scene scenes/cubes15.scene.json]');
  await runWithServerAndBrowser(args, async ({ browser, url, base, sceneId }) => {
    const { page, pageErrors } = await openPage(browser, url);
    check((await state(page)).ready, 'the page is ready');
    await focusOnLight(page);
    await orbit(page);
    await newLight(page, base, sceneId);
    await newBoxAndDuplicate(page, base, sceneId);
    await loadedVolume(page);
    check(pageErrors.length === 0, 'no page errors', pageErrors.join('\n'));
  });
}

main();
