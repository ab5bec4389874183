#!/usr/bin/env node
// A long server render from the page (sensor GI of the 15-cube room, seconds): the render panel
// shows the server's stage and fraction as they move, with a Cancel button; Cancel stops the
// render on the server (DELETE of its ticket; the job ends "cancelled" within --cancelSeconds),
// the panel says it stopped and nothing is shown as an error. A render stops at its next progress
// report: for GI every 64 sensors (tens of milliseconds). The progress comes through
// the scene's event stream: the page polls no render list meanwhile.
//
// usage: node tests/web/render_cancel_e2e.mjs --penumbra build/penumbra [--cancelSeconds 8]
import path from 'node:path';

import { check, repo, runWithServerAndBrowser, until, usageOnHelp } from './harness.mjs';
import { openPage } from './page_actions.mjs';

const defaults = { penumbra: path.join(repo, 'build', 'penumbra'), scene: path.join(repo, 'scenes', 'cubes15.scene.json'),
  startupSeconds: 120, cancelSeconds: 8 };

async function renders(base, sceneId) {
  const response = await fetch(`${base}/api/scenes/${sceneId}/renders`);
  return (await response.json()).renders;
}

async function main() {
  const args = usageOnHelp(process.argv, defaults, 'node tests/web/render_cancel_e2e.mjs --penumbra build/penumbra [--cancelSeconds S]');
  await runWithServerAndBrowser(args, async ({ browser, url, base, sceneId }) => {
    const { page, pageErrors } = await openPage(browser, url);
    check(await until(async () => (await page.evaluate(() => window.penumbra.renderPasses())).passes.length > 0),
      'the server render is shown');
    let polled = 0; // the page's own GET of the scene's render list
    page.on('request', (request) => {
      if (new URL(request.url()).pathname.endsWith('/renders') && request.method() === 'GET') ++polled;
    });
    await page.check('#toggle-gi');
    // The fraction moves while the GI render runs; the Cancel button is there.
    const seen = new Set();
    const moving = await until(async () => {
      const text = await page.textContent('#render-fraction');
      const m = text.match(/^GI sensors (\d+)%$/);
      if (m) seen.add(Number(m[1]));
      return seen.size >= 2 && text;
    }, 60);
    check(moving !== null, 'the panel shows the GI render\'s stage and a moving fraction', JSON.stringify([...seen]));
    check(await page.isVisible('#render-cancel') && await page.isVisible('#render-bar'), 'a Cancel button and a bar show while it runs');
    check(polled === 0, 'the progress came through the scene\'s event stream, no render list polled', `${polled} polls`);
    const running = (await renders(base, sceneId)).filter((r) => r.state === 'running');
    check(running.length === 1 && running[0].progress.stage === 'sensors', 'the server lists the render running', JSON.stringify(running));

    const cancelled = Date.now();
    await page.click('#render-cancel');
    const ended = await until(async () => {
      const job = (await renders(base, sceneId)).find((r) => r.ticket === running[0]?.ticket);
      return job && job.state !== 'running' && job;
    }, args.cancelSeconds);
    check(ended && ended.state === 'cancelled', `Cancel stops the render on the server within ${args.cancelSeconds} s`,
      JSON.stringify({ ended, seconds: (Date.now() - cancelled) / 1000 }));
    check(await until(async () => !(await page.isVisible('#render-cancel')), 5) !== null, 'the Cancel button goes');
    const info = await page.textContent('#render-info');
    check(info.includes('stopped'), 'the panel says the render stopped', info);
    const final = await page.evaluate(() => window.penumbra.state());
    check(!final.errors.length && !final.bannerVisible && !pageErrors.length, 'no error shown or logged',
      JSON.stringify({ errors: final.errors, pageErrors }));
  });
}

main();
