#!/usr/bin/env node
// Renaming a scene from the page (README "The page"), in Debian's chromium: the scene list's Rename
// asks for a name and PATCHes it; the header and the list follow; bad names are refused naming
// `name` (the page says so in a sentence) and change nothing; the name survives a restart of a
// journaled server (a fresh server on the same data directory lists and shows it).
//
// usage: node tests/web/rename_e2e.mjs --penumbra build/penumbra [--scene scenes/cornell.scene.json]
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';

import { check, launchBrowser, repo, startServer, tally, usageOnHelp } from './harness.mjs';
import { openPage, serverScene } from './page_actions.mjs';

const defaults = { penumbra: path.join(repo, 'build', 'penumbra'), scene: path.join(repo, 'scenes', 'cornell.scene.json'), startupSeconds: 120 };
const NEW_NAME = 'Kitchen · draft 2';

const header = (page) => page.evaluate(() => document.getElementById('scene-name').textContent);
const listed = (page, id) => page.evaluate((sid) => document.querySelector(`#scene-list li[data-scene="${sid}"]`)?.textContent || '', id);

async function patchName(base, id, body) {
  const response = await fetch(`${base}/api/scenes/${id}`, { method: 'PATCH', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body) });
  return { status: response.status, body: await response.json() };
}

async function renameInPage(page, sceneId, name) {
  page.once('dialog', (dialog) => dialog.accept(name));
  await page.click(`#scene-list li[data-scene="${sceneId}"] button[data-action="rename"]`);
}

async function badNames(page, base, sceneId) {
  const before = await serverScene(base, sceneId);
  for (const [body, why] of [[{}, 'no name'], [{ name: 5 }, 'a number as name'], [{ name: '   ' }, 'a blank name'],
    [{ name: 'a\u0007b' }, 'a name with a control character'], [{ name: 'x'.repeat(201) }, 'a name of 201 characters']]) {
    const { status, body: answer } = await patchName(base, sceneId, body);
    check(status === 422 && answer.error.code === 'invalid_name' && answer.error.path === 'name', `${why} is refused naming "name"`,
      JSON.stringify({ status, answer }));
  }
  const after = await serverScene(base, sceneId);
  check(after.name === before.name && after.version === before.version, 'refused names change nothing', JSON.stringify([before.name, after.name]));
  await renameInPage(page, sceneId, '\t');
  const banner = await page.waitForFunction(() => window.penumbra.state().errors.some((e) => /refused the name/.test(e)), null, { timeout: 5000 })
    .then(() => true, () => false);
  check(banner, 'the page says the server refused the name', JSON.stringify(await page.evaluate(() => window.penumbra.state().errors)));
}

async function main() {
  const args = usageOnHelp(process.argv, defaults, 'node tests/web/rename_e2e.mjs --penumbra build/penumbra [--scene FILE]');
  const deadline = setTimeout(() => { console.log('FAIL the test took over 3 minutes'); process.exit(1); }, 180000);
  const data = fs.mkdtempSync(path.join(os.tmpdir(), 'penumbra-rename-'));
  const storage = ['--data', data];
  let server = null;
  let browser = null;
  try {
    const started = await startServer(args.penumbra, args.scene, args.startupSeconds, 0, undefined, storage);
    server = started.server;
    const { url } = started;
    const base = new URL(url).origin;
    const sceneId = new URL(url).searchParams.get('scene');
    browser = await launchBrowser();
    const { page, pageErrors } = await openPage(browser, url);
    const version = (await serverScene(base, sceneId)).version;

    await renameInPage(page, sceneId, NEW_NAME);
    await page.waitForFunction((name) => document.getElementById('scene-name').textContent.includes(name), NEW_NAME, { timeout: 10000 }).catch(() => {});
    check((await header(page)) === `${sceneId} (${NEW_NAME})`, 'the header shows the new name', await header(page));
    await page.waitForFunction(([id, name]) => (document.querySelector(`#scene-list li[data-scene="${id}"]`)?.textContent || '').includes(name),
      [sceneId, NEW_NAME], { timeout: 10000 }).catch(() => {});
    check((await listed(page, sceneId)).includes(NEW_NAME), 'the scene list shows the new name', await listed(page, sceneId));
    const renamed = await serverScene(base, sceneId);
    check(renamed.name === NEW_NAME && renamed.version === version, 'the server holds the name, the version unchanged',
      JSON.stringify({ name: renamed.name, version: renamed.version, before: version }));
    await badNames(page, base, sceneId);
    const unexpected = pageErrors.filter((e) => !/422/.test(e));
    check(unexpected.length === 0, 'nothing else is logged as an error', JSON.stringify(unexpected));

    // A restart on the same data directory: the journal brings the scene back under its new name.
    const port = Number(new URL(url).port);
    const exited = new Promise((resolve) => server.on('exit', resolve));
    server.kill('SIGTERM');
    await exited;
    server = (await startServer(args.penumbra, null, args.startupSeconds, port, undefined, storage)).server;
    const { scenes } = await (await fetch(`${base}/api/scenes`)).json();
    const back = scenes.find((s) => s.id === sceneId);
    check(back && back.name === NEW_NAME, 'after a restart the scene list has the new name', JSON.stringify(scenes.map((s) => [s.id, s.name])));
    const { page: again } = await openPage(browser, url);
    check((await header(again)) === `${sceneId} (${NEW_NAME})`, 'after a restart the page shows the new name', await header(again));
  } catch (error) {
    check(false, 'the test ran to the end', error.stack || String(error));
  } finally {
    if (browser) await browser.close();
    if (server) server.kill('SIGTERM');
    fs.rmSync(data, { recursive: true, force: true });
    clearTimeout(deadline);
  }
  process.exit(tally() ? 1 : 0);
}

main();
