// The readout: the last edit's engine timings (remove / add / relight / total), vertices relit
// / changed / created, receivers changed, the server's display meshing, the page's round trip
// (edit sent → the page holds its version's mesh: the edit's answer, then the wait for the delta,
// which overlaps the next edit) and bytes of the fetch that brought it, edits per second over the
// last seconds, beside the full-rebuild time, the WebGL renderer (software or not, antialiased or not)
// and how a drag's frames are drawn (resolution, frames over the frame cache's picture).

const ms = (s) => (s === undefined || s === null ? '–' : `${(1000 * s).toFixed(1)} ms`);

export class TimingsPanel {
  constructor(table) {
    this.table = table;
    this.frame = null;
    this.roundTrip = null;
    this.bytes = null;
    this.rebuild = null;
    this.initialBuild = null;
    this.gl = null; // {renderer, software, antialias} from SceneView
    this.view = null; // the SceneView (its frame cache's counts)
    this.stamps = [];
    this.totals = { frames: 0, roundTrip: 0, edit: 0, mesh: 0, engine: 0, meshing: 0 }; // sums, seconds
    this.draw();
  }

  // phases: {edit, mesh} seconds — the edit's answer, then until its version's delta is applied.
  edited(frame, roundTripSeconds, bytes, phases) {
    this.frame = frame;
    this.phases = phases;
    this.totals.frames += 1;
    this.totals.roundTrip += roundTripSeconds;
    this.totals.edit += phases.edit;
    this.totals.mesh += phases.mesh;
    this.totals.engine += frame.seconds ? frame.seconds.total : 0;
    this.totals.meshing += frame.mesh_seconds || 0;
    this.roundTrip = roundTripSeconds;
    this.bytes = bytes;
    const now = performance.now();
    this.stamps.push(now);
    while (this.stamps.length && now - this.stamps[0] > 2000) this.stamps.shift();
    this.draw();
  }

  // How the view draws a drag's frames: the resolution (below full on a software GL) and how many
  // of the frames drawn during drags came from the frame cache (frame_cache.js).
  dragFrames() {
    if (!this.view) return '–';
    const { cached, rebuilt, direct } = this.view.cache.stats;
    const scale = this.view.gl.dragScale;
    const resolution = scale < 1 ? `${scale}× resolution` : 'full resolution';
    if (!this.view.cacheDrags) return `${resolution}; drawn whole${this.gl.antialias ? ' (antialiased)' : ''}`;
    return `${resolution}; ${cached + rebuilt} of ${cached + rebuilt + direct} frames over a cached picture (${rebuilt} redrawn)`;
  }

  editsPerSecond() {
    if (this.stamps.length < 2) return 0;
    return (this.stamps.length - 1) / ((this.stamps[this.stamps.length - 1] - this.stamps[0]) / 1000);
  }

  draw() {
    const f = this.frame || {};
    const s = f.seconds || {};
    const v = f.vertices || {};
    const rows = [
      ['remove', ms(s.remove)], ['add', ms(s.add)], ['relight', ms(s.relight)], ['engine total', ms(s.total)],
      ['vertices relit / changed / created', f.vertices ? `${v.relit} / ${v.changed} / ${v.created}` : '–'],
      ['receivers changed', f.changed_receivers_count ?? '–'],
      // The server meshes the changed display chunks before it answers (absent from older servers).
      ['display meshing (chunks meshed / kept)', f.mesh_seconds === undefined ? '–'
        : `${ms(f.mesh_seconds)}${f.mesh_cells ? ` (${f.mesh_cells.chunks_meshed} / ${f.mesh_cells.chunks_kept})` : ''}`],
      ['round trip (edit + mesh)', this.phases ? `${ms(this.roundTrip)} (${ms(this.phases.edit)} + ${ms(this.phases.mesh)})` : ms(this.roundTrip)],
      ['mesh delta (fetch)', this.bytes === null ? '–' : `${(this.bytes / 1024).toFixed(1)} KiB`],
      ['edits / s (last 2 s)', this.editsPerSecond().toFixed(1)],
      ['full build, engine (at load)', ms(this.initialBuild)],
      // The rebuild adds the display meshing the initial build's figure leaves out.
      ['full rebuild: engine + display meshing', this.rebuild
        ? `${ms(this.rebuild.seconds.build)} + ${ms(this.rebuild.seconds.mesh)} = ${ms(this.rebuild.seconds.total)} (v${this.rebuild.version})` : '–'],
      ['WebGL', this.gl ? `${this.gl.software ? 'software GL' : 'GL'}: antialiasing ${this.gl.antialias ? 'on' : 'off'} (${this.gl.name})` : '–'],
      ['frames while dragging', this.dragFrames()],
    ];
    this.table.replaceChildren(...rows.map(([k, value]) => {
      const tr = document.createElement('tr');
      for (const text of [k, value]) {
        const td = document.createElement('td');
        td.textContent = String(text);
        tr.appendChild(td);
      }
      return tr;
    }));
  }
}

// The readout on the page (page: {hub, view}): each edit of the page's as its mesh is held, and the
// full builds' times (at load, a rebuild).
export function installTimings({ hub, view }) {
  const timings = new TimingsPanel(document.getElementById('timings'));
  timings.gl = view.gl;
  timings.view = view;
  timings.draw();
  hub.on('edited', ({ result, roundTrip, bytes, phases }) => timings.edited(result, roundTrip, bytes, phases));
  hub.on('built', (stats, rebuilt) => {
    if (rebuilt) timings.rebuild = stats;
    else timings.initialBuild = stats.build && stats.build.seconds ? stats.build.seconds.total : null;
    timings.draw();
  });
  return timings;
}
