#!/usr/bin/env node
// End-to-end test of interchange in the page (Debian's chromium driven by playwright-core):
// starts `penumbra serve SCENE --port 0`; in the page, three.js's GLTFLoader reads the lit mesh as
// GLB (GET /api/scenes/ID/mesh?format=glb) and the test checks the vertex count of every object
// against the mesh JSON per the exporter's layout (README "Import and export": a receiver's mesh
// vertices, then the corners of each face no light reaches), COLOR_0 = albedo/π × irradiance ×
// the served colour scale, unlit materials, and that the shadows show when three.js draws it.
// Then it loads the millimetre Cornell box OBJ + MTL through the page's file input (scale 0.001),
// checks the page switches to the new scene, shows its light and lit floor, and the import report;
// and a broken OBJ is refused with the server's error in the banner. Prints the import + build time.
//
// usage: node tests/web/interchange_e2e.mjs --penumbra build/penumbra [--screenshot build/web-interchange.png]
import fs from 'node:fs';
import path from 'node:path';

import { check, repo, runWithServerAndBrowser, usageOnHelp } from './harness.mjs';

const data = path.join(repo, 'tests', 'interchange', 'data');
const defaults = { penumbra: path.join(repo, 'build', 'penumbra'), scene: path.join(repo, 'scenes', 'cornell.scene.json'),
    screenshot: path.join(repo, 'build', 'web-interchange.png'), startupSeconds: 120 };

const pageReady = () => window.penumbra && (window.penumbra.state().ready || window.penumbra.state().bannerVisible);

// In the page: GLTFLoader reads the served GLB; every object's vertex count and some vertices'
// positions and colours are compared with the mesh JSON and scene JSON of the same version.
async function glbChecks(page, sceneId) {
  return page.evaluate(async (sceneId) => {
    const THREE = await import('three');
    const { GLTFLoader } = await import('/node_modules/three/examples/jsm/loaders/GLTFLoader.js');
    const glbResponse = await fetch(`/api/scenes/${sceneId}/mesh?format=glb`);
    if (!glbResponse.ok) return { error: `GET mesh?format=glb: ${glbResponse.status} ${await glbResponse.text()}` };
    const contentType = glbResponse.headers.get('Content-Type');
    const headerScale = Number(glbResponse.headers.get('X-Penumbra-Color-Scale'));
    const glbVersion = glbResponse.headers.get('X-Penumbra-Version');
    const gltf = await new GLTFLoader().parseAsync(await glbResponse.arrayBuffer(), '');
    const meshResponse = await fetch(`/api/scenes/${sceneId}/mesh`);
    const meshJson = await meshResponse.json();
    const { scene } = await (await fetch(`/api/scenes/${sceneId}`)).json();
    const scale = gltf.asset.extras && gltf.asset.extras.penumbra ? gltf.asset.extras.penumbra.color_scale : null;
    const ambient = gltf.asset.extras && gltf.asset.extras.penumbra ? gltf.asset.extras.penumbra.ambient : null;

    const meshes = new Map();
    gltf.scene.traverse((o) => { if (o.isMesh) meshes.set(o.name, o); });
    const close = (a, b) => Math.abs(a - b) <= 1e-6 * Math.max(1, Math.abs(b));
    const perObject = [];
    let colourChecks = 0, colourMismatches = 0, positionMismatches = 0, unlit = 0, expectedTotal = 0, totalVertices = 0;
    const examples = [];
    for (const object of scene.objects) {
      const mesh = meshes.get(object.id);
      const albedo = object.material ? scene.materials[object.material].albedo : [0.8, 0.8, 0.8];
      const receivers = meshJson.receivers.filter((r) => r.object === object.id);
      const received = new Set(receivers.map((r) => r.face));
      const darkCorners = object.faces.reduce((n, face, i) => n + (received.has(i) ? 0 : face.length), 0);
      const expected = receivers.reduce((n, r) => n + r.positions.length, 0) + darkCorners;
      expectedTotal += expected;
      if (!mesh) { perObject.push({ id: object.id, missing: true, expected }); continue; }
      const position = mesh.geometry.attributes.position;
      const color = mesh.geometry.attributes.color;
      const exact = mesh.geometry.attributes._radiance;  // GLTFLoader keeps _RADIANCE lower-cased
      totalVertices += position.count;
      if (mesh.material.isMeshBasicMaterial && mesh.material.vertexColors) ++unlit;
      perObject.push({ id: object.id, vertices: position.count, expected });
      // Vertices in layout order: this object's receivers in mesh order. Check the first, the
      // brightest and the darkest of each receiver (a penumbra's two sides).
      let base = 0;
      for (const r of receivers) {
        const radiance = (k) => [0, 1, 2].map((c) => albedo[c] / Math.PI * r.irradiance[k][c]);
        const order = r.irradiance.map((e, k) => [e[0] + e[1] + e[2], k]).sort((a, b) => a[0] - b[0]);
        for (const k of new Set([0, order[0][1], order[order.length - 1][1]])) {
          // COLOR_0: the page's display colour, min(1, scale × albedo/π × (E + ambient)); _RADIANCE exact.
          const want = radiance(k).map((x, c) => Math.min(1, scale * (x + albedo[c] / Math.PI * ambient[c])));
          const got = [color.getX(base + k), color.getY(base + k), color.getZ(base + k)];
          const gotExact = exact ? [exact.getX(base + k), exact.getY(base + k), exact.getZ(base + k)] : null;
          ++colourChecks;
          if (!want.every((x, c) => close(got[c], x)) || !gotExact || !radiance(k).every((x, c) => close(gotExact[c], x))) {
            ++colourMismatches;
            if (examples.length < 5) examples.push({ object: object.id, face: r.face, vertex: k, want, got, exact: radiance(k), gotExact });
          }
          const p = [position.getX(base + k), position.getY(base + k), position.getZ(base + k)];
          if (!p.every((x, c) => Math.abs(x - r.positions[k][c]) <= 1e-6 * Math.max(1, Math.abs(r.positions[k][c])))) ++positionMismatches;
        }
        base += r.positions.length;
      }
    }
    // Each light: its own mesh, named by its id, emitting radiance × scale (emissive × intensity).
    const lights = scene.lights.map((l) => meshes.get(l.id)).filter((m) => m);
    const lightCorners = scene.lights.reduce((n, l) => n + l.polygon.length, 0);
    const lightVertices = lights.reduce((n, m) => n + m.geometry.attributes.position.count, 0);
    const first = meshes.get(scene.lights[0].id);
    const lightColour = first ? [0, 1, 2].map((c) => first.material.emissive.toArray()[c] * first.material.emissiveIntensity) : null;

    // Draw the GLB as three.js shows it (unlit, vertex colours) from the scene's camera: the
    // floor must show both light and shadow (the baked soft shadows are visible).
    const width = 320, height = 240;
    const renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
    renderer.setSize(width, height, false);
    renderer.outputColorSpace = THREE.LinearSRGBColorSpace;
    const cam = scene.camera;
    const camera = new THREE.PerspectiveCamera(cam.fov_y_deg, width / height, cam.near, cam.far);
    camera.position.set(...cam.position);
    camera.up.set(...cam.up);
    camera.lookAt(new THREE.Vector3(...cam.target));
    const view = new THREE.Scene();
    view.add(gltf.scene);
    renderer.render(view, camera);
    const pixels = new Uint8Array(width * height * 4);
    const gl = renderer.getContext();
    gl.readPixels(0, 0, width, height, gl.RGBA, gl.UNSIGNED_BYTE, pixels);
    // The floor's pixels: project the floor's receiver vertices' bounding box centre region.
    const floor = meshes.get(scene.objects[0].id);
    let bright = 0, dark = 0, floorPixels = 0; const sums = [];
    const raycaster = new THREE.Raycaster();
    for (let j = 4; j < height; j += 8) {
      for (let i = 4; i < width; i += 8) {
        raycaster.setFromCamera(new THREE.Vector2(i / width * 2 - 1, 1 - j / height * 2), camera);
        const hit = raycaster.intersectObjects(gltf.scene.children, true)[0];
        if (!hit || hit.object !== floor) continue;
        ++floorPixels;
        const at = 4 * ((height - 1 - j) * width + i);
        const g = pixels[at] + pixels[at + 1] + pixels[at + 2];
        sums.push(g);
      }
    }
    renderer.dispose();
    // Linear colours scaled to the brightest vertex (near the light): the floor is dimmer, so
    // light and shadow are judged against the floor's brightest pixel.
    const floorMax = Math.max(0, ...sums);
    for (const g of sums) { if (g >= 0.5 * floorMax) ++bright; else if (g <= 0.1 * floorMax) ++dark; }
    return { contentType, headerScale, scale, glbVersion, meshVersion: meshResponse.headers.get('X-Penumbra-Version'),
      perObject, totalVertices, expectedTotal, colourChecks, colourMismatches, positionMismatches, examples,
      unlit, objects: scene.objects.length, lightVertices, lightCorners,
      lightColour, lightRadiance: scene.lights[0].radiance, floorPixels, floorMax, bright, dark };
  }, sceneId);
}

async function glbTest(page, sceneId) {
  const r = await glbChecks(page, sceneId);
  if (!check(!r.error, 'GLTFLoader read GET /mesh?format=glb', r.error)) return;
  check(r.contentType === 'model/gltf-binary', 'the GLB is served as model/gltf-binary', r.contentType);
  check(r.glbVersion === r.meshVersion, 'GLB and mesh JSON are of the same version', `${r.glbVersion} vs ${r.meshVersion}`);
  check(r.scale > 0 && r.scale === r.headerScale, 'asset.extras.penumbra.color_scale = X-Penumbra-Color-Scale', `${r.scale} vs ${r.headerScale}`);
  const wrong = r.perObject.filter((o) => o.missing || o.vertices !== o.expected);
  check(wrong.length === 0 && r.perObject.length === r.objects,
    'every object\'s GLB mesh has the mesh JSON\'s vertex count (receivers\' vertices + dark faces\' corners)', JSON.stringify(wrong));
  check(r.totalVertices === r.expectedTotal && r.totalVertices > 0, `GLB vertices total ${r.totalVertices} = expected ${r.expectedTotal}`);
  check(r.lightVertices === r.lightCorners, 'the lights\' meshes have the lights\' corners', `${r.lightVertices} vs ${r.lightCorners}`);
  check(r.colourChecks >= 3 * r.objects && r.colourMismatches === 0 && r.positionMismatches === 0,
    `COLOR_0 = min(1, color_scale × albedo/π × (E + ambient)), _RADIANCE = albedo/π × E and POSITION = the mesh's, at ${r.colourChecks} vertices`,
    JSON.stringify(r.examples));
  check(r.lightColour && r.lightColour.every((x, c) => Math.abs(x - r.lightRadiance[c] * r.scale) <= 1e-5 * Math.max(1, x)),
    'the light emits its radiance × color_scale (emissive × KHR_materials_emissive_strength)', JSON.stringify(r.lightColour));
  check(r.unlit === r.objects, 'GLTFLoader made unlit vertex-coloured materials (KHR_materials_unlit)', `${r.unlit} of ${r.objects}`);
  check(r.floorPixels > 50 && r.floorMax >= 20 && r.bright > 5 && r.dark > 5,
    'drawn by three.js, the floor shows both light and shadow',
    JSON.stringify({ floorPixels: r.floorPixels, floorMax: r.floorMax, bright: r.bright, dark: r.dark }));
}

// Posts the Cornell OBJ + MTL from node (as a browser form would) and times it.
async function timeImport(base) {
  const form = new FormData();
  form.append('file', new Blob([fs.readFileSync(path.join(data, 'cornell_mm.obj'))]), 'cornell_mm.obj');
  form.append('mtl', new Blob([fs.readFileSync(path.join(data, 'cornell_mm.mtl'))]), 'cornell_mm.mtl');
  const start = performance.now();
  const response = await fetch(`${base}/api/scenes?scale=0.001&name=timed`, { method: 'POST', body: form });
  const wall = (performance.now() - start) / 1000;
  const body = await response.json();
  check(response.status === 201, 'POST /api/scenes with the OBJ + MTL form: 201', JSON.stringify(body));
  console.log(`     Cornell OBJ over HTTP: request ${wall.toFixed(3)} s, import ${body.import && body.import.seconds.toFixed(4)} s, build ${body.build_seconds && body.build_seconds.toFixed(4)} s (${body.faces} faces, ${body.receivers} receivers)`);
  await fetch(`${base}/api/scenes/${body.id}`, { method: 'DELETE' });
}

async function objUploadTest(page, pageErrors, base, screenshot) {
  await page.fill('#import-scale', '0.001');
  const navigated = page.waitForURL(/scene=cornell_mm/, { timeout: 60000 });
  await page.setInputFiles('#scene-file', [path.join(data, 'cornell_mm.obj'), path.join(data, 'cornell_mm.mtl')]);
  await navigated;
  await page.waitForFunction(pageReady, null, { timeout: 120000 });
  const state = await page.evaluate(() => window.penumbra.state());
  check(state.ready && state.sceneId === 'cornell_mm' && state.receivers > 0 && state.vertices > 0,
    'the page switched to the imported scene and shows its mesh', JSON.stringify({ ...state, lastFrame: undefined }));
  const served = await (await fetch(`${base}/api/scenes/cornell_mm`)).json();
  const light = served.scene.lights[0];
  check(served.scene.lights.length === 1 && JSON.stringify(light.radiance) === '[17,12,4]' &&
    light.polygon.every((p) => Math.abs(p[1] - 0.5488) < 1e-9),
  'the server holds the light where the file puts it (metres) with its Ke radiance', JSON.stringify(light));
  // The floor under the light's centre is lit; the page interpolates it from its own mesh.
  const centre = light.polygon.reduce((s, p) => s.map((x, k) => x + p[k] / light.polygon.length), [0, 0, 0]);
  const floor = served.scene.objects.find((o) => o.id === 'floor');
  const under = await page.evaluate((p) => window.penumbra.irradianceAt('floor', 0, p), [centre[0], 0, centre[2]]);
  // A rough independent figure: the light as a point source straight above, E ≈ L·A/d² (the mesh
  // interpolates linearly between its vertices, so it may be lower, not by half).
  const [a, b, c] = light.polygon;
  const edge1 = [0, 1, 2].map((k) => b[k] - a[k]), edge2 = [0, 1, 2].map((k) => c[k] - b[k]);
  const area = Math.hypot(edge1[1] * edge2[2] - edge1[2] * edge2[1], edge1[2] * edge2[0] - edge1[0] * edge2[2],
    edge1[0] * edge2[1] - edge1[1] * edge2[0]);
  const estimate = light.radiance[0] * area / (centre[1] ** 2);
  check(floor && under && under[0] > 0.5 * estimate && under[0] < 1.01 * estimate,
    'the page\'s floor is lit under the imported light', `${JSON.stringify(under)} vs L·A/d² = ${estimate}`);
  const report = await page.evaluate(() => {
    const root = document.getElementById('import-report');
    return { hidden: root.hidden, text: root.textContent, repairs: [...root.querySelectorAll('li')].map((li) => li.dataset.repair) };
  });
  check(!report.hidden && /Imported cornell_mm\.obj \(obj\)/.test(report.text) && /1 light/.test(report.text),
    'the page shows the import report', report.text);
  check(report.repairs.includes('non_planar_polygons_split'), 'the report lists the repairs (the non-planar wall split)', JSON.stringify(report.repairs));
  const final = await page.evaluate(() => window.penumbra.state());
  check(!final.bannerVisible && pageErrors.length === 0, 'no error banner or console error', JSON.stringify([final.errors, pageErrors]));
  fs.mkdirSync(path.dirname(screenshot), { recursive: true });
  await page.screenshot({ path: screenshot });
  console.log(`     screenshot: ${screenshot}`);

  // A broken OBJ: refused whole, the server's code and key path in the banner, no scene added.
  const before = (await (await fetch(`${base}/api/scenes`)).json()).scenes.length;
  await page.setInputFiles('#scene-file', { name: 'broken.obj', mimeType: 'model/obj', buffer: Buffer.from('v 0 0 0\nv 1 0 0\nf 1 2 9\n') });
  await page.waitForFunction(() => window.penumbra.state().bannerVisible, null, { timeout: 10000 }).catch(() => {});
  const banner = await page.evaluate(() => ({ visible: window.penumbra.state().bannerVisible, text: document.getElementById('error-text').textContent }));
  check(banner.visible && /422 invalid_scene/.test(banner.text) && /\(obj\)/.test(banner.text),
    'a broken OBJ shows the server\'s 422 with the importer\'s path in the banner', banner.text);
  const after = (await (await fetch(`${base}/api/scenes`)).json()).scenes.length;
  check(after === before, 'the refused OBJ created no scene', `${before} → ${after}`);
  // An .mtl alone is refused by the page before anything is sent.
  await page.setInputFiles('#scene-file', { name: 'lonely.mtl', mimeType: 'text/plain', buffer: Buffer.from('newmtl a\n') });
  await page.waitForFunction(() => /need their \.obj/.test(document.getElementById('error-text').textContent), null, { timeout: 10000 }).catch(() => {});
  check(/need their \.obj/.test(await page.textContent('#error-text')), 'an .mtl picked without its .obj is explained');
}

async function main() {
  const args = usageOnHelp(process.argv, defaults, 'node tests/web/interchange_e2e.mjs --penumbra build/penumbra [--screenshot PNG]');
  await runWithServerAndBrowser(args, async ({ browser, url, base, sceneId }) => {
    const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
    const pageErrors = [];
    page.on('pageerror', (error) => pageErrors.push(error.message));
    page.on('console', (message) => {
      // The refused uploads below are logged by the banner on purpose.
      if (message.type() === 'error' && !/^penumbra:/.test(message.text())) pageErrors.push(message.text());
    });
    await page.goto(url, { waitUntil: 'domcontentloaded', timeout: 120000 });
    await page.waitForFunction(pageReady, null, { timeout: 120000 });
    if (!check((await page.evaluate(() => window.penumbra.state())).ready, 'the page loaded the scene')) throw new Error('page not ready');
    await glbTest(page, sceneId);
    await timeImport(base);
    await objUploadTest(page, pageErrors, base, args.screenshot);
  });
}

main();
