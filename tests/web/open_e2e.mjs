#!/usr/bin/env node
// Opening the page (README "The page"): static files come compressed once with gzip (not
// brotli per request), with ETag / Cache-Control and 304 on revalidation; while the scene loads
// an overlay says what is awaited (the mesh download's bytes; an upload, then the server's build
// with a seconds counter that moves for the whole build: a generated scene of --slowCubes cubes
// that takes the server more than a second) and the panel's controls are disabled. Prints the
// page-ready time, cold and warm.
//
// usage: node tests/web/open_e2e.mjs --penumbra build/penumbra [--scene scenes/cubes15.scene.json] [--opens 1] [--slowCubes 1000]
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';

import { check, parseArgs, repo, runWithServerAndBrowser, sleep, usageOnHelp } from './harness.mjs';

const defaults = { penumbra: path.join(repo, 'build', 'penumbra'), scene: path.join(repo, 'scenes', 'cubes15.scene.json'),
  opens: 1, startupSeconds: 120, slowCubes: 1000 };

async function staticHeaders(base) {
  const started = performance.now();
  const core = await fetch(`${base}/node_modules/three/build/three.core.js`, { headers: { 'Accept-Encoding': 'gzip, deflate, br' } });
  const seconds = (performance.now() - started) / 1000;
  await core.arrayBuffer();
  const etag = core.headers.get('etag');
  check(core.ok && core.headers.get('content-encoding') === 'gzip', 'three.core.js comes gzip-compressed to a browser that also accepts br',
    `${core.status} ${core.headers.get('content-encoding')}`);
  check(/max-age=\d+/.test(core.headers.get('cache-control') || '') && !!etag, 'node_modules files carry Cache-Control max-age and an ETag',
    `${core.headers.get('cache-control')} ${etag}`);
  check(seconds < 1, 'three.core.js (1.3 MB) is served in under a second', `${seconds.toFixed(3)} s`);
  const again = await fetch(`${base}/node_modules/three/build/three.core.js`, { headers: { 'Accept-Encoding': 'gzip', 'If-None-Match': etag } });
  check(again.status === 304, 'a request naming its ETag is answered 304', String(again.status));
  const html = await (await fetch(`${base}/`)).text();
  check(/<script type="module" src="dist\/page\.js"/.test(html), 'index.html loads the page as one bundled module (dist/page.js)');
  const page = await fetch(`${base}/dist/page.js`, { headers: { 'Accept-Encoding': 'gzip' } });
  const text = await page.text();
  check(page.headers.get('cache-control') === 'no-cache' && !!page.headers.get('etag') && page.headers.get('content-encoding') === 'gzip'
    && text.includes('penumbra:ready') && !/^import /m.test(text),
    'the bundle holds the page and three.js (no imports left), gzip-compressed and revalidated on every load (no-cache + ETag)',
    `${page.headers.get('cache-control')} ${page.headers.get('content-encoding')}`);
  const escape = await fetch(`${base}/src/..%2f..%2fCMakeLists.txt`);
  check(escape.status === 404, 'a path leading out of the page\'s folder is 404', String(escape.status));
}

// Records every text the loading overlay shows, across navigations (sessionStorage).
const recordLoadingTexts = () => {
  const keep = (text) => sessionStorage.setItem('loadingTexts', JSON.stringify([...JSON.parse(sessionStorage.getItem('loadingTexts') || '[]'), text]));
  document.addEventListener('DOMContentLoaded', () => {
    const node = document.getElementById('loading-text');
    new MutationObserver(() => keep(node.textContent)).observe(node, { childList: true, characterData: true, subtree: true });
  });
};

// A generated scene whose build takes the server over a second (1000 cubes: ~1.5 s on 2 cores).
function slowScene(penumbra, cubes) {
  const file = path.join(fs.mkdtempSync(path.join(os.tmpdir(), 'penumbra-open-')), 'slow.scene.json');
  execFileSync(penumbra, ['generate', '--cubes', String(cubes), '--out', file], { stdio: 'ignore' });
  return file;
}

async function loadingOverlay(browser, url, slowFile) {
  const context = await browser.newContext({ viewport: { width: 1280, height: 800 } });
  await context.addInitScript(recordLoadingTexts);
  const page = await context.newPage();
  // The mesh is held back until the test has looked: meanwhile the overlay shows and the controls are disabled.
  let release;
  const held = new Promise((resolve) => { release = resolve; });
  await page.route(/\/mesh\?format=bin$/, async (route) => { await held; await route.continue(); });
  await page.goto(url, { waitUntil: 'domcontentloaded' });
  const controls = () => ({ overlay: getComputedStyle(document.getElementById('loading')).display !== 'none', text: document.getElementById('loading-text').textContent,
    undo: document.getElementById('undo').matches(':disabled'), move: document.getElementById('mode-translate').matches(':disabled'),
    file: document.getElementById('scene-file').matches(':disabled') });
  const atOnce = await page.evaluate(controls);
  check(atOnce.overlay && atOnce.move && atOnce.undo && !atOnce.file, 'as the page opens: the overlay shows and the buttons are disabled (the file input is not)',
    JSON.stringify(atOnce));
  await page.waitForFunction(() => window.penumbra && window.penumbra.state().loading.text !== 'Loading the page…', null, { timeout: 60000 });
  await sleep(200);
  const during = await page.evaluate(controls);
  release();
  check(during.overlay && during.move && /^(Loading the scene|Downloading the lit mesh)/.test(during.text),
    'while the mesh is awaited: the overlay says so and the buttons stay disabled', JSON.stringify(during));
  await page.waitForFunction(() => window.penumbra.state().ready, null, { timeout: 60000 });
  const after = await page.evaluate(() => {
    const rect = document.getElementById('viewport').getBoundingClientRect();
    const top = document.elementFromPoint(rect.left + rect.width / 2, rect.top + rect.height / 2);
    return { ...window.penumbra.state().loading, move: document.getElementById('mode-translate').matches(':disabled'), top: top && top.tagName };
  });
  check(!after.visible && !after.controlsDisabled && !after.move && after.top === 'CANVAS',
    'once loaded: the overlay is gone (the view takes clicks) and the buttons work', JSON.stringify(after));
  await page.unroute(/\/mesh\?format=bin$/);
  // The legend says what the light between vertices is, as the server states it (fans by default).
  const sceneId = await page.evaluate(() => new URL(window.location.href).searchParams.get('scene'));
  const served = await (await fetch(`${new URL(url).origin}/api/scenes/${sceneId}/stats`)).json();
  const bound = await page.evaluate(() => { const line = document.getElementById('mesh-bound'); return { hidden: line.hidden, text: line.textContent }; });
  check(typeof served.mesh.tolerance === 'number' && !bound.hidden &&
    (served.mesh.tolerance > 0 ? bound.text.includes(`${Number((served.mesh.tolerance * 100).toPrecision(3))}%`) : /not refined/.test(bound.text)),
    'the legend states the bound the server\'s mesh meets between vertices', `${served.mesh.tolerance}: ${bound.text}`);

  // Loading a scene file: upload, the server's build, then the new scene's mesh download.
  await page.setInputFiles('#scene-file', { name: 'slow.scene.json', mimeType: 'application/json', buffer: fs.readFileSync(slowFile) });
  await page.waitForURL(/scene=slow/, { timeout: 120000 });
  await page.waitForFunction(() => window.penumbra && window.penumbra.state().ready, null, { timeout: 120000 });
  const stats = await (await fetch(`${new URL(url).origin}/api/scenes/${new URL(page.url()).searchParams.get('scene')}/stats`)).json();
  const build = stats.build.seconds.total;
  const texts = await page.evaluate(() => JSON.parse(sessionStorage.getItem('loadingTexts') || '[]'));
  const counted = texts.map((t) => t.match(/^The server builds the discontinuity mesh(?:…|: .+) (\d+\.\d) s$/)).filter(Boolean).map((m) => Number(m[1]));
  console.log(`     the server built the slow scene in ${build.toFixed(2)} s (engine); the counter showed ${counted.length} values up to ${Math.max(...counted)} s`);
  check(counted.length >= 5 && new Set(counted).size >= 5 && Math.max(...counted) >= 1,
    'a file load shows the server\'s build with seconds waited, counting for the whole build (past 1 s)', JSON.stringify(counted));
  check(texts.some((t) => /^Downloading the lit mesh: [\d.]+ of [\d.]+ MB$/.test(t)), 'the mesh download shows bytes received of the total',
    JSON.stringify(texts.slice(0, 12)));
  await context.close();
}

// Page-ready time: navigation start → the page holds the mesh and its controls are enabled.
async function openTimes(browser, url, opens) {
  const context = await browser.newContext({ viewport: { width: 1280, height: 800 } });
  const times = [];
  for (let i = 0; i < opens; ++i) {
    const page = await context.newPage();
    await page.goto(url, { waitUntil: 'domcontentloaded' });
    await page.waitForFunction(() => window.penumbra && window.penumbra.state().ready, null, { timeout: 60000 });
    times.push(await page.evaluate(() => performance.getEntriesByName('penumbra:ready')[0].startTime / 1000));
    await page.close();
  }
  await context.close();
  console.log(`     page ready (s, first open cold, then cached; bench/web/page_open.mjs measures more): ${times.map((t) => t.toFixed(2)).join(', ')}`);
  check(times.length === opens, 'the page opened every time');
}

async function main() {
  const args = usageOnHelp(process.argv, defaults, 'node tests/web/open_e2e.mjs --penumbra build/penumbra [--scene FILE] [--opens N] [--slowCubes N]');
  await runWithServerAndBrowser(args, async ({ browser, url, base }) => {
    await staticHeaders(base);
    await loadingOverlay(browser, url, slowScene(args.penumbra, args.slowCubes));
    await openTimes(browser, url, args.opens);
  });
}

main();
