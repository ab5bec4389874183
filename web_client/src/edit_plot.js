// "Edit vs full build": a small live plot of the last edits' times beside the time of building the
// same scene from scratch, on a log scale (edits take milliseconds, a build tens to thousands):
// per edit frame, the server's work (orange: the engine and the display meshing of the changed
// receivers) and the page's round trip (blue, edit sent → its mesh drawn); the full build as a grey
// line; and below, the ratio in words, "faster" or "slower". A ratio compares only what was
// measured the same way: after a *Full rebuild* (engine + display meshing, timed by the server)
// the edits' engine + meshing; at load, when only the build's engine time is known, the edits'
// engine time alone, and the caption says so. Frames the engine did no timed work for (a volume's
// isovalue or upload) are left out of the ratio.
const KEEP = 60;
const COLOURS = { work: '#ff9020', roundTrip: '#4090ff', build: '#888', grid: '#2a2a2a', text: '#aaa' };

const ms = (s) => `${(1000 * s).toFixed(s < 0.01 ? 1 : 0)} ms`;

const median = (values) => {
  if (!values.length) return null;
  const sorted = [...values].sort((a, b) => a - b);
  return sorted[Math.floor(sorted.length / 2)];
};

export class EditPlot {
  constructor(canvas, caption) {
    this.canvas = canvas;
    this.caption = caption;
    this.history = []; // {engine, work, roundTrip} seconds, oldest first (work: engine + display meshing)
    this.build = null; // {seconds, label, meshing: whether seconds include the display meshing}
    // No drawing until there is something to show: a 2D canvas's first use costs a software GL
    // ~0.1 s, which the page's opening need not wait for.
    this.caption.textContent = 'no edit yet';
  }

  // engineSeconds: the frame's engine time; meshSeconds: the server's display meshing of it.
  add(engineSeconds, meshSeconds, roundTripSeconds) {
    this.history.push({ engine: engineSeconds, work: engineSeconds + meshSeconds, roundTrip: roundTripSeconds });
    if (this.history.length > KEEP) this.history.shift();
    this.draw();
  }

  // The full build's seconds; label says which build ('at load' or 'rebuild of vN'); meshing:
  // whether they include the display meshing (a rebuild's total) or are the engine's alone.
  setBuild(seconds, label, meshing) {
    this.build = seconds > 0 ? { seconds, label, meshing } : null;
    this.draw();
  }

  // The comparison the figures allow: {edit (median of the last 10 timed frames, measured as the
  // build was), frames, ratio = build ÷ edit}, or null.
  comparison() {
    if (!this.build) return null;
    const timed = this.history.filter((h) => h.engine > 0).slice(-10);
    const edit = median(timed.map((h) => (this.build.meshing ? h.work : h.engine)));
    return edit > 0 ? { edit, frames: timed.length, ratio: this.build.seconds / edit } : null;
  }

  // The last comparison's ratio (full build ÷ edit), or null.
  ratio() {
    const comparison = this.comparison();
    return comparison && comparison.ratio;
  }

  words() {
    const { build } = this;
    if (!this.history.length) return build ? `full build ${ms(build.seconds)} (${build.label}); drag an object to compare` : 'no edit yet';
    const comparison = this.comparison();
    if (!comparison) return build ? `full build ${ms(build.seconds)} (${build.label}); no timed edit to compare yet` : 'no full build timed yet';
    const { edit, frames, ratio } = comparison;
    const what = build.meshing ? 'engine + display meshing' : 'engine only; Full rebuild times the display meshing too';
    const factor = ratio >= 1 ? ratio : 1 / ratio;
    return `edit ${ms(edit)} (median of last ${frames}) vs full build ${ms(build.seconds)} (${build.label}, ${what}): `
      + `${factor.toFixed(factor < 10 ? 1 : 0)}× ${ratio >= 1 ? 'faster' : 'slower'}`;
  }

  draw() {
    const { canvas } = this;
    this.caption.textContent = this.words();
    // Not while its section is closed (drawn when it opens): on a software GL the 2D canvas drawn
    // at each edit, unseen, took a timer drag of the 150-cube room from 44 edits sent a second to 30.
    if (canvas.closest('details:not([open])')) return;
    const ctx = canvas.getContext('2d');
    const w = canvas.width, h = canvas.height;
    ctx.fillStyle = '#161616';
    ctx.fillRect(0, 0, w, h);
    const values = this.history.flatMap((e) => [e.work, e.roundTrip]).concat(this.build ? [this.build.seconds] : []).filter((v) => v > 0);
    if (values.length) {
      // Decades from 1 ms (or less) up to the largest value.
      const lo = Math.log10(Math.min(1e-3, ...values)), hi = Math.log10(Math.max(...values)) + 0.15;
      const y = (s) => h - 4 - (Math.log10(Math.max(s, 1e-6)) - lo) / (hi - lo) * (h - 8);
      ctx.strokeStyle = COLOURS.grid;
      ctx.fillStyle = COLOURS.text;
      ctx.font = '9px sans-serif';
      for (let d = Math.ceil(lo); d <= hi; ++d) {
        ctx.beginPath();
        ctx.moveTo(0, y(10 ** d));
        ctx.lineTo(w, y(10 ** d));
        ctx.stroke();
        ctx.fillText(ms(10 ** d), 2, y(10 ** d) - 1);
      }
      if (this.build) {
        ctx.strokeStyle = COLOURS.build;
        ctx.setLineDash([4, 3]);
        ctx.beginPath();
        ctx.moveTo(0, y(this.build.seconds));
        ctx.lineTo(w, y(this.build.seconds));
        ctx.stroke();
        ctx.setLineDash([]);
      }
      const step = w / KEEP;
      this.history.forEach((e, i) => {
        const x = w - (this.history.length - i) * step + step / 2;
        for (const [key, colour] of [['roundTrip', COLOURS.roundTrip], ['work', COLOURS.work]]) {
          ctx.fillStyle = colour;
          ctx.fillRect(x - 1.5, y(e[key]) - 1.5, 3, 3);
        }
      });
    }
  }
}

// The plot on the page (page: {hub}): each edit of the page's against the full build (the one at
// load until a rebuild, which includes the display meshing).
export function installEditPlot({ hub }) {
  const plot = new EditPlot(document.getElementById('edit-plot'), document.getElementById('edit-ratio'));
  const section = plot.canvas.closest('details');
  if (section) section.addEventListener('toggle', () => { if (section.open) plot.draw(); });
  let rebuilt = false;
  hub.on('edited', ({ result, roundTrip }) => plot.add(result.seconds ? result.seconds.total : 0, result.mesh_seconds || 0, roundTrip));
  hub.on('built', (stats, rebuild) => {
    if (rebuild) {
      rebuilt = true;
      plot.setBuild(stats.seconds.total, `rebuild of v${stats.version}`, true);
    } else if (!rebuilt) {
      plot.setBuild(stats.build && stats.build.seconds ? stats.build.seconds.total : null, 'at load', false);
    }
  });
  return plot;
}
