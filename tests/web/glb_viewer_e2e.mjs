#!/usr/bin/env node
// A GLB export opened in a standard viewer: `penumbra build SCENE --out X.glb`, then a plain page
// with no Penumbra code (three.js from web_client/node_modules, served to Debian's chromium by
// playwright's request routing) loads it with three.js's GLTFLoader and draws it as a glTF viewer
// does: as loaded (unlit vertex colours, the lights' emissive materials), from the file's own
// camera, sRGB output, no tone mapping. Checks: the file's meshes and camera arrive; the image
// is not blank; the light shows white; on the floor, pixels at vertices the file's _IRRADIANCE
// puts in the umbra, the penumbra and the full light are drawn in that order of brightness (the
// soft shadows show), and the lit floor is not flat white. Writes the canvas as a PNG (README).
//
// usage: node tests/web/glb_viewer_e2e.mjs --penumbra build/penumbra [--image build/glb-viewer.png]
import { execFileSync } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';

import { check, launchBrowser, repo, tally, usageOnHelp } from './harness.mjs';

const defaults = { penumbra: path.join(repo, 'build', 'penumbra'), scene: path.join(repo, 'scenes', 'cornell.scene.json'),
  image: path.join(repo, 'build', 'glb-viewer.png'), width: 480, height: 360 };

const origin = 'http://viewer.invalid';
const page = `<!doctype html>
<html><head><meta charset="utf-8"><title>GLB viewer</title>
<style>html, body { margin: 0; background: #202020; } canvas { display: block; }</style>
<script type="importmap">{ "imports": { "three": "/three/build/three.module.js", "three/addons/": "/three/examples/jsm/" } }</script>
</head><body></body></html>`;

const contentTypes = { '.html': 'text/html', '.js': 'text/javascript', '.glb': 'model/gltf-binary' };

// Serves the page, three.js and the GLB at `origin` from this machine's files.
async function routeViewer(browserPage, glb) {
  const three = path.join(repo, 'web_client', 'node_modules', 'three');
  await browserPage.route(`${origin}/**`, async (route) => {
    const url = new URL(route.request().url());
    if (url.pathname === '/') return route.fulfill({ contentType: contentTypes['.html'], body: page });
    const file = url.pathname === '/model.glb' ? glb : path.join(three, path.normalize(url.pathname.replace(/^\/three\//, '')));
    if (file !== glb && (!url.pathname.startsWith('/three/') || !file.startsWith(three + path.sep) || !fs.existsSync(file)))
      return route.fulfill({ status: 404 });
    return route.fulfill({ contentType: contentTypes[path.extname(file)] || 'application/octet-stream', body: fs.readFileSync(file) });
  });
}

// In the page: load, draw, and measure (rows of the pixels read back run bottom to top). An
// object-id pass (each mesh one flat colour) says which surface each pixel shows, so a floor vertex is measured only where a 5×5 block around its pixel
// is all floor.
function viewAndMeasure({ width, height, floorId, lightId }) {
  return (async () => {
    const THREE = await import('three');
    const { GLTFLoader } = await import('three/addons/loaders/GLTFLoader.js');
    const gltf = await new GLTFLoader().loadAsync('/model.glb');
    const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    renderer.setSize(width, height);
    document.body.appendChild(renderer.domElement);
    const view = new THREE.Scene();
    view.background = new THREE.Color(0x202020);
    view.add(gltf.scene);
    view.updateMatrixWorld(true);
    const camera = gltf.cameras[0];
    if (!camera) return { error: 'the GLB has no camera' };
    camera.aspect = width / height;
    camera.updateProjectionMatrix();

    const meshes = [];
    gltf.scene.traverse((o) => { if (o.isMesh) meshes.push(o); });
    // Object ids, unblended (a render target has no antialiasing): mesh i drawn as colour i + 1.
    const materials = meshes.map((m) => m.material);
    meshes.forEach((m, i) => { m.material = new THREE.MeshBasicMaterial({ color: new THREE.Color().setHex(i + 1, THREE.LinearSRGBColorSpace) }); });
    const target = new THREE.WebGLRenderTarget(width, height);
    renderer.setRenderTarget(target);
    renderer.render(view, camera);
    const idPixels = new Uint8Array(width * height * 4);
    renderer.readRenderTargetPixels(target, 0, 0, width, height, idPixels);
    renderer.setRenderTarget(null);
    meshes.forEach((m, i) => { m.material.dispose(); m.material = materials[i]; });
    // The view as a viewer shows it.
    renderer.render(view, camera);
    const pixels = new Uint8Array(width * height * 4);
    const gl = renderer.getContext();
    gl.readPixels(0, 0, width, height, gl.RGBA, gl.UNSIGNED_BYTE, pixels);

    const at = (x, y) => 4 * ((height - 1 - y) * width + x);
    const idAt = (x, y) => { const k = at(x, y); return (idPixels[k] << 16 | idPixels[k + 1] << 8 | idPixels[k + 2]) - 1; };
    const floorIndex = meshes.findIndex((m) => m.name === floorId);
    const lightIndex = meshes.findIndex((m) => m.name === lightId);
    // The mean of the 5×5 block's three channels around a point, or null unless all of it shows mesh `index`.
    const block = (point, index) => {
      const p = point.clone().project(camera);
      const x = Math.round((p.x + 1) / 2 * width - 0.5), y = Math.round((1 - p.y) / 2 * height - 0.5);
      if (p.z > 1 || x < 2 || y < 2 || x >= width - 2 || y >= height - 2) return null;
      const sum = [0, 0, 0];
      for (let dy = -2; dy <= 2; ++dy) {
        for (let dx = -2; dx <= 2; ++dx) {
          if (idAt(x + dx, y + dy) !== index) return null;
          for (let c = 0; c < 3; ++c) sum[c] += pixels[at(x + dx, y + dy) + c];
        }
      }
      return sum.map((s) => s / 25);
    };

    // Floor vertices by their exact irradiance relative to the floor's brightest.
    const floor = meshes[floorIndex];
    const groups = { umbra: [], penumbra: [], lit: [] };
    let saturated = 0, measured = 0;
    if (floor) {
      const position = floor.geometry.attributes.position, irradiance = floor.geometry.attributes._irradiance;
      let maxE = 0;
      for (let i = 0; i < irradiance.count; ++i) maxE = Math.max(maxE, irradiance.getX(i));
      for (let i = 0; i < position.count; ++i) {
        const rgb = block(new THREE.Vector3().fromBufferAttribute(position, i).applyMatrix4(floor.matrixWorld), floorIndex);
        if (!rgb) continue;
        ++measured;
        if (Math.max(...rgb) >= 254.5) ++saturated;
        const e = irradiance.getX(i) / maxE, luminance = (rgb[0] + rgb[1] + rgb[2]) / 3;
        if (e <= 0.05) groups.umbra.push(luminance);
        else if (e >= 0.3 && e <= 0.6) groups.penumbra.push(luminance);
        else if (e >= 0.9) groups.lit.push(luminance);
      }
    }
    const median = (v) => { const s = [...v].sort((a, b) => a - b); return s.length ? s[s.length >> 1] : null; };

    // The light: the centre of its mesh's corners.
    let lightRgb = null;
    const light = meshes[lightIndex];
    if (light) {
      const centre = new THREE.Vector3();
      const corners = light.geometry.attributes.position;
      for (let i = 0; i < corners.count; ++i) centre.add(new THREE.Vector3().fromBufferAttribute(corners, i));
      lightRgb = block(centre.divideScalar(corners.count).applyMatrix4(light.matrixWorld), lightIndex);
    }

    // Blank or not: the spread of the image's brightness.
    const levels = new Set();
    let sum = 0, sumSquares = 0;
    for (let k = 0; k < pixels.length; k += 4) {
      const l = (pixels[k] + pixels[k + 1] + pixels[k + 2]) / 3;
      levels.add(Math.round(l)); sum += l; sumSquares += l * l;
    }
    const n = pixels.length / 4, mean = sum / n;
    return { meshNames: meshes.map((m) => m.name), cameras: gltf.cameras.length,
      levels: levels.size, mean, deviation: Math.sqrt(Math.max(0, sumSquares / n - mean * mean)),
      lightRgb, measured, saturated,
      counts: Object.fromEntries(Object.entries(groups).map(([k, v]) => [k, v.length])),
      medians: Object.fromEntries(Object.entries(groups).map(([k, v]) => [k, median(v)])) };
  })();
}

async function main() {
  const args = usageOnHelp(process.argv, defaults,
    'node tests/web/glb_viewer_e2e.mjs --penumbra build/penumbra [--scene SCENE] [--image PNG] [--width W --height H]');
  const deadline = setTimeout(() => { console.log('FAIL the test took over 2 minutes'); process.exit(1); }, 120000);
  const folder = fs.mkdtempSync(path.join(os.tmpdir(), 'penumbra-viewer-'));
  let browser = null;
  try {
    const scene = JSON.parse(fs.readFileSync(args.scene, 'utf8'));
    const glb = path.join(folder, 'model.glb');
    execFileSync(args.penumbra, ['build', args.scene, '--out', glb, '--threads', '2'], { stdio: ['ignore', 'ignore', 'pipe'] });
    browser = await launchBrowser();
    const browserPage = await browser.newPage({ viewport: { width: args.width, height: args.height } });
    const pageErrors = [];
    browserPage.on('pageerror', (error) => pageErrors.push(error.message));
    browserPage.on('console', (message) => { if (message.type() === 'error') pageErrors.push(message.text()); });
    await routeViewer(browserPage, glb);
    await browserPage.goto(`${origin}/`);
    const floorId = scene.objects[0].id, lightId = scene.lights[0].id;
    const m = await browserPage.evaluate(viewAndMeasure, { width: args.width, height: args.height, floorId, lightId });
    if (m.error) throw new Error(m.error);
    console.log(`     ${JSON.stringify(m.counts)} medians ${JSON.stringify(m.medians)} light ${JSON.stringify(m.lightRgb)} ` +
                `levels ${m.levels} deviation ${m.deviation.toFixed(1)} saturated ${m.saturated}/${m.measured}`);

    const names = new Set(m.meshNames);
    const ids = [...scene.objects, ...scene.lights].map((o) => o.id);
    check(ids.every((id) => names.has(id)) && m.meshNames.length === ids.length,
      'GLTFLoader reads one mesh per object and per light, named by its id', m.meshNames.join(' '));
    check(m.cameras === 1, 'the scene\'s camera arrives as the file\'s camera');
    check(pageErrors.length === 0, 'the viewer page logs no error', pageErrors.join('; '));
    check(m.levels >= 64 && m.deviation >= 20, 'the image is not blank',
      `${m.levels} brightness levels, deviation ${m.deviation.toFixed(1)}`);
    check(m.lightRgb && m.lightRgb.every((c) => c >= 250), 'the light shows white (its emissive material)', JSON.stringify(m.lightRgb));
    const { umbra, penumbra, lit } = m.medians;
    check(m.counts.umbra >= 3 && m.counts.penumbra >= 3 && m.counts.lit >= 3,
      'the floor shows vertices in umbra, penumbra and full light', JSON.stringify(m.counts));
    // sRGB steps of 255: the penumbra lies well between the umbra (ambient only) and the full light.
    check(umbra !== null && penumbra !== null && lit !== null && umbra + 15 <= penumbra && penumbra + 15 <= lit,
      'the floor\'s umbra, penumbra and lit pixels are drawn darker to brighter', JSON.stringify(m.medians));
    check(m.saturated <= 0.1 * m.measured, 'the lit floor is not flat white (COLOR_0 within [0, 1] by the exposure)',
      `${m.saturated} of ${m.measured} floor samples have a channel at 255`);

    const canvas = await browserPage.$('canvas');
    fs.mkdirSync(path.dirname(path.resolve(args.image)), { recursive: true });
    await canvas.screenshot({ path: args.image });
    console.log(`     image: ${args.image} (${fs.statSync(args.image).size} bytes)`);
  } catch (error) {
    check(false, 'the test ran to the end', error.stack || String(error));
  } finally {
    if (browser) await browser.close();
    fs.rmSync(folder, { recursive: true, force: true });
    clearTimeout(deadline);
  }
  process.exit(tally() ? 1 : 0);
}

main();
