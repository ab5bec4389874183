#!/usr/bin/env node
// A screenshot of the page for the README: serves SCENE, opens the page in Debian's chromium
// (SwiftShader), optionally turns on the image panel's GI and the baked bounced light, waits for
// the server image's last pass (and the bake), and writes a PNG of the whole window.
//
// usage: node bench/web/screenshot.mjs --penumbra build/penumbra --scene SCENE --out PNG [--gi 1]
import path from 'node:path';

import { check, repo, runWithServerAndBrowser, sleep, usageOnHelp } from '../../tests/web/harness.mjs';
import { openPage } from '../../tests/web/page_actions.mjs';

const defaults = { penumbra: path.join(repo, 'build', 'penumbra'), scene: path.join(repo, 'scenes', 'cubes15.scene.json'),
  out: 'page.png', gi: 0, width: 1280, height: 800, startupSeconds: 120 };

async function until(what, seconds = 120) {
  const deadline = Date.now() + seconds * 1000;
  while (Date.now() < deadline) {
    const value = await what();
    if (value) return value;
    await sleep(250);
  }
  return null;
}

async function main() {
  const args = usageOnHelp(process.argv, defaults,
    'node bench/web/screenshot.mjs --penumbra build/penumbra --scene SCENE --out PNG [--gi 1]');
  await runWithServerAndBrowser(args, async ({ browser, url }) => {
    const { page } = await openPage(browser, url);
    await page.setViewportSize({ width: args.width, height: args.height });
    if (args.gi) {
      await page.check('#toggle-gi');
      await page.check('#toggle-indirect');
      check(await until(async () => (await page.evaluate(() => window.penumbra.bakedIndirect())).version !== null),
        'the baked bounced light is shown');
    }
    const lastPass = async () => {
      const passes = (await page.evaluate(() => window.penumbra.renderPasses())).passes;
      const last = passes[passes.length - 1];
      return last && !(await page.evaluate(() => window.penumbra.renderPasses())).inFlight && (!args.gi || last.giSensors > 0);
    };
    check(await until(lastPass), 'the server image has its last pass');
    await sleep(500);
    await page.screenshot({ path: path.resolve(args.out) });
    check(true, `wrote ${args.out}`);
  });
}

main();
