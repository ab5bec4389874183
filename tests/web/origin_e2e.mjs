#!/usr/bin/env node
// Browsers cannot be used against the server (issue 36, item 6), in chromium: a page served from
// a second origin (a node server on another port) posts an edit to the token-less server the way
// a malicious site would (fetch no-cors with text/plain, and an HTML form): the scene's version
// does not move. The same fetch from the server's own page applies.
//
// usage: node tests/web/origin_e2e.mjs --penumbra build/penumbra [--scene scenes/cubes15.scene.json]
import http from 'node:http';
import path from 'node:path';

import { check, parseArgs, repo, runWithServerAndBrowser, sleep, usageOnHelp } from './harness.mjs';

const defaults = { penumbra: path.join(repo, 'build', 'penumbra'), scene: path.join(repo, 'scenes', 'cubes15.scene.json'),
  startupSeconds: 120 };

const frame = JSON.stringify({ edits: [{ op: 'move', id: 'cube_3', transform: { translate: [0.1, 0.5, 0] } }] });

// A page that writes to `target` as a foreign site can: a no-cors fetch and a form post.
function attackerPage(target) {
  return `<!doctype html><html><body>
<form id="f" method="POST" action="${target}" enctype="text/plain" target="sink">
<input name='${frame.slice(0, -1)}, "x": "' value='"}'></form><iframe name="sink"></iframe>
<script>
fetch(${JSON.stringify(target)}, { method: 'POST', mode: 'no-cors', headers: { 'Content-Type': 'text/plain' },
  body: ${JSON.stringify(frame)} }).finally(() => { document.getElementById('f').submit(); document.title = 'sent'; });
</script></body></html>`;
}

async function version(base, sceneId) {
  return (await (await fetch(`${base}/api/scenes/${sceneId}`)).json()).version;
}

async function main() {
  const options = parseArgs(process.argv.slice(2), defaults);
  usageOnHelp(process.argv.slice(2), defaults, 'node tests/web/origin_e2e.mjs --penumbra build/penumbra');
  await runWithServerAndBrowser(options, async ({ browser, url, base, sceneId }) => {
    const target = `${base}/api/scenes/${sceneId}/edits`;
    const foreign = http.createServer((req, res) => { res.setHeader('Content-Type', 'text/html'); res.end(attackerPage(target)); });
    await new Promise((resolve) => foreign.listen(0, '127.0.0.1', resolve));
    const foreignUrl = `http://localhost:${foreign.address().port}/`;  // another origin (host and port)
    try {
      const before = await version(base, sceneId);
      const page = await browser.newPage();
      await page.goto(foreignUrl);
      await page.waitForFunction(() => document.title === 'sent', null, { timeout: 20000 });
      await sleep(1500);  // the form's navigation lands in the iframe
      check(await version(base, sceneId) === before, 'a page of another origin cannot edit the scene (fetch and form post)',
        `version ${before} → ${await version(base, sceneId)}`);
      await page.goto(url);  // the server's own page: the same request applies
      const status = await page.evaluate(async ([t, body]) => (await fetch(t, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body })).status,
        [target, frame]);
      check(status === 200 && await version(base, sceneId) === before + 1, 'the server\'s own page edits it', `status ${status}`);
    } finally {
      foreign.close();
    }
  });
}

main();
