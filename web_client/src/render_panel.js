// The server's rendering of the page's current view (GET /image with the camera as query
// parameters), refreshed a short while after the camera or the scene version stops changing.
// Scenes with microfacet materials refine progressively: a fast image with 1 sample first, then
// RATIO times the samples each pass, each shown as it comes, until the render has converged
// (render_panel_noise.js) or reached the most samples the server allows at this size; a new
// camera or version, or Cancel, stops the passes left. With GI on, a last pass at the final
// samples adds bounced light by sensors and the info shows their count and time.
// Every pass is a render job on the server (its ticket and this page's label): while one runs a
// counter beside the info says so ("rendering with GI… 12.3 s"), its stage and fraction and a
// Cancel button follow it (render_panel_progress.js); a newer pass of this page stops the older
// one on the server too. Passes are numbered (`seq`), so a pass's request overtaken on its way by
// the next one's (sent just before its abort, it reaches the server second) is refused there
// instead of stopping the newer pass.

import { ElapsedCounter } from './elapsed_counter.js';
import { CONVERGED_LEVELS, RATIO, noiseLevels, pixelsOf } from './render_panel_noise.js';
import { RenderProgress } from './render_panel_progress.js';

const DEBOUNCE_MS = 250;
const WIDTH = 320;
// The server's bounds on a request's samples (server/limits.h): at most MAX_SAMPLES, and
// samples × pixels at most SAMPLE_BUDGET.
const MAX_SAMPLES = 256;
const SAMPLE_BUDGET = 2 ** 24;
// The first passes' samples (then × RATIO until converged).
export const PROGRESSIVE_SAMPLES = [1, 4, 16];

// Samples of each pass for an image of `pixels`: 1, 4, 16, … up to the server's bound.
export function sampleSchedule(pixels) {
  const most = Math.max(1, Math.min(MAX_SAMPLES, Math.floor(SAMPLE_BUDGET / pixels)));
  const out = [];
  for (let s = 1; s < most; s *= RATIO) out.push(s);
  out.push(most);
  return out;
}

const randomLabel = () => Math.random().toString(36).slice(2, 10);

export class RenderPanel {
  // progressive(): whether the scene has materials that need samples (else one pass).
  // progress: the element for the running pass's counter.
  constructor(api, sceneId, view, img, info, progress, onError, progressive = () => false) {
    Object.assign(this, { api, sceneId, view, img, info, progress, onError, progressive });
    this.counter = new ElapsedCounter((text) => { this.progress.textContent = text; });
    this.job = new RenderProgress(api, sceneId, progress, () => this.stop());
    this.page = `p${randomLabel()}`; // this page's renders: a newer one stops the older
    this.timer = null;
    this.abort = null;
    this.url = null;
    this.renders = 0;
    this.lastVersion = null;
    this.passes = []; // {version, samples, seconds, giSensors, noise} of each image shown, newest last (bounded)
    this.aborted = 0;
    this.tickets = 0;
    this.gi = false; // bounced light by sensors (gi=sensors), off by default: it costs seconds
    this.outcome = ''; // how the last refinement ended: 'converged', 'at the server's limit', 'stopped'
  }

  setGi(on) {
    this.gi = on;
    this.refresh();
  }

  schedule() {
    clearTimeout(this.timer);
    this.timer = setTimeout(() => this.refresh(), DEBOUNCE_MS);
  }

  // Stops the passes on their way (Cancel): the shown image stays.
  stop() {
    if (!this.abort) return;
    this.abort.abort();
    ++this.aborted;
    this.outcome = 'stopped';
    this.info.textContent += ' — stopped';
  }

  async refresh() {
    if (this.abort) {
      this.abort.abort();
      ++this.aborted;
    }
    const abort = new AbortController();
    this.abort = abort;
    this.outcome = '';
    const width = WIDTH;
    const height = Math.max(1, Math.round(WIDTH / this.view.aspect()));
    const camera = this.view.cameraQuery();
    const schedule = this.progressive() ? sampleSchedule(width * height) : [null];
    let previous = null; // the last pass's pixels and samples, for the noise estimate
    try {
      for (const [i, samples] of schedule.entries()) {
        const last = i === schedule.length - 1;
        // GI costs the same whatever the samples: a refining scene pays it once, at the end.
        const gi = this.gi && last && schedule.length === 1;
        const image = await this.pass(width, height, camera, abort, samples, gi);
        if (!image) return;
        const pixels = schedule.length > 1 ? await pixelsOf(image.blob) : null;
        if (abort.signal.aborted) return;
        const noise = previous ? noiseLevels(previous.pixels, pixels, image.samples / previous.samples) : null;
        previous = { pixels, samples: image.samples };
        const converged = noise !== null && noise < CONVERGED_LEVELS;
        this.outcome = schedule.length === 1 ? 'converged' : converged ? 'converged' : last ? 'at the server\'s limit' : '';
        this.show(image, width, height, noise);
        if (this.outcome && this.gi && schedule.length > 1) {
          const withGi = await this.pass(width, height, camera, abort, image.samples, true);
          if (!withGi) return;
          this.show(withGi, width, height, noise);
        }
        if (this.outcome) break;
      }
    } catch (error) {
      // Aborted (a new view, Cancel), or ended by the server (409 render_cancelled: its ticket
      // deleted elsewhere, the server stopping, which the connection bar says): not an error.
      const ended = error.code === 'render_cancelled' || abort.signal.aborted;
      if (error.name !== 'AbortError' && !ended) this.onError(error);
    } finally {
      if (this.abort === abort) {
        this.abort = null;
        this.counter.stop();
        this.job.stop();
        this.progress.textContent = '';
      }
    }
  }

  // One render on the server, followed until it comes (null when aborted).
  async pass(width, height, camera, abort, samples, gi) {
    const seq = ++this.tickets;
    const ticket = `${this.page}-${seq}`;
    this.counter.start(`rendering${gi ? ' with GI (sensors)' : ''}${samples ? `, ${samples} samples` : ''}…`);
    this.job.follow(ticket);
    const image = await this.api.image(this.sceneId, width, height, camera, abort.signal, samples, gi,
                                       { ticket, page: this.page, seq: String(seq) });
    return abort.signal.aborted ? null : image;
  }

  show({ blob, version, seconds, samples, giSensors, giSeconds }, width, height, noise) {
    if (this.url) URL.revokeObjectURL(this.url);
    this.url = URL.createObjectURL(blob);
    this.img.src = this.url;
    this.lastVersion = version;
    ++this.renders;
    this.passes.push({ version, samples, seconds, giSensors, noise });
    if (this.passes.length > 64) this.passes.shift();
    const gi = giSensors === null ? '' : `, GI: ${giSensors} sensors in ${(giSeconds * 1000).toFixed(0)} ms`;
    const refining = this.progressive()
      ? `${samples} samples${noise === null ? '' : `, noise ${noise.toFixed(1)}/255`}${this.outcome ? ` (${this.outcome})` : ''}, `
      : '';
    this.info.textContent = `v${version}, ${width}×${height}, ${refining}${(seconds * 1000).toFixed(0)} ms${gi}`;
  }
}
