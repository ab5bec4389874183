#!/usr/bin/env node
// What the page says back (README "The page"): a drag past the edit volume stops the object at
// its last accepted place with one banner (a few refused frames, not one per pointer move), which
// the next accepted edit clears; the edges legend shows only with the overlay; the edit-vs-build
// plot and ratio fill in ("slower" when slower); the banner says why in a sentence with the code
// and key path on a detail line; a stopped server shows "disconnected — reconnecting", and the
// page catches up when a server comes back on the same port (dropping the undo steps of the old
// version, and the "could not be reached" banner); leaving the page logs nothing.
//
// usage: node tests/web/feedback_e2e.mjs --penumbra build/penumbra [--scene scenes/cubes15.scene.json]
import path from 'node:path';

import { check, repo, runWithServerAndBrowser, sleep, startServer, usageOnHelp } from './harness.mjs';
import { clickObject, dragXHandle, openPage, serverScene } from './page_actions.mjs';

const defaults = { penumbra: path.join(repo, 'build', 'penumbra'), scene: path.join(repo, 'scenes', 'cubes15.scene.json'), startupSeconds: 120 };

const shown = (id) => `getComputedStyle(document.getElementById('${id}')).display !== 'none'`;

async function legend(page) {
  const visible = () => page.evaluate(shown('edge-legend'));
  const before = await visible();
  await page.check('#toggle-edges');
  const on = await visible();
  await page.uncheck('#toggle-edges');
  const off = await visible();
  check(!before && on && !off, 'the edges legend shows only while the overlay is on', JSON.stringify({ before, on, off }));
}

async function refusedDrag(page, base, sceneId) {
  const refusals = [];
  page.on('response', (response) => { if (response.status() === 422) refusals.push(response.url()); });
  // Zoomed out, so the screen reaches past the room's walls (and the edit volume beyond them).
  const rect = await page.evaluate(() => document.getElementById('viewport').getBoundingClientRect().toJSON());
  await page.mouse.move(rect.x + rect.width / 2, rect.y + rect.height / 2);
  for (let i = 0; i < 6; ++i) { await page.mouse.wheel(0, 400); await sleep(60); }
  const id = 'cube_3';
  check((await clickObject(page, id)) === id, `a click selects ${id}`);
  const steps = 30;
  await dragXHandle(page, 5, steps, 40); // x from 1.7 to 6.7: the room's wall is at 4.74, the volume ends ~0.7 m beyond
  await page.evaluate(() => window.penumbra.idle());
  const state = await page.evaluate(() => window.penumbra.state());
  const held = await page.evaluate((id) => window.penumbra.objectTransform(id).translate, id);
  const server = (await serverScene(base, sceneId)).scene.objects.find((o) => o.id === id).transform.translate;
  console.log(`     ${refusals.length} refused frames of ${state.editsSent} sent for ${steps} pointer moves`);
  check(refusals.length >= 1 && refusals.length <= 5, `a drag past the edit volume costs a few refused frames, not one per move (${steps} moves)`,
    `${refusals.length} refused, ${state.editsSent} sent`);
  // Frames are sent one per round trip: how far the last accepted one got depends on how many
  // went out (on a loaded machine the first round trip can last the whole drag, 2 frames for
  // 30 moves). Near the volume's edge is asked when enough went to reach it.
  const reachedEdge = state.editsSent < 5 || server[0] > 3;
  check(held.every((x, k) => Math.abs(x - server[k]) < 1e-9) && server[0] > 1.7 && reachedEdge,
    'the object stops at its last accepted place (page = server), past its start, near the volume\'s edge when 5+ frames went',
    `page ${held}, server ${server}, ${state.editsSent} sent`);
  const refusedErrors = state.errors.filter((e) => /422/.test(e));
  check(state.bannerVisible && refusedErrors.length === 1, 'one banner for the whole drag', JSON.stringify(state.errors));
  const banner = await page.evaluate(() => ({ sentence: document.getElementById('error-text').firstChild.textContent,
    detail: (document.querySelector('#error-text .error-detail') || {}).textContent }));
  check(/^The server refused the edit: .*edit volume.*\. It stays at its last accepted place\.$/.test(banner.sentence) && !/invalid_frame|edits\[/.test(banner.sentence)
    && /^422 invalid_frame at edits\[\d+\]/.test(banner.detail || ''), 'the banner says why in a sentence, the code and key path on a detail line', JSON.stringify(banner));
  await page.keyboard.press('Control+z'); // an accepted edit: back to where the drag began
  await page.evaluate(() => window.penumbra.idle());
  const after = await page.evaluate(() => window.penumbra.state());
  check(!after.bannerVisible, 'the next accepted edit clears the banner', JSON.stringify(after.errors));
  return refusals.length;
}

async function plot(page) {
  // The benchmark tables are folded into "Stats", closed by default.
  const closed = await page.evaluate(() => !document.getElementById('stats').open && !document.getElementById('rebuild').checkVisibility());
  check(closed, 'the Stats section (plot, timings, rebuild) is closed when the page opens');
  // Drawn when shown, not at every edit while closed (on a software GL each drawing costs the
  // browser's GPU process what a frame of the view does).
  const plotted = () => page.evaluate(() => {
    const canvas = document.getElementById('edit-plot');
    const data = canvas.getContext('2d').getImageData(0, 0, canvas.width, canvas.height).data;
    let orange = 0;
    for (let i = 0; i < data.length; i += 4) if (data[i] === 0xff && data[i + 1] === 0x90 && data[i + 2] === 0x20) ++orange;
    return { orange, history: window.penumbra.state().editHistory };
  });
  const unseen = await plotted();
  await page.click('#stats summary');
  const opened = await page.waitForFunction(() => {
    const canvas = document.getElementById('edit-plot');
    const data = canvas.getContext('2d').getImageData(0, 0, canvas.width, canvas.height).data;
    for (let i = 0; i < data.length; i += 4) if (data[i] === 0xff && data[i + 1] === 0x90 && data[i + 2] === 0x20) return true;
    return false;
  }, null, { timeout: 10000 }).then(() => true, () => false);
  check(unseen.history > 0 && unseen.orange === 0 && opened,
    'the edit plot is not drawn while Stats is closed, and is drawn with the edits so far when it opens', JSON.stringify({ unseen, opened }));
  await page.click('#rebuild');
  await page.waitForFunction(() => /rebuild of v\d+/.test(document.getElementById('edit-ratio').textContent), null, { timeout: 30000 });
  const r = { ...(await plotted()), text: await page.textContent('#edit-ratio') };
  check(r.orange > 0 && r.history > 0 && /edit [\d.]+ ms .* vs full build [\d.]+ ms \(rebuild of v\d+, engine \+ display meshing\): [\d.]+× (faster|slower)$/.test(r.text),
    'the plot shows the edits\' times and the ratio to a full build, both with their display meshing', JSON.stringify(r));
  // A build faster than the edits (a rebuild answer that says so): the words say "slower", not "0.1× faster".
  await page.route(/\/rebuild$/, async (route) => {
    const answer = await (await route.fetch()).json();
    answer.seconds = { build: 1e-5, mesh: 1e-5, total: 2e-5 };
    await route.fulfill({ json: answer });
  });
  await page.click('#rebuild');
  await page.waitForFunction(() => /0\.0 ms \(rebuild/.test(document.getElementById('edit-ratio').textContent), null, { timeout: 30000 }).catch(() => {});
  const slower = await page.textContent('#edit-ratio');
  check(/: [\d.]+× slower$/.test(slower) && !/faster/.test(slower), 'an edit slower than the build reads "slower"', slower);
  await page.unroute(/\/rebuild$/);
}

async function disconnect(args, page, server, url) {
  server.kill('SIGTERM');
  await new Promise((resolve) => server.once('exit', resolve));
  await page.waitForFunction((s) => eval(s), shown('connection'), { timeout: 15000 }).catch(() => {});
  const lost = await page.evaluate(() => ({ text: document.getElementById('connection').textContent, state: window.penumbra.state().connection }));
  check(/Server disconnected — reconnecting/.test(lost.text) && lost.state === 'reconnecting', 'a stopped server shows "disconnected — reconnecting"', JSON.stringify(lost));
  // A request the server cannot answer still reaches the banner (only leaving the page drops one).
  await page.evaluate(() => { document.getElementById('stats').open = true; });
  await page.click('#rebuild');
  const failed = await page.waitForFunction(() => window.penumbra.state().errors.some((e) => /network_error/.test(e)), null, { timeout: 5000 })
    .then(() => true, () => false);
  check(failed, 'a request to a stopped server shows a network error in the banner', JSON.stringify(await page.evaluate(() => window.penumbra.state().errors)));
  const redoBefore = await page.evaluate(() => !document.getElementById('redo').disabled);
  const port = Number(new URL(url).port);
  const again = await startServer(args.penumbra, args.scene, args.startupSeconds, port);
  await page.waitForFunction((s) => !eval(s) && window.penumbra.state().connection === 'connected' && !window.penumbra.state().busy,
    shown('connection'), { timeout: 15000 }).catch(() => {});
  await page.evaluate(() => window.penumbra.idle());
  const back = await page.evaluate(() => window.penumbra.state());
  check(back.connection === 'connected' && back.version === 0 && back.receivers > 0,
    'when a server is back on the port the bar goes and the page holds its scene (a fresh one: version 0)', JSON.stringify({ c: back.connection, v: back.version }));
  const buttons = await page.evaluate(() => ({ undo: document.getElementById('undo').disabled, redo: document.getElementById('redo').disabled }));
  check(redoBefore && buttons.undo && buttons.redo, 'a server back at another version (no journal): the page offers no undo or redo from before', JSON.stringify({ redoBefore, buttons }));
  check(!back.bannerVisible, 'the "could not be reached" banner goes once the server is back', JSON.stringify(back.errors));
  return again.server;
}

async function main() {
  const args = usageOnHelp(process.argv, defaults, 'node tests/web/feedback_e2e.mjs --penumbra build/penumbra [--scene FILE]');
  await runWithServerAndBrowser(args, async ({ browser, url, base, sceneId, server }) => {
    const { page, pageErrors } = await openPage(browser, url);
    await legend(page);
    await refusedDrag(page, base, sceneId);
    await plot(page);
    const before = pageErrors.length;
    await page.goto(url, { waitUntil: 'domcontentloaded' }); // leaving the page
    await page.waitForFunction(() => window.penumbra && window.penumbra.state().ready, null, { timeout: 60000 });
    await sleep(300);
    const logged = pageErrors.slice(before);
    check(logged.length === 0, 'leaving the page logs nothing (no "event stream closed")', JSON.stringify(logged));
    const restarted = await disconnect(args, page, server, url);
    restarted.kill('SIGTERM');
  });
}

main();
