#!/usr/bin/env node
// Volumes in the page (issue 15), in Debian's chromium, on the volume room: the volume shows as a
// dashed box with a point-cloud preview of its isosurface and the note that the DM mesh has no
// volume occluders; clicked, it is selected and dragged by the gizmo (move edits), its isovalue
// slider sends set_volume; after each the server's image differs and the page's render panel shows
// the new version; undo takes both back (the image is the first one again); a .nrrd loaded with
// the panel's control becomes a second volume (undo removes it, redo adds it back); Delete and its
// undo take the scene's own volume away and back; no error shown.
//
// usage: node tests/web/volume_e2e.mjs --penumbra build/penumbra [--scene scenes/volume_room.scene.json]
import path from 'node:path';

import { check, repo, runWithServerAndBrowser, sleep, until, usageOnHelp } from './harness.mjs';
import { dragXHandle, openPage, serverScene } from './page_actions.mjs';

const defaults = { penumbra: path.join(repo, 'build', 'penumbra'), scene: path.join(repo, 'scenes', 'volume_room.scene.json'), startupSeconds: 120 };

const volume = async (page) => (await page.evaluate(() => window.penumbra.volumes()))[0];
const idle = (page) => page.evaluate(() => window.penumbra.idle());

// The server's image of the scene's own camera (the same request whatever the page's view).
async function serverImage(base, sceneId) {
  const response = await fetch(`${base}/api/scenes/${sceneId}/image?width=96&height=72`);
  return Buffer.from(await response.arrayBuffer()).toString('base64');
}

async function smokeOnServer(base, sceneId) {
  return (await serverScene(base, sceneId)).scene.objects.find((o) => o.id === 'smoke');
}

// The render panel has shown an image of `version` (the page asks after each edit).
const renderedVersion = (page, version) => until(async () => {
  const passes = await page.evaluate(() => window.penumbra.renderPasses());
  return passes && passes.passes.some((p) => p.version === version);
});

async function main() {
  const args = usageOnHelp(process.argv, defaults, 'node tests/web/volume_e2e.mjs --penumbra build/penumbra [--scene FILE]');
  await runWithServerAndBrowser(args, async ({ browser, url, base, sceneId }) => {
    const { page, pageErrors } = await openPage(browser, url);
    await idle(page);
    const first = await volume(page);
    check(first && first.id === 'smoke' && first.box, 'the volume is drawn as its grid box', JSON.stringify(first));
    check(first && first.previewPoints > 100 && first.previewIsovalue === 40.5, 'with a point cloud of its isosurface at the file\'s isovalue', JSON.stringify(first));
    const note = await page.locator('#volume-note');
    check(await note.isVisible() && /no volume occluders/.test(await note.textContent()), 'the panel says the DM mesh has no volume occluders');
    const image0 = await serverImage(base, sceneId);

    // Select by a click on the box's centre, then drag the gizmo's X handle.
    const centre = await page.evaluate(() => window.penumbra.objectCentre('smoke'));
    const screen = await page.evaluate((p) => window.penumbra.screenOf(p), centre);
    await page.mouse.click(screen.x, screen.y);
    await sleep(100);
    check((await page.evaluate(() => window.penumbra.state().selected)) === 'smoke', 'a click selects the volume');
    check(await page.locator('#volume-isovalue').isVisible() && await page.locator('.inspector .volume-note').isVisible(),
      'the inspector shows its isovalue slider and the note');
    const before = await smokeOnServer(base, sceneId);
    await dragXHandle(page, -0.4, 8, 60);
    await idle(page);
    const moved = await smokeOnServer(base, sceneId);
    const dx = moved.transform.translate[0] - before.transform.translate[0];
    check(dx < -0.2 && dx > -0.6, 'the gizmo drag moved the volume on the server (move edits)', JSON.stringify({ before: before.transform, moved: moved.transform }));
    const page1 = await volume(page);
    check(Math.abs(page1.transform.translate[0] - moved.transform.translate[0]) < 1e-9, 'the page holds the server\'s place');
    const image1 = await serverImage(base, sceneId);
    check(image1 !== image0, 'the server image shows the volume at its new place');
    const v1 = (await serverScene(base, sceneId)).version;
    check(await renderedVersion(page, v1), 'the render panel shows the moved version', `version ${v1}`);

    // The isovalue slider: set_volume, a new preview, a new image.
    await page.locator('#volume-isovalue').fill('100');
    await idle(page);
    const iso = await smokeOnServer(base, sceneId);
    check(iso.isovalue === 100, 'the slider sets the isovalue on the server (set_volume)', JSON.stringify(iso));
    const page2 = await volume(page);
    check(page2.previewIsovalue === 100 && page2.previewPoints !== first.previewPoints, 'the preview follows the isovalue', JSON.stringify(page2));
    const image2 = await serverImage(base, sceneId);
    check(image2 !== image1, 'the server image shows the new isosurface');
    const v2 = (await serverScene(base, sceneId)).version;
    check(await renderedVersion(page, v2), 'the render panel shows the new isovalue\'s version', `version ${v2}`);
    // The DM mesh does not change with a volume: the floor's mesh version stays.
    const floor = await page.evaluate(() => window.penumbra.receiver('floor', 0).sceneVersion);
    check(floor === 0, 'the DM mesh is untouched by volume edits', `floor at version ${floor}`);

    // A value outside the data's range is refused in the page (marked, nothing sent).
    const sent = (await page.evaluate(() => window.penumbra.state())).editsSent;
    await page.locator('#volume-isovalue-number').fill('1e9');
    await page.locator('#volume-isovalue-number').press('Enter');
    await idle(page);
    check((await page.evaluate(() => window.penumbra.state())).editsSent === sent
      && await page.locator('#volume-isovalue-number.invalid').count() === 1, 'an isovalue outside the values is marked and not sent');

    // Undo twice: the isovalue, then the move; the image is the first one again.
    await page.click('#undo');
    await idle(page);
    check((await smokeOnServer(base, sceneId)).isovalue === 40.5, 'undo takes the isovalue back');
    await page.click('#undo');
    await idle(page);
    const back = await smokeOnServer(base, sceneId);
    // (the page's pivot arithmetic round-trips the place to ~1e-16)
    check(back.transform.translate.every((x, k) => Math.abs(x - before.transform.translate[k]) < 1e-9), 'a second undo takes the move back',
      JSON.stringify(back.transform));
    check(await serverImage(base, sceneId) === image0, 'the server image is the first one again');
    await page.click('#redo');
    await idle(page);
    check(Math.abs((await smokeOnServer(base, sceneId)).transform.translate[0] - moved.transform.translate[0]) < 1e-9, 'redo moves it again');

    // Load a volume file: uploaded, placed, selected; undo removes it, redo adds it back (add_volume).
    const imageBeforeLoad = await serverImage(base, sceneId);
    await page.locator('#volume-file').setInputFiles(path.join(repo, 'scenes', 'volumes', 'smoke64.nrrd'));
    await until(async () => (await page.evaluate(() => window.penumbra.volumes())).length === 2);
    await idle(page);
    const volumesOnServer = async () => (await serverScene(base, sceneId)).scene.objects.filter((o) => o.type === 'volume').map((o) => o.id);
    const loaded = await page.evaluate(() => window.penumbra.volumes());
    check(JSON.stringify(await volumesOnServer()) === '["smoke","smoke64"]' && loaded.length === 2 && loaded[1].previewPoints > 100,
      'a loaded .nrrd becomes a volume on the server, drawn with its preview', JSON.stringify({ server: await volumesOnServer(), loaded }));
    check((await page.evaluate(() => window.penumbra.state().selected)) === 'smoke64', 'the loaded volume is selected');
    check(await serverImage(base, sceneId) !== imageBeforeLoad, 'the server image shows the loaded volume');
    await page.click('#undo');
    await idle(page);
    check(JSON.stringify(await volumesOnServer()) === '["smoke"]', 'undo removes the loaded volume');
    await page.click('#redo');
    await idle(page);
    check(JSON.stringify(await volumesOnServer()) === '["smoke","smoke64"]'
      && (await page.evaluate(() => window.penumbra.volumes())).length === 2, 'redo adds it back');

    // Delete the scene's own volume and undo: add_volume names the scene's file, which the server holds.
    await page.evaluate(() => window.penumbra.select('smoke'));
    await page.click('#delete');
    await idle(page);
    check(JSON.stringify(await volumesOnServer()) === '["smoke64"]', 'Delete removes the selected volume');
    await page.click('#undo');
    await idle(page);
    const restored = await smokeOnServer(base, sceneId);
    check(restored && Math.abs(restored.transform.translate[0] - moved.transform.translate[0]) < 1e-9 && restored.isovalue === 40.5,
      'undo adds it back where it was', JSON.stringify(restored));

    const final = await page.evaluate(() => window.penumbra.state());
    check(!final.errors.length && !final.bannerVisible && !pageErrors.length, 'no error shown or logged', JSON.stringify({ errors: final.errors, pageErrors }));
  });
}

main();
