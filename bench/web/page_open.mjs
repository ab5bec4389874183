#!/usr/bin/env node
// Page-open time (README "The page"): wall clock from navigation to the page holding its scene's
// mesh with its controls enabled (window.penumbra.state().ready), in Debian's chromium, for one or
// more builds (penumbra binary + page folder) opened in turn, so that their figures share the
// machine's load. Each round opens every build once in a fresh browser context (cold: nothing
// cached), then twice more in that context (warm: the browser's cache).
//
// usage: node bench/web/page_open.mjs --penumbra build/penumbra [--static web_client]
//          [--penumbra2 OTHER/build/penumbra --static2 OTHER/web_client] [--scene scenes/cubes15.scene.json] [--rounds 3]
import path from 'node:path';

import { launchBrowser, repo, startServer, usageOnHelp } from '../../tests/web/harness.mjs';

const defaults = { penumbra: path.join(repo, 'build', 'penumbra'), static: path.join(repo, 'web_client'), penumbra2: null, static2: null,
  scene: path.join(repo, 'scenes', 'cubes15.scene.json'), rounds: 3 };

async function openSeconds(context, url) {
  const page = await context.newPage();
  const start = Date.now();
  await page.goto(url, { waitUntil: 'domcontentloaded', timeout: 120000 });
  await page.waitForFunction(() => window.penumbra && window.penumbra.state().ready, null, { timeout: 120000 });
  const seconds = (Date.now() - start) / 1000;
  await page.close();
  return seconds;
}

async function main() {
  const args = usageOnHelp(process.argv, defaults, 'node bench/web/page_open.mjs --penumbra BIN [--static DIR] [--penumbra2 BIN --static2 DIR] [--scene FILE] [--rounds N]');
  const builds = [[args.penumbra, args.static]];
  if (args.penumbra2) builds.push([args.penumbra2, args.static2 || args.static]);
  const servers = [];
  for (const [binary, dir] of builds) servers.push(await startServer(binary, args.scene, 120, 0, dir));
  const browser = await launchBrowser();
  const times = builds.map(() => ({ cold: [], warm: [] }));
  try {
    for (let round = 0; round < args.rounds; ++round) {
      for (const [i, { url }] of servers.entries()) {
        const context = await browser.newContext({ viewport: { width: 1280, height: 800 } });
        times[i].cold.push(await openSeconds(context, url));
        for (let k = 0; k < 2; ++k) times[i].warm.push(await openSeconds(context, url));
        await context.close();
      }
    }
  } finally {
    await browser.close();
    for (const { server } of servers) server.kill('SIGTERM');
  }
  const median = (xs) => [...xs].sort((a, b) => a - b)[Math.floor(xs.length / 2)];
  builds.forEach(([binary, dir], i) => {
    const t = times[i];
    console.log(JSON.stringify({ penumbra: binary, static: dir, cold_seconds: t.cold, warm_seconds: t.warm,
      median_cold: median(t.cold), median_warm: median(t.warm) }));
  });
}

main();
