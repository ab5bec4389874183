#!/usr/bin/env node
// A long build from the page (a generated torus knot of --triangles triangles, seconds on the
// server): the loading overlay shows the build's stage and fraction with a seconds counter that
// moves, another tab's scene list shows the scene as building, and the overlay's Cancel stops the
// build (DELETE): the overlay goes within --cancelSeconds, the page stays on its scene, nothing of
// the cancelled scene is left and the server serves on. The build stops at its next progress
// report (per cast, every 64 vertices lit): the DELETE takes under 0.1 s; the bound leaves room
// for a busy machine. The progress comes through the builds event stream (the page polls no scene
// list meanwhile); with that stream refused, the page polls the scene list and shows it all the same.
//
// usage: node tests/web/build_cancel_e2e.mjs --penumbra build/penumbra [--triangles 16000] [--cancelSeconds 5]
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';

import { check, repo, runWithServerAndBrowser, sleep, until, usageOnHelp } from './harness.mjs';

const defaults = { penumbra: path.join(repo, 'build', 'penumbra'), scene: path.join(repo, 'scenes', 'cubes15.scene.json'),
  startupSeconds: 120, triangles: 16000, cancelSeconds: 5 };

function knotScene(penumbra, triangles) {
  const file = path.join(fs.mkdtempSync(path.join(os.tmpdir(), 'penumbra-cancel-')), 'knot.scene.json');
  execFileSync(penumbra, ['generate', '--model', 'torus-knot', '--triangles', String(triangles), '--out', file], { stdio: 'ignore' });
  return file;
}

const overlayText = () => document.getElementById('loading-text').textContent;

async function buildAndCancel(browser, url, base, knotFile, cancelSeconds) {
  const context = await browser.newContext({ viewport: { width: 1280, height: 800 } });
  const page = await context.newPage();
  await page.goto(url, { waitUntil: 'domcontentloaded' });
  await page.waitForFunction(() => window.penumbra && window.penumbra.state().ready, null, { timeout: 60000 });
  const startUrl = page.url();
  const other = await context.newPage(); // a second tab: its scene list shows the build
  await other.goto(startUrl, { waitUntil: 'domcontentloaded' });
  await other.waitForFunction(() => window.penumbra && window.penumbra.state().ready, null, { timeout: 60000 });

  // The page's own requests: scene lists polled and builds streams opened.
  const asked = { lists: 0, streams: 0 };
  page.on('request', (request) => {
    const { pathname } = new URL(request.url());
    if (pathname === '/api/scenes' && request.method() === 'GET') ++asked.lists;
    if (pathname === '/api/builds/events') ++asked.streams;
  });
  await page.setInputFiles('#scene-file', { name: 'knot.scene.json', mimeType: 'application/json', buffer: fs.readFileSync(knotFile) });
  await page.waitForFunction((pattern) => new RegExp(pattern).test(document.getElementById('loading-text').textContent),
    building.source, { timeout: 60000 });
  // Meanwhile the other tab opens again and lists the scene being built.
  const otherLists = { count: 0 };
  other.on('request', (request) => {
    if (new URL(request.url()).pathname === '/api/scenes' && request.method() === 'GET') ++otherLists.count;
  });
  const listed = other.reload({ waitUntil: 'domcontentloaded' })
    .then(() => other.waitForFunction(() => document.querySelector('#scene-list li[data-state="building"]'), null, { timeout: 30000 }))
    .then((item) => item.evaluate((node) => node.textContent)).catch((error) => `none: ${error.message}`);
  await watchTheOverlay(page, '');
  const item = await listed;
  check(/building: \w+/.test(item), 'another tab\'s scene list shows the scene being built with its stage', item);
  // Its entry follows the builds event stream: it changes, and no list is asked for meanwhile.
  otherLists.count = 0;
  const entry = () => other.evaluate(() => document.querySelector('#scene-list li[data-state="building"]')?.textContent || '');
  // Sampled until its stage or fraction moves, at most 15 s (a bound for a loaded machine: every
  // step reports as it goes, illumination per 64 vertices lit).
  const progressOf = (e) => e.replace(/ · \d+\.\d s(Cancel)?$/, '');
  const entries = [await entry()];
  for (let i = 0; i < 75 && (entries.length < 2 || new Set([item, ...entries].map(progressOf)).size < 2); ++i) {
    await sleep(200);
    entries.push(await entry());
  }
  // Its seconds count on between events; its stage and fraction (the text before them) come
  // only from the stream, so they must have moved since the entry was first listed.
  check(new Set(entries).size >= 2 && new Set([item, ...entries].map(progressOf)).size >= 2 &&
    entries.every((e) => /building: \w+/.test(e)) && otherLists.count === 0,
    'the other tab\'s entry follows the build with no scene list polled', JSON.stringify({ item, entries, lists: otherLists.count }));
  await other.close();
  check(asked.streams >= 1 && asked.lists === 0, 'the build\'s progress came through the builds event stream, no scene list polled',
    JSON.stringify(asked));
  await cancelAndCheck(page, base, startUrl, cancelSeconds);

  // The stream refused (a proxy that drops it): the page polls the scene list instead.
  await page.route('**/api/builds/events', (route) => route.abort());
  asked.lists = 0;
  await page.setInputFiles('#scene-file', { name: 'knot.scene.json', mimeType: 'application/json', buffer: fs.readFileSync(knotFile) });
  await watchTheOverlay(page, ' (the stream refused)');
  check(asked.lists >= 3, 'without the stream the page polls the scene list for the build\'s progress', JSON.stringify(asked));
  await cancelAndCheck(page, base, startUrl, cancelSeconds);
  await context.close();
}

const building = /^The server builds the discontinuity mesh: (\w+)(?: (\d+) %)? (\d+\.\d) s$/;

// The overlay during the build: the stage, a fraction that rises and a seconds counter that moves; Cancel offered.
async function watchTheOverlay(page, how) {
  await page.waitForFunction((pattern) => new RegExp(pattern).test(document.getElementById('loading-text').textContent),
    building.source, { timeout: 60000 });
  const texts = [];
  for (let i = 0; i < 12; ++i) {
    texts.push(await page.evaluate(overlayText));
    await sleep(150);
  }
  const seconds = texts.map((t) => t.match(building)).filter(Boolean).map((m) => Number(m[3]));
  check(seconds.length >= 9 && new Set(seconds).size >= 9 && seconds.every((s, i) => i === 0 || s >= seconds[i - 1]),
    `the overlay shows the build's stage with a seconds counter that moves${how}`, JSON.stringify(texts.slice(0, 4)));
  // The fraction moves as the build's steps go on: sampled on until it moves, at most 15 s more
  // (as the other tab's entry below).
  const fractionsOf = () => new Set(texts.map((t) => t.match(building)).filter((m) => m && m[2] !== undefined).map((m) => `${m[1]} ${m[2]}`));
  for (let i = 0; i < 75 && fractionsOf().size < 2; ++i) {
    await sleep(200);
    texts.push(await page.evaluate(overlayText));
  }
  check(fractionsOf().size >= 2, `the overlay shows the stage's fraction moving${how}`, JSON.stringify(texts.slice(-3)));
  const cancelVisible = await page.evaluate(() => !document.getElementById('loading-cancel').hidden);
  check(cancelVisible, `the overlay offers Cancel while the server builds${how}`);
}

async function cancelAndCheck(page, base, startUrl, cancelSeconds) {
  const clicked = performance.now();
  await page.click('#loading-cancel');
  await page.waitForFunction(() => document.getElementById('loading').hidden, null, { timeout: 60000 });
  const took = (performance.now() - clicked) / 1000;
  console.log(`     the overlay went ${took.toFixed(2)} s after Cancel`);
  check(took < cancelSeconds, `Cancel stops the build within ${cancelSeconds} s`, `${took.toFixed(2)} s`);
  const scenes = (await (await fetch(`${base}/api/scenes`)).json()).scenes;
  check(scenes.length === 1 && scenes[0].state === 'ready', 'nothing is left of the cancelled scene', JSON.stringify(scenes.map((s) => s.id)));
  check(page.url() === startUrl, 'the page stays on its scene', page.url());
  const health = await fetch(`${base}/api/health`);
  check(health.ok, 'the server serves on');
  const banner = await page.evaluate(() => {
    const node = document.getElementById('error-banner');
    return node && !node.hidden ? node.textContent : '';
  });
  check(!banner, 'a cancel is not an error', banner);
}

async function main() {
  const args = usageOnHelp(process.argv, defaults, 'node tests/web/build_cancel_e2e.mjs --penumbra build/penumbra [--triangles N] [--cancelSeconds S]');
  await runWithServerAndBrowser(args, async ({ browser, url, base }) => {
    await buildAndCancel(browser, url, base, knotScene(args.penumbra, args.triangles), args.cancelSeconds);
  });
}

main();
