#!/usr/bin/env node
// Adding and deleting lights in the page (README "The page"), in Debian's chromium with real
// clicks and keys: with the scene's only light selected, Delete is disabled; "+ Light" adds a copy
// beside it (one add_light: a second light on the server, selected in the page, the floor brighter);
// Delete removes it (one remove_light: the floor exactly as before); Ctrl+Z brings it back with its
// polygon and radiance, Ctrl+Z again takes it away, Ctrl+Shift+Z adds it again; nothing is shown or
// logged as an error.
//
// usage: node tests/web/light_count_e2e.mjs --penumbra build/penumbra [--scene scenes/cubes15.scene.json]
import path from 'node:path';

import { check, repo, runWithServerAndBrowser, sleep, usageOnHelp } from './harness.mjs';
import { openPage, serverScene } from './page_actions.mjs';

const defaults = { penumbra: path.join(repo, 'build', 'penumbra'), scene: path.join(repo, 'scenes', 'cubes15.scene.json'), startupSeconds: 120 };
const state = (page) => page.evaluate(() => window.penumbra.state());
const idle = (page) => page.evaluate(() => window.penumbra.idle());
const floorSum = (page) => page.evaluate(() => window.penumbra.receiver('floor', 0).irradiance.reduce((s, x) => s + x, 0));
const disabled = (page, id) => page.evaluate((button) => document.getElementById(button).disabled, id);
const near = (a, b, eps = 1e-9) => Math.abs(a - b) <= eps * Math.max(Math.abs(a), Math.abs(b));

async function settle(page) {
  await sleep(80);
  await idle(page);
}

async function press(page, key) {
  await page.keyboard.press(key);
  await settle(page);
}

async function click(page, id) {
  await page.click(`#${id}`);
  await settle(page);
}

async function selectLight(page) {
  await press(page, 'a'); // the scene's camera leaves the ceiling's light just out of view
  const at = await page.evaluate(() => window.penumbra.lightCentre('light'));
  const screen = await page.evaluate((p) => window.penumbra.screenOf(p), at);
  await page.mouse.click(screen.x, screen.y);
  await sleep(100);
  check((await state(page)).selected === 'light:light' && await disabled(page, 'delete') && !await disabled(page, 'add-light'),
    'with the only light selected, Delete is disabled (a scene keeps a light) and + Light is not');
}

// What the server and the page show now.
async function snapshot(page, base, sceneId) {
  const scene = await serverScene(base, sceneId);
  return { version: scene.version, lights: scene.scene.lights, floor: await floorSum(page), page: await state(page) };
}

async function main() {
  const args = usageOnHelp(process.argv, defaults, 'node tests/web/light_count_e2e.mjs --penumbra build/penumbra [--scene FILE]');
  await runWithServerAndBrowser(args, async ({ browser, url, base, sceneId }) => {
    const { page, pageErrors } = await openPage(browser, url);
    await selectLight(page);
    const start = await snapshot(page, base, sceneId);
    check(start.lights.length === 1, 'the scene starts with one light', JSON.stringify(start.lights.map((l) => l.id)));

    await click(page, 'add-light');
    const added = await snapshot(page, base, sceneId);
    const copy = added.lights[1];
    check(added.lights.length === 2 && copy && copy.id === 'light_2' && added.version === start.version + 1
      && added.page.version === added.version && added.page.selected === 'light:light_2',
    '+ Light adds one light (one version) with a fresh id, selected in the page', JSON.stringify({ ids: added.lights.map((l) => l.id), version: added.version, selected: added.page.selected }));
    check(copy && JSON.stringify(copy.radiance) === JSON.stringify(start.lights[0].radiance)
      && copy.polygon.every((p, i) => Math.abs(p[1] - start.lights[0].polygon[i][1]) < 1e-12)
      && copy.polygon.some((p, i) => Math.abs(p[0] - start.lights[0].polygon[i][0]) > 0.5),
    'the new light is a copy of the selected one, beside it at the same height', JSON.stringify(copy));
    check(added.floor > 1.2 * start.floor, 'the floor\'s mesh follows: brighter under two lights', JSON.stringify({ before: start.floor, after: added.floor }));
    check(!await disabled(page, 'delete'), 'with two lights, Delete is enabled for the selected light');

    await click(page, 'delete');
    const deleted = await snapshot(page, base, sceneId);
    check(deleted.lights.length === 1 && deleted.lights[0].id === 'light' && deleted.version === added.version + 1
      && deleted.page.version === deleted.version && near(deleted.floor, start.floor),
    'Delete removes the selected light (one version): the floor is as it was', JSON.stringify({ ids: deleted.lights.map((l) => l.id), floor: deleted.floor, start: start.floor }));

    await press(page, 'Control+z');
    const back = await snapshot(page, base, sceneId);
    check(back.lights.length === 2 && JSON.stringify(back.lights[1]) === JSON.stringify(copy) && near(back.floor, added.floor),
      'Ctrl+Z brings the deleted light back, polygon and radiance (the floor as with two lights)', JSON.stringify({ ids: back.lights.map((l) => l.id), floor: back.floor }));

    await press(page, 'Control+z');
    const undone = await snapshot(page, base, sceneId);
    check(undone.lights.length === 1 && near(undone.floor, start.floor) && undone.page.version === undone.version,
      'Ctrl+Z again undoes the addition: one light, the floor as at the start', JSON.stringify({ ids: undone.lights.map((l) => l.id), floor: undone.floor }));

    await press(page, 'Control+Shift+z');
    const redone = await snapshot(page, base, sceneId);
    check(redone.lights.length === 2 && JSON.stringify(redone.lights[1]) === JSON.stringify(copy) && near(redone.floor, added.floor),
      'Ctrl+Shift+Z adds it again', JSON.stringify({ ids: redone.lights.map((l) => l.id) }));

    await page.screenshot({ path: path.join(repo, 'build', 'web-light-count.png') });
    const final = await state(page);
    check(!final.bannerVisible && pageErrors.length === 0, 'no error shown or logged', JSON.stringify([final.errors, pageErrors]));
  });
}

main();
