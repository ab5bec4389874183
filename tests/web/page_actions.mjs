// What the browser tests do in the page with real input: open it and wait until it is ready,
// click an object, drag the translate gizmo's X handle; and read the server's scene.
import { sleep } from './harness.mjs';

export async function openPage(browser, url) {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  const pageErrors = [];
  page.on('pageerror', (error) => pageErrors.push(error.message));
  page.on('console', (message) => { if (message.type() === 'error') pageErrors.push(message.text()); });
  await page.goto(url, { waitUntil: 'domcontentloaded', timeout: 120000 });
  await page.waitForFunction(() => window.penumbra && (window.penumbra.state().ready || window.penumbra.state().bannerVisible),
    null, { timeout: 120000 });
  return { page, pageErrors };
}

export async function serverScene(base, id) {
  const response = await fetch(`${base}/api/scenes/${id}`);
  if (!response.ok) throw new Error(`GET scene: ${response.status}`);
  return response.json();
}

// Presses on the selected object's X translate handle and drags it so the object moves about
// `dx` metres along x, in `steps` real mouse moves `stepMs` apart; `midway` (async), if given, runs
// halfway, the button still down. Returns the handle's start.
export async function dragXHandle(page, dx, steps, stepMs, midway = null) {
  let handle = null;
  for (const t of [0.35, -0.35, 0.5, -0.5, 0.2, -0.2]) {
    const point = await page.evaluate((t) => window.penumbra.gizmoAxisPoint('x', t), t);
    const screen = await page.evaluate((p) => window.penumbra.screenOf(p), point);
    await page.mouse.move(screen.x, screen.y);
    await sleep(50);
    if ((await page.evaluate(() => window.penumbra.state().gizmoAxis)) === 'X') {
      handle = screen;
      break;
    }
  }
  if (!handle) throw new Error('the translate gizmo\'s X handle is not under any probed point');
  const shift = await page.evaluate((dx) => {
    const state = window.penumbra.state();
    const t = window.penumbra.objectTransform(state.selected).translate;
    const a = window.penumbra.screenOf(t);
    const b = window.penumbra.screenOf([t[0] + dx, t[1], t[2]]);
    return { x: b.x - a.x, y: b.y - a.y };
  }, dx);
  await page.mouse.down();
  for (let s = 1; s <= steps; ++s) {
    await page.mouse.move(handle.x + shift.x * s / steps, handle.y + shift.y * s / steps);
    await sleep(stepMs);
    if (midway && s === Math.ceil(steps / 2)) await midway();
  }
  await page.mouse.up();
  return handle;
}

export async function clickObject(page, id) {
  const point = await page.evaluate((id) => window.penumbra.objectTransform(id).translate, id);
  const screen = await page.evaluate((p) => window.penumbra.screenOf(p), point);
  await page.mouse.click(screen.x, screen.y);
  await sleep(100);
  return page.evaluate(() => window.penumbra.state().selected);
}


// The page's pixels [r, g, b] (0..255, as shown) at page points {x, y}: one screenshot of the
// window, decoded in the page.
export async function pixelsAt(page, points) {
  const png = await page.screenshot();
  return page.evaluate(async ({ b64, points }) => {
    const img = new Image();
    img.src = `data:image/png;base64,${b64}`;
    await img.decode();
    const canvas = Object.assign(document.createElement('canvas'), { width: img.width, height: img.height });
    const ctx = canvas.getContext('2d');
    ctx.drawImage(img, 0, 0);
    return points.map((p) => [...ctx.getImageData(Math.round(p.x), Math.round(p.y), 1, 1).data.slice(0, 3)]);
  }, { b64: png.toString('base64'), points });
}
