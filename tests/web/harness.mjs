// What the browser end-to-end tests share: option parsing, pass/fail checks and their tally,
// starting `penumbra serve SCENE --port 0` and Debian's chromium (playwright-core), and a run
// wrapper that stops both, prints "N passed, M failed" and exits with the verdict.
import { spawn } from 'node:child_process';
import { createRequire } from 'node:module';
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

export const repo = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
const requireFromPage = createRequire(path.join(repo, 'web_client', 'package.json'));

// --key value pairs over `defaults`; numbers stay numbers.
export function parseArgs(argv, defaults) {
  const args = { ...defaults };
  for (let i = 2; i < argv.length; i += 2) {
    const key = argv[i].replace(/^--/, '');
    if (!(key in args) || i + 1 >= argv.length) throw new Error(`usage: unknown or incomplete option ${argv[i]}`);
    args[key] = typeof defaults[key] === 'number' ? Number(argv[i + 1]) : argv[i + 1];
  }
  return args;
}

// parseArgs for a script's main: --help / -h prints `usage` and the options with their defaults
// and exits 0; a bad option prints the problem and `usage` (no stack trace) and exits 2.
export function usageOnHelp(argv, defaults, usage) {
  const options = Object.entries(defaults).map(([key, value]) => `  --${key} ${value === null ? '(none)' : value}`).join('\n');
  if (argv.includes('--help') || argv.includes('-h')) {
    console.log(`usage: ${usage}\noptions and their defaults:\n${options}`);
    process.exit(0);
  }
  try {
    return parseArgs(argv, defaults);
  } catch (error) {
    console.error(`${error.message.replace(/^usage: /, '')}\nusage: ${usage}\noptions and their defaults:\n${options}`);
    process.exit(2);
  }
}

export const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

// Polls `what` (async) every 200 ms until it gives a truthy value (returned), or null after `seconds`.
export async function until(what, seconds = 60) {
  const deadline = Date.now() + seconds * 1000;
  for (;;) {
    const value = await what();
    if (value) return value;
    if (Date.now() > deadline) return null;
    await sleep(200);
  }
}

let failures = 0;
let passes = 0;
export function check(condition, what, detail = '') {
  if (condition) {
    ++passes;
    console.log(`ok   ${what}`);
  } else {
    ++failures;
    console.log(`FAIL ${what}${detail ? `: ${detail}` : ''}`);
  }
  return condition;
}

// Starts the server (on `port`, 0: any free one; serving the page in `staticDir`; `storage`: its
// journal options, ephemeral unless given; `scene` null: only what the journal holds) and resolves
// with {server, url} once it prints the page's URL.
export function startServer(penumbra, scene, timeoutSeconds, port = 0, staticDir = path.join(repo, 'web_client'),
  storage = ['--ephemeral']) {
  return new Promise((resolve, reject) => {
    const server = spawn(penumbra, ['serve', ...(scene ? [scene] : []), '--port', String(port), ...storage, '--static', staticDir],
      { cwd: repo, stdio: ['ignore', 'pipe', 'pipe'] });
    let out = '';
    let err = '';
    const timer = setTimeout(() => {
      server.kill('SIGTERM');
      reject(new Error(`server printed no URL within ${timeoutSeconds} s\nstdout: ${out}\nstderr: ${err}`));
    }, timeoutSeconds * 1000);
    server.stdout.on('data', (chunk) => {
      out += chunk;
      const match = out.match(/open (http:\/\/\S+\?scene=\S+)/);
      if (match) {
        clearTimeout(timer);
        resolve({ server, url: match[1] });
      }
    });
    server.stderr.on('data', (chunk) => { err += chunk; });
    server.on('exit', (code) => {
      clearTimeout(timer);
      reject(new Error(`server exited (${code}) before printing its URL\nstderr: ${err}`));
    });
  });
}

export async function launchBrowser() {
  let chromium;
  try {
    ({ chromium } = requireFromPage('playwright-core'));
  } catch (error) {
    throw new Error(`playwright-core is not installed (run: bash .ci/install-deps): ${error.message}`);
  }
  const executablePath = process.env.PENUMBRA_CHROMIUM || '/usr/bin/chromium';
  if (!fs.existsSync(executablePath)) throw new Error(`no chromium at ${executablePath} (run: bash .ci/install-deps)`);
  return chromium.launch({
    executablePath,
    args: ['--headless', '--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--disable-gpu-sandbox',
      '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
}

// Starts the server on `scene` and a browser, runs body({browser, base, sceneId, url}),
// then stops both, prints the tally and exits (1 on any failure or after 5 minutes).
export async function runWithServerAndBrowser({ penumbra, scene, startupSeconds }, body) {
  const deadline = setTimeout(() => { console.log('FAIL the test took over 5 minutes'); process.exit(1); }, 300000);
  let server = null;
  let browser = null;
  try {
    let url;
    ({ server, url } = await startServer(penumbra, scene, startupSeconds));
    browser = await launchBrowser();
    await body({ browser, url, server, base: new URL(url).origin, sceneId: new URL(url).searchParams.get('scene') });
  } catch (error) {
    check(false, 'the test ran to the end', error.stack || String(error));
  } finally {
    if (browser) await browser.close();
    if (server) server.kill('SIGTERM');
    clearTimeout(deadline);
  }
  process.exit(tally() ? 1 : 0);
}

// Prints "N passed, M failed" for the checks so far; the number failed.
export function tally() {
  console.log(`${passes} passed, ${failures} failed`);
  return failures;
}
