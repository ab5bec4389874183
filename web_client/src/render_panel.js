// The server's rendering of the page's current view (GET /image with the camera as query
// parameters), refreshed a short while after the camera or the scene version stops changing.
// Scenes with microfacet materials refine progressively: a fast image with few samples first,
// then better ones, each replacing the shown one; a new camera or version aborts the passes left.
// With GI on, the last pass asks for bounced light by sensors and the info shows their count and time.
// While a pass is on its way a counter beside the info says so ("rendering with GI… 12.3 s"): a GI
// render takes seconds to minutes.

import { ElapsedCounter } from './elapsed_counter.js';

const DEBOUNCE_MS = 250;
const WIDTH = 320;
// Microfacet paths per pixel of each pass (the last is the server's default, as `penumbra render`).
export const PROGRESSIVE_SAMPLES = [1, 4, 16];

export class RenderPanel {
  // progressive(): whether the scene has materials that need samples (else one pass).
  // progress: the element for the running pass's counter.
  constructor(api, sceneId, view, img, info, progress, onError, progressive = () => false) {
    Object.assign(this, { api, sceneId, view, img, info, progress, onError, progressive });
    this.counter = new ElapsedCounter((text) => { this.progress.textContent = text; });
    this.timer = null;
    this.abort = null;
    this.url = null;
    this.renders = 0;
    this.lastVersion = null;
    this.passes = []; // {version, samples, seconds} of each image shown, the newest last (bounded)
    this.aborted = 0;
    this.gi = false; // bounced light by sensors (gi=sensors), off by default: it costs seconds
  }

  setGi(on) {
    this.gi = on;
    this.refresh();
  }

  schedule() {
    clearTimeout(this.timer);
    this.timer = setTimeout(() => this.refresh(), DEBOUNCE_MS);
  }

  async refresh() {
    if (this.abort) {
      this.abort.abort();
      ++this.aborted;
    }
    const abort = new AbortController();
    this.abort = abort;
    const width = WIDTH;
    const height = Math.max(1, Math.round(WIDTH / this.view.aspect()));
    const camera = this.view.cameraQuery();
    const passes = this.progressive() ? PROGRESSIVE_SAMPLES : [null];
    try {
      for (const [i, samples] of passes.entries()) {
        // GI costs the same whatever the samples: only the last pass pays it, the first shows fast.
        const gi = this.gi && i === passes.length - 1;
        this.counter.start(`rendering${gi ? ' with GI (sensors)' : ''}${samples ? `, ${samples} samples` : ''}…`);
        const image = await this.api.image(this.sceneId, width, height, camera, abort.signal, samples, gi);
        if (abort.signal.aborted) return;
        this.show(image, width, height, passes.length > 1 ? `${image.samples}/${passes.at(-1)} samples, ` : '');
      }
    } catch (error) {
      if (error.name !== 'AbortError') this.onError(error);
    } finally {
      if (this.abort === abort) {
        this.abort = null;
        this.counter.stop();
        this.progress.textContent = '';
      }
    }
  }

  show({ blob, version, seconds, samples, giSensors, giSeconds }, width, height, pass) {
    if (this.url) URL.revokeObjectURL(this.url);
    this.url = URL.createObjectURL(blob);
    this.img.src = this.url;
    this.lastVersion = version;
    ++this.renders;
    this.passes.push({ version, samples, seconds, giSensors });
    if (this.passes.length > 64) this.passes.shift();
    const gi = giSensors === null ? '' : `, GI: ${giSensors} sensors in ${(giSeconds * 1000).toFixed(0)} ms`;
    this.info.textContent = `v${version}, ${width}×${height}, ${pass}${(seconds * 1000).toFixed(0)} ms${gi}`;
  }
}
