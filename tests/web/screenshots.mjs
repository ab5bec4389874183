#!/usr/bin/env node
// The README's pictures of the page, made in Debian's chromium: for each scene a server is started,
// the page opened at 1280×800 and, once it is ready and the server render beside it has finished its
// passes, the whole window saved as docs/images/page_<scene>.png. Not a test: run it after a change
// to the page's looks (docs/TESTING.md).
//
// usage: node tests/web/screenshots.mjs --penumbra build/penumbra [--out docs/images] [--scenes cubes15,materials]
import path from 'node:path';

import { launchBrowser, repo, sleep, startServer, usageOnHelp } from './harness.mjs';
import { openPage } from './page_actions.mjs';

const defaults = { penumbra: path.join(repo, 'build', 'penumbra'), out: path.join(repo, 'docs', 'images'), scenes: 'cubes15,materials',
  startupSeconds: 120 };

async function shoot(browser, args, name) {
  const { server, url } = await startServer(args.penumbra, path.join(repo, 'scenes', `${name}.scene.json`), args.startupSeconds);
  try {
    const { page } = await openPage(browser, url);
    await page.evaluate(() => window.penumbra.idle());
    // The render panel's passes for this view (a few seconds in software GL), then a quiet frame.
    await page.waitForFunction(() => {
      const { passes, renders } = window.penumbra.renderPasses();
      return renders > 0 && passes.length > 0 && passes[passes.length - 1].samples >= 16;
    }, null, { timeout: 120000 }).catch(() => console.log(`${name}: the server render did not finish its passes; saved as it was`));
    await sleep(500);
    const file = path.join(args.out, `page_${name}.png`);
    await page.screenshot({ path: file });
    console.log(`wrote ${path.relative(repo, file)}`);
    await page.close();
  } finally {
    server.kill('SIGTERM');
  }
}

async function main() {
  const args = usageOnHelp(process.argv, defaults, 'node tests/web/screenshots.mjs --penumbra build/penumbra [--out DIR] [--scenes a,b]');
  const browser = await launchBrowser();
  try {
    for (const name of String(args.scenes).split(',')) await shoot(browser, args, name);
  } finally {
    await browser.close();
  }
}

main().catch((error) => { console.error(error); process.exit(1); });
