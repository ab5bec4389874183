// Validates GLB files with the Khronos glTF-Validator (npm gltf-validator, installed into
// web_client/node_modules by .ci/install-web): prints each file's error, warning and info
// counts and every error and warning, and exits 1 when any file has an error or a warning not
// in ALLOWED_WARNINGS (each with why it is expected; none so far).
//   node tests/interchange/gltf_validate.mjs FILE.glb...
//   node tests/interchange/gltf_validate.mjs --penumbra build/penumbra --scenes scenes
// The second form first exports every SCENE.scene.json in the folder (plain, --indirect and
// --edges) and a generated resting teapot, as `penumbra build SCENE --out X.glb` writes them.
import { createRequire } from 'node:module';
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readdirSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { fileURLToPath } from 'node:url';
import path from 'node:path';

const here = path.dirname(fileURLToPath(import.meta.url));
const require = createRequire(path.join(here, '../../web_client/package.json'));
const validator = require('gltf-validator');

const ALLOWED_WARNINGS = new Map([]);

function option(args, name) {
  const at = args.indexOf(name);
  if (at < 0) return null;
  const value = args[at + 1];
  args.splice(at, 2);
  return value;
}

// The GLBs of every bundled scene, written into `folder`.
function exportScenes(penumbra, scenes, folder) {
  const files = [];
  const run = (args) => execFileSync(penumbra, args, { stdio: ['ignore', 'ignore', 'pipe'] });
  for (const name of readdirSync(scenes).filter((n) => n.endsWith('.scene.json')).sort()) {
    const scene = path.join(scenes, name);
    const stem = path.join(folder, name.replace('.scene.json', ''));
    for (const [suffix, extra] of [['', []], ['-indirect', ['--indirect']], ['-edges', ['--edges']]]) {
      run(['build', scene, '--out', `${stem}${suffix}.glb`, '--threads', '2', ...extra]);
      files.push(`${stem}${suffix}.glb`);
    }
  }
  const teapot = path.join(folder, 'teapot.scene.json');
  run(['generate', '--model', 'teapot', '--triangles', '992', '--rest', '--out', teapot]);
  run(['build', teapot, '--out', path.join(folder, 'teapot.glb'), '--threads', '2']);
  files.push(path.join(folder, 'teapot.glb'));
  return files;
}

const args = process.argv.slice(2);
const penumbra = option(args, '--penumbra'), scenes = option(args, '--scenes');
const files = [...args];
let folder = null;
if (penumbra && scenes) {
  folder = mkdtempSync(path.join(tmpdir(), 'penumbra-glb-'));
  files.push(...exportScenes(penumbra, scenes, folder));
}
if (!files.length) {
  console.error('usage: gltf_validate.mjs FILE.glb... | --penumbra PENUMBRA --scenes DIR');
  process.exit(2);
}
let failed = false;
for (const file of files) {
  const report = await validator.validateBytes(new Uint8Array(readFileSync(file)), { uri: path.basename(file), maxIssues: 0 });
  const { numErrors, numWarnings, numInfos } = report.issues;
  console.log(`${path.basename(file)}: ${numErrors} errors, ${numWarnings} warnings, ${numInfos} infos`);
  for (const m of report.issues.messages) {
    if (m.severity > 1) continue;  // 0 error, 1 warning, 2 info, 3 hint
    const allowed = m.severity === 1 && ALLOWED_WARNINGS.has(m.code);
    console.log(`  ${m.severity === 0 ? 'error' : 'warning'} ${m.code} ${m.pointer || ''}: ${m.message}` +
                (allowed ? ` (allowed: ${ALLOWED_WARNINGS.get(m.code)})` : ''));
    if (!allowed) failed = true;
  }
}
if (folder) rmSync(folder, { recursive: true, force: true });
process.exit(failed ? 1 : 0);
