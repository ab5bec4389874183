#!/usr/bin/env node
// End-to-end test of the page (web_client/) in Debian's chromium driven by playwright-core:
// starts `penumbra serve SCENE --port 0`, opens the printed URL, checks the page's camera maths
// against the C++ renderer's images, selects a cube with a real click, drags the translate
// gizmo's X handle with real mouse events, and asserts the version advanced, the floor's shadow
// moved, undo/redo re-sent the transforms, and no error was shown; saves a screenshot. With
// --measure SCENE it instead drags one cube for a few seconds and prints edits/s, bytes, round
// trips and frames drawn, then times drawing the view (orbiting) with and without antialiasing.
//
// usage: node tests/web/drag_e2e.mjs --penumbra build/penumbra [--scene scenes/cubes15.scene.json]
//          [--screenshot build/web-e2e.png] [--measure build/cubes150.scene.json --seconds 5]
//          [--query drag_scale=0.35]   (extra page query parameters, to compare the page's choices)
import fs from 'node:fs';
import path from 'node:path';

import { check, repo, runWithServerAndBrowser, sleep, usageOnHelp } from './harness.mjs';
import { clickObject, dragXHandle, openPage, serverScene } from './page_actions.mjs';

const defaults = { penumbra: path.join(repo, 'build', 'penumbra'), scene: path.join(repo, 'scenes', 'cubes15.scene.json'),
    screenshot: path.join(repo, 'build', 'web-e2e.png'), measure: null, seconds: 5, startupSeconds: 120, query: '' };

// The renderer's camera maths (docs/API.md, README "Rendering": three.js lookAt view matrix,
// PerspectiveCamera / OrthographicCamera projection, NDC → pixel with y down), written out
// independently of three.js so the page's projection is checked against the formulas.
function formulaPixel(query, point, width, height) {
  const p = (s) => s.split(',').map(Number);
  const eye = p(query.position), target = p(query.target), up = p(query.up);
  const sub = (a, b) => a.map((x, i) => x - b[i]);
  const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  const unit = (a) => a.map((x) => x / Math.hypot(...a));
  const z = unit(sub(eye, target));
  const x = unit(cross(up, z));
  const y = cross(z, x);
  const d = sub(point, eye);
  const v = [dot(d, x), dot(d, y), dot(d, z)]; // view space, looking down -z
  const aspect = width / height;
  let ndcX, ndcY;
  if (query.projection === 'orthographic') {
    const top = Number(query.ortho_height) / 2;
    ndcX = v[0] / (aspect * top);
    ndcY = v[1] / top;
  } else {
    const top = Math.tan(Number(query.fov_y_deg) * Math.PI / 360);
    ndcX = v[0] / (-v[2] * aspect * top);
    ndcY = v[1] / (-v[2] * top);
  }
  return { x: (ndcX + 1) / 2 * width, y: (1 - ndcY) / 2 * height };
}

// In the page: renders `query` on the server, projects the light's corners with a three.js
// camera built from the same parameters, and compares every pixel near the light: a pixel whose
// centre is inside the projected polygon by more than `margin` must show the light's radiance, one
// outside by more than `margin` must not. Returns the counts.
async function lightPixelCheck(page, sceneId, query, light, width, height, lightThreshold) {
  return page.evaluate(async ({ sceneId, query, light, width, height, lightThreshold }) => {
    const THREE = await import('three');
    const v = (s) => new THREE.Vector3(...s.split(',').map(Number));
    const aspect = width / height;
    let camera;
    if (query.projection === 'orthographic') {
      const h = Number(query.ortho_height) / 2;
      camera = new THREE.OrthographicCamera(-aspect * h, aspect * h, h, -h, Number(query.near), Number(query.far));
    } else {
      camera = new THREE.PerspectiveCamera(Number(query.fov_y_deg), aspect, Number(query.near), Number(query.far));
    }
    camera.up.copy(v(query.up));
    camera.position.copy(v(query.position));
    camera.lookAt(v(query.target));
    camera.updateMatrixWorld();
    const corners = light.map((p) => {
      const ndc = new THREE.Vector3(...p).project(camera);
      return [(ndc.x + 1) / 2 * width, (1 - ndc.y) / 2 * height];
    });
    // Linear radiance (EXR): the light shows its emitted radiance, surfaces far less, whatever
    // the PNG's exposure would clip.
    const params = new URLSearchParams({ width, height, ...query, format: 'exr' });
    const response = await fetch(`/api/scenes/${sceneId}/image?${params}`);
    if (!response.ok) return { error: `${response.status} ${await response.text()}` };
    const { EXRLoader } = await import('three/addons/loaders/EXRLoader.js');
    const loader = new EXRLoader();
    loader.setDataType(THREE.FloatType);
    const exr = loader.parse(await response.arrayBuffer());
    if (exr.width !== width || exr.height !== height) return { error: `EXR is ${exr.width}×${exr.height}` };
    const channels = exr.data.length / (width * height);
    // EXRLoader stores rows bottom-up (a texture's order): image row j is data row height-1-j.
    const radiance = (i, j) => exr.data[channels * ((height - 1 - j) * width + i)];
    // Signed distance (pixels) of a point inside the projected convex polygon (either winding).
    const area = corners.reduce((s, a, i) => { const b = corners[(i + 1) % corners.length]; return s + a[0] * b[1] - b[0] * a[1]; }, 0);
    const inside = (x, y) => Math.min(...corners.map((a, i) => {
      const b = corners[(i + 1) % corners.length];
      const cross = (b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0]);
      return Math.sign(area) * cross / Math.hypot(b[0] - a[0], b[1] - a[1]);
    }));
    const margin = 0.01;
    let insideChecked = 0, outsideChecked = 0, mismatches = 0, ambiguous = 0;
    const examples = [];
    for (let j = 0; j < height; ++j) {
      for (let i = 0; i < width; ++i) {
        const white = radiance(i, j) > lightThreshold;
        const s = inside(i + 0.5, j + 0.5);
        if (Math.abs(s) <= margin) { ++ambiguous; continue; }
        if (s > 0) ++insideChecked; else if (s > -3) ++outsideChecked; else continue;
        if (white !== s > 0) {
          ++mismatches;
          if (examples.length < 5) examples.push({ i, j, signedDistance: s, white });
        }
      }
    }
    return { insideChecked, outsideChecked, mismatches, ambiguous, examples, corners };
  }, { sceneId, query, light, width, height, lightThreshold });
}

async function projectionChecks(page, base, sceneId, scene) {
  // 1. The page's own camera: three.js's Vector3.project vs the formulas, on the query the page
  //    sends to /image (so its parameters describe exactly the camera it draws with).
  const query = await page.evaluate(() => window.penumbra.cameraQuery());
  const points = [[0, 0, 0], [1.5, 0.5, -2], [-3, 2.5, 1], ...scene.lights[0].polygon];
  // The image's size must have the canvas's aspect, as the render panel asks for it.
  const { width, height } = await page.evaluate(() => window.penumbra.state().canvas);
  const threePixels = await page.evaluate(({ points, width, height }) => window.penumbra.projectToPixels(points, width, height),
    { points, width, height });
  let worst = 0;
  points.forEach((p, i) => {
    const f = formulaPixel(query, p, width, height);
    worst = Math.max(worst, Math.hypot(f.x - threePixels[i].x, f.y - threePixels[i].y));
  });
  check(worst < 1e-6, 'page camera: three.js Vector3.project = the renderer formulas (pixels)', `worst ${worst}`);

  // 2. Against the C++ renderer itself: the light's pixels in /image, perspective and orthographic.
  const light = scene.lights[0].polygon;
  const centre = light.reduce((s, p) => s.map((x, k) => x + p[k] / light.length), [0, 0, 0]);
  const cameras = [
    { position: '0.3,0.8,1.5', target: `${centre[0]},${centre[1]},${centre[2]}`, up: '0,1,0', projection: 'perspective', fov_y_deg: '60', near: '0.1', far: '50' },
    { position: '-0.4,0.5,0.9', target: `${centre[0] + 0.2},${centre[1]},${centre[2] - 0.1}`, up: '0,1,0', projection: 'orthographic', ortho_height: '3', near: '0.1', far: '50' },
  ];
  for (const camera of cameras) {
    const result = await lightPixelCheck(page, sceneId, camera, light, 160, 120, 0.5 * Math.min(...scene.lights[0].radiance));
    if (!check(!result.error, `${camera.projection} image fetched`, result.error)) continue;
    check(result.insideChecked > 50 && result.mismatches === 0,
      `${camera.projection}: the renderer's light pixels are exactly three.js's projected light polygon`,
      JSON.stringify(result));
    console.log(`     ${camera.projection}: ${result.insideChecked} pixels inside, ${result.outsideChecked} outside checked, ${result.ambiguous} within 0.01 px of an edge`);
  }
}

// In the page: the served whole binary mesh (its parts) decoded afresh by the page's decoder
// must equal what the page holds after its deltas: the same parts, receivers, vertices, and the
// floor's merged arrays; and the decoder must refuse a buffer of another layout version.
async function meshConsistency(page, sceneId, label) {
  const r = await page.evaluate(async (sceneId) => {
    const { decodeMeshBinary } = await import('/src/mesh_binary.js');
    const response = await fetch(`/api/scenes/${sceneId}/mesh?format=bin`);
    const buffer = await response.arrayBuffer();
    const whole = decodeMeshBinary(buffer);
    const state = window.penumbra.state();
    const floorParts = whole.parts.filter((p) => p.receiverKey === 'floor/0')
      .sort((a, b) => a.chunk[1] - b.chunk[1] || a.chunk[0] - b.chunk[0]);
    const concat = (key) => floorParts.flatMap((p) => Array.from(p[key]));
    const floor = window.penumbra.receiver('floor', 0);
    const old = buffer.slice(0);
    new DataView(old).setUint32(4, 1, true);
    let refused = '';
    try { decodeMeshBinary(old); } catch (error) { refused = error.message; }
    return { served: whole.sceneVersion, held: state.version, parts: [whole.parts.length, state.parts],
      receivers: [new Set(whole.parts.map((p) => p.receiverKey)).size, state.receivers],
      vertices: [whole.totalVertices, state.vertices], triangles: [whole.totalTriangles, state.triangles],
      floorParts: floorParts.length, floorSame: !!floor && floor.vertexCount === concat('classes').length
        && JSON.stringify(floor.irradiance) === JSON.stringify(concat('irradiance'))
        && JSON.stringify(floor.positions) === JSON.stringify(concat('positions')), refused };
  }, sceneId);
  const same = ([a, b]) => a === b;
  check(r.served === r.held && same(r.parts) && same(r.receivers) && same(r.vertices) && same(r.triangles) && r.floorSame,
    `${label}: the page's parts equal the served whole mesh decoded afresh (counts, the floor's ${r.floorParts} parts merged)`, JSON.stringify(r));
  if (label === 'at load') check(/unsupported layout version 1/.test(r.refused), 'the decoder refuses layout 1 by name', r.refused);
}

async function dragTest(page, pageErrors, base, sceneId, screenshot) {
  const initial = await page.evaluate(() => window.penumbra.state());
  check(initial.receivers > 0 && initial.vertices > 0, 'the mesh loaded', JSON.stringify(initial));
  check(initial.version === 0, 'the page holds version 0 at start', String(initial.version));
  check(initial.parts >= initial.receivers, 'every receiver held is made of parts (display chunks)', `${initial.parts} parts, ${initial.receivers} receivers`);
  // The harness runs chromium on SwiftShader: the page must see a software GL and not antialias.
  check(initial.gl.software && !initial.gl.antialias, 'on a software GL the page draws without antialiasing', JSON.stringify(initial.gl));
  await meshConsistency(page, sceneId, 'at load');
  const scene = (await serverScene(base, sceneId)).scene;
  await projectionChecks(page, base, sceneId, scene);

  // The cube with the largest shadow near the light; the floor point under its centre is in
  // its contact umbra now and lit once it has moved away.
  const cubeId = 'cube_3';
  const cube = scene.objects.find((o) => o.id === cubeId);
  const [cx, , cz] = cube.transform.translate;
  const under = [cx, 0, cz];
  const floorBefore = await page.evaluate(() => window.penumbra.receiver('floor', 0));
  const underBefore = await page.evaluate((p) => window.penumbra.irradianceAt('floor', 0, p), under);
  const floorMax = Math.max(...floorBefore.irradiance);

  check((await clickObject(page, cubeId)) === cubeId, `a click on ${cubeId} selects it`);
  // Halfway, the button still down and the shadows caught up: the frame the cache draws (the
  // unchanged objects' picture, the moved cube and the changed mesh parts over it) is the whole frame.
  const cacheChecks = [];
  await dragXHandle(page, -1.3, 24, 40, async () => {
    await page.evaluate(() => window.penumbra.idle());
    for (let i = 0; i < 2; ++i) cacheChecks.push(await page.evaluate(() => window.penumbra.cachedFrameDifference(1)));
  });
  check(cacheChecks.some((c) => c.how === 'cached') && cacheChecks.every((c) => c.how !== 'direct' && c.differing === 0),
    'during the drag, a frame drawn through the frame cache equals the whole frame (each channel within 1 of 255)', JSON.stringify(cacheChecks));
  await page.evaluate(() => window.penumbra.idle());
  const after = await page.evaluate(() => window.penumbra.state());
  check(after.frameCache.cached > 0 && !after.frameCache.active && after.pixelRatio === 1,
    'the drag drew frames from the cache; after it the view draws whole frames at full resolution', JSON.stringify({ ...after.frameCache, pixelRatio: after.pixelRatio }));
  const server = await serverScene(base, sceneId);
  const moved = server.scene.objects.find((o) => o.id === cubeId).transform.translate;
  check(server.version > 0, 'the scene version advanced on the server', String(server.version));
  check(after.version === server.version, 'the page holds the server\'s newest version', `${after.version} vs ${server.version}`);
  check(moved[0] < cx - 0.5 && Math.abs(moved[1] - cube.transform.translate[1]) < 1e-9,
    'the drag moved the cube along -x on the server', `${cube.transform.translate} → ${moved}`);
  check(after.editsSent >= 2, 'edits flowed while dragging (more than one frame)', `${after.editsSent} frames, ${after.editsReplaced} coalesced away`);
  const floorAfter = await page.evaluate(() => window.penumbra.receiver('floor', 0));
  const underAfter = await page.evaluate((p) => window.penumbra.irradianceAt('floor', 0, p), under);
  check(floorAfter.sceneVersion > floorBefore.sceneVersion, 'the floor receiver was replaced by a newer version',
    `${floorBefore.sceneVersion} → ${floorAfter.sceneVersion}`);
  check(JSON.stringify(floorAfter.irradiance) !== JSON.stringify(floorBefore.irradiance), 'the floor\'s vertex irradiance changed');
  check(underBefore && underBefore[0] < 0.01 * floorMax, 'the floor under the cube was dark before', JSON.stringify(underBefore));
  check(underAfter && underAfter[0] > 0.1 * floorMax, 'the floor under the cube\'s old place is lit after the drag',
    `${JSON.stringify(underAfter)} vs max ${floorMax}`);

  // The server's render follows the new version.
  await page.waitForFunction((v) => window.penumbra.state().renderVersion === v, server.version, { timeout: 30000 }).catch(() => {});
  check((await page.evaluate(() => window.penumbra.state().renderVersion)) === server.version, 'the server render panel shows the new version');

  // Undo and redo re-send the absolute transforms.
  await page.keyboard.press('Control+z');
  await sleep(50);
  await page.evaluate(() => window.penumbra.idle());
  const undone = await serverScene(base, sceneId);
  const undoneAt = undone.scene.objects.find((o) => o.id === cubeId).transform.translate;
  check(undone.version > server.version && undoneAt.every((x, k) => Math.abs(x - cube.transform.translate[k]) < 1e-9),
    'Ctrl+Z puts the cube back where it was (a new version)', `${undoneAt} at v${undone.version}`);
  await page.keyboard.press('Control+Shift+z');
  await sleep(50);
  await page.evaluate(() => window.penumbra.idle());
  const redone = await serverScene(base, sceneId);
  const redoneAt = redone.scene.objects.find((o) => o.id === cubeId).transform.translate;
  check(redoneAt.every((x, k) => Math.abs(x - moved[k]) < 1e-9), 'Ctrl+Shift+Z moves it again', `${redoneAt}`);
  await meshConsistency(page, sceneId, 'after the drag, undo and redo (deltas)');

  // Another client removes the cube (its parts arrive as removed parts through the event stream), then adds it back.
  const postFrame = async (edits) => {
    const response = await fetch(`${base}/api/scenes/${sceneId}/edits`, { method: 'POST', body: JSON.stringify({ edits }) });
    if (!response.ok) throw new Error(`POST edits: ${response.status} ${await response.text()}`);
    return (await response.json()).version;
  };
  const beforeRemoval = await page.evaluate(() => window.penumbra.state());
  const cubeObject = redone.scene.objects.find((o) => o.id === cubeId);
  const removedAt = await postFrame([{ op: 'remove', id: cubeId }]);
  await page.waitForFunction((v) => window.penumbra.state().version >= v, removedAt, { timeout: 30000 }).catch(() => {});
  await page.evaluate(() => window.penumbra.idle());
  const afterRemoval = await page.evaluate(() => window.penumbra.state());
  const cubeFaces = await page.evaluate((id) => [0, 1, 2, 3, 4, 5].filter((f) => window.penumbra.receiver(id, f)).length, cubeId);
  check(afterRemoval.version === removedAt && afterRemoval.parts < beforeRemoval.parts && cubeFaces === 0,
    'another client\'s removal reaches the page: the cube\'s parts are dropped', `${beforeRemoval.parts} → ${afterRemoval.parts} parts, ${cubeFaces} cube faces held`);
  await meshConsistency(page, sceneId, 'after another client removed the cube');
  const addedAt = await postFrame([{ op: 'add', object: cubeObject }]);
  await page.waitForFunction((v) => window.penumbra.state().version >= v, addedAt, { timeout: 30000 }).catch(() => {});
  await page.evaluate(() => window.penumbra.idle());
  await meshConsistency(page, sceneId, 'after another client added it back');

  await page.check('#toggle-edges');
  await page.waitForFunction((v) => window.penumbra.state().renderVersion === v, redone.version, { timeout: 30000 }).catch(() => {});
  await sleep(200);
  const final = await page.evaluate(() => window.penumbra.state());
  check(!final.bannerVisible && final.errors.length === 0, 'no error banner', JSON.stringify(final.errors));
  check(pageErrors.length === 0, 'no errors in the page\'s console', JSON.stringify(pageErrors));
  fs.mkdirSync(path.dirname(screenshot), { recursive: true });
  await page.screenshot({ path: screenshot });
  console.log(`     screenshot: ${screenshot}`);

  // A bad scene file is refused by the server and the page shows why.
  await page.setInputFiles('#scene-file', { name: 'bad.scene.json', mimeType: 'application/json',
    buffer: Buffer.from(JSON.stringify({ format: 'penumbra.scene', version: 1, lights: [], objects: [] })) });
  await page.waitForFunction(() => window.penumbra.state().bannerVisible, null, { timeout: 10000 }).catch(() => {});
  const banner = await page.evaluate(() => ({ visible: window.penumbra.state().bannerVisible, text: document.getElementById('error-text').textContent }));
  check(banner.visible && /invalid_scene/.test(banner.text) && /lights/.test(banner.text),
    'a refused scene file shows the server\'s error (code and key path) in the banner', banner.text);
}

// What the page did between two states over `seconds`: frames (edits) sent and applied end to
// end (edit answered and its version's mesh applied), mesh bytes, round trips, frames drawn.
function tally(state0, state, seconds) {
  const frames = state.editsSent - state0.editsSent;
  const meshBytes = state.mesh.totalBytes - state0.mesh.totalBytes;
  const fetches = state.mesh.fetches - state0.mesh.fetches;
  const report = { seconds, frames_sent: frames, coalesced_away: state.editsReplaced - state0.editsReplaced,
    edits_per_second: frames / seconds, mesh_fetches: fetches, mesh_bytes_per_fetch: fetches ? meshBytes / fetches : 0,
    mesh_bytes_per_edit: frames ? meshBytes / frames : 0, frames_drawn_per_second: (state.frames - state0.frames) / seconds,
    shadow_updates_drawn_per_second: (state.meshFramesDrawn - state0.meshFramesDrawn) / seconds,
    last_frame_engine_seconds: state.lastFrame && state.lastFrame.seconds, last_round_trip_seconds: state.roundTrip };
  const t = state.totals, t0 = state0.totals, n = t.frames - t0.frames;
  if (n > 0) {
    // Mean seconds per frame: edit sent → answered (engine and display meshing inside it),
    // answered → its version's mesh applied.
    report.mean_seconds = { round_trip: (t.roundTrip - t0.roundTrip) / n, edit_answer: (t.edit - t0.edit) / n,
      engine: (t.engine - t0.engine) / n, server_display_meshing: (t.meshing - t0.meshing) / n,
      mesh_wait_fetch_and_apply: (t.mesh - t0.mesh) / n };
  }
  return report;
}

// Drags one cube for `seconds`, a mouse move every 16 ms (a 60 Hz pointer; the browser delivers
// them no faster than it draws), then moves it back from a 16 ms timer in the page (the edit
// pipeline alone), and reports each; then times drawing with and without antialiasing.
async function measure(page, base, sceneId, seconds) {
  const scene = (await serverScene(base, sceneId)).scene;
  // A movable cube near the middle of the room, so its shadow falls on many receivers.
  const cubes = scene.objects.filter((o) => !o.static && o.transform);
  cubes.sort((a, b) => Math.hypot(a.transform.translate[0], a.transform.translate[2]) - Math.hypot(b.transform.translate[0], b.transform.translate[2]));
  let selected = null;
  for (const cube of cubes.slice(0, 10)) if ((selected = await clickObject(page, cube.id)) === cube.id) break;
  if (!selected) throw new Error('could not select a cube');
  const state0 = await page.evaluate(() => window.penumbra.state());
  const steps = Math.round(seconds * 1000 / 16);
  let start = Date.now();
  await dragXHandle(page, 0.8, steps, 16);
  await page.evaluate(() => window.penumbra.idle());
  const state1 = await page.evaluate(() => window.penumbra.state());
  const mouse = { mouse_moves: steps, ...tally(state0, state1, (Date.now() - start) / 1000) };
  start = Date.now();
  const timerSteps = await page.evaluate(({ id, seconds }) => window.penumbra.drive(id, -0.8, seconds, 16), { id: selected, seconds });
  const state2 = await page.evaluate(() => window.penumbra.state());
  const timer = { timer_steps: timerSteps, ...tally(state1, state2, (Date.now() - start) / 1000) };
  const report = { scene: sceneId, cube: selected, receivers: state2.receivers, parts: state2.parts, batches: state2.batches, vertices: state2.vertices,
    gl: state2.gl, canvas: state2.canvas, frame_cache: state2.frameCache, mouse_drag: mouse, timer_drag: timer };
  console.log(JSON.stringify(report, null, 2));
  check(mouse.frames_sent > 0 && timer.frames_sent > 0 && !state2.bannerVisible, 'frames applied while dragging, no error', JSON.stringify(state2.errors));
  // Drawing alone, orbiting: this page (antialiasing as chosen by GL renderer), then a page forced the other way.
  const draw = { [state2.gl.antialias ? 'antialias' : 'no_antialias']: (await page.evaluate(() => window.penumbra.timeFrames(20))).msPerFrame };
  const other = await openPage(page.context().browser(), `${page.url()}&antialias=${state2.gl.antialias ? 'off' : 'on'}`);
  draw[state2.gl.antialias ? 'no_antialias' : 'antialias'] = (await other.page.evaluate(() => window.penumbra.timeFrames(20))).msPerFrame;
  await other.page.close();
  console.log(JSON.stringify({ draw_ms_per_frame: draw }));
  check(!state2.gl.software || !state2.gl.antialias, 'a software GL draws without antialiasing', JSON.stringify(state2.gl));
}

async function main() {
  const args = usageOnHelp(process.argv, defaults, 'node tests/web/drag_e2e.mjs --penumbra build/penumbra [--scene FILE] [--screenshot PNG]\n'
    + '       [--measure build/cubes150.scene.json --seconds 5] [--query drag_scale=0.35]');
  await runWithServerAndBrowser({ ...args, scene: args.measure || args.scene }, async ({ browser, url, base, sceneId }) => {
    const { page, pageErrors } = await openPage(browser, args.query ? `${url}&${args.query}` : url);
    const ready = await page.evaluate(() => window.penumbra.state());
    if (!check(ready.ready, 'the page loaded the scene', JSON.stringify(ready.errors))) throw new Error('page not ready');
    if (args.measure) await measure(page, base, sceneId, args.seconds);
    else await dragTest(page, pageErrors, base, sceneId, args.screenshot);
  });
}

main();
