// "Edit vs full build": a small live plot of the last edits' times beside the time of building the
// same scene from scratch, on a log scale (edits take milliseconds, a build tens to thousands):
// per edit frame, the engine's time (orange) and the page's round trip (blue, edit sent → its
// mesh drawn); the full build's engine time as a grey line; and below, the ratio in words.
// Both engine figures are the same work measured the same way (core's Engine: build vs apply).

const KEEP = 60;
const COLOURS = { engine: '#ff9020', roundTrip: '#4090ff', build: '#888', grid: '#2a2a2a', text: '#aaa' };

const median = (values) => {
  if (!values.length) return null;
  const sorted = [...values].sort((a, b) => a - b);
  return sorted[Math.floor(sorted.length / 2)];
};

export class EditPlot {
  constructor(canvas, caption) {
    this.canvas = canvas;
    this.caption = caption;
    this.history = []; // {engine, roundTrip} seconds, oldest first
    this.build = null; // {seconds, label}
    // No drawing until there is something to show: a 2D canvas's first use costs a software GL
    // ~0.1 s, which the page's opening need not wait for.
    this.caption.textContent = 'no edit yet';
  }

  add(engineSeconds, roundTripSeconds) {
    this.history.push({ engine: engineSeconds, roundTrip: roundTripSeconds });
    if (this.history.length > KEEP) this.history.shift();
    this.draw();
  }

  // The full build's engine seconds; label says which build ('at load' or 'rebuild of vN').
  setBuild(seconds, label) {
    this.build = seconds > 0 ? { seconds, label } : null;
    this.draw();
  }

  // Full build ÷ the median edit of the last 10 (engine times), or null.
  ratio() {
    const edit = median(this.history.slice(-10).map((h) => h.engine));
    return this.build && edit > 0 ? this.build.seconds / edit : null;
  }

  draw() {
    const { canvas } = this;
    const ctx = canvas.getContext('2d');
    const w = canvas.width, h = canvas.height;
    ctx.fillStyle = '#161616';
    ctx.fillRect(0, 0, w, h);
    const values = this.history.flatMap((e) => [e.engine, e.roundTrip]).concat(this.build ? [this.build.seconds] : []).filter((v) => v > 0);
    const ms = (s) => `${(1000 * s).toFixed(s < 0.01 ? 1 : 0)} ms`;
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
        for (const [key, colour] of [['roundTrip', COLOURS.roundTrip], ['engine', COLOURS.engine]]) {
          ctx.fillStyle = colour;
          ctx.fillRect(x - 1.5, y(e[key]) - 1.5, 3, 3);
        }
      });
    }
    const ratio = this.ratio();
    const edit = median(this.history.slice(-10).map((e) => e.engine));
    this.caption.textContent = ratio
      ? `edit ${ms(edit)} (median of last ${Math.min(10, this.history.length)}) vs full build ${ms(this.build.seconds)} (${this.build.label}): ${ratio.toFixed(ratio < 10 ? 1 : 0)}× faster`
      : this.build ? `full build ${ms(this.build.seconds)} (${this.build.label}); drag an object to compare` : 'no edit yet';
  }
}
