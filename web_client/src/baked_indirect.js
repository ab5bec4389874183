// Bounced light baked on the mesh (GET mesh?format=bin&indirect=1): when on, the whole mesh with
// each vertex's indirect irradiance is fetched for the newest version a short while after the
// versions stop changing; a newer version aborts the fetch under way, as the render panel's
// passes do. onIndirect(Map part key → {indirect, vertexCount, version} | null) gets each result,
// null when turned off.
import { decodeMeshBinary } from './mesh_binary.js';

const DEBOUNCE_MS = 300;

export class BakedIndirect {
  constructor(api, sceneId, onIndirect, onError) {
    Object.assign(this, { api, sceneId, onIndirect, onError });
    this.on = false;
    this.timer = null;
    this.abort = null;
    this.version = null; // of the bake shown
    this.seconds = null; // the server's bake time of it
    this.fetches = 0;
    this.aborted = 0;
  }

  setOn(on) {
    this.on = on;
    if (on) return this.refresh();
    clearTimeout(this.timer);
    this.cancel();
    this.version = null;
    this.onIndirect(null);
    return Promise.resolve();
  }

  // A new version is held: bake it once edits pause.
  schedule() {
    if (!this.on) return;
    clearTimeout(this.timer);
    this.timer = setTimeout(() => this.refresh(), DEBOUNCE_MS);
  }

  cancel() {
    if (!this.abort) return;
    this.abort.abort();
    ++this.aborted;
    this.abort = null;
  }

  async refresh() {
    this.cancel();
    const abort = new AbortController();
    this.abort = abort;
    try {
      const { buffer, seconds } = await this.api.meshIndirect(this.sceneId, abort.signal);
      if (abort.signal.aborted || !this.on) return;
      const decoded = decodeMeshBinary(buffer);
      const byPart = new Map();
      for (const part of decoded.parts)
        byPart.set(part.key, { indirect: part.indirect, vertexCount: part.vertexCount, version: decoded.sceneVersion });
      this.version = decoded.sceneVersion;
      this.seconds = seconds;
      ++this.fetches;
      this.onIndirect(byPart);
    } catch (error) {
      if (error.name !== 'AbortError') this.onError(error);
    } finally {
      if (this.abort === abort) this.abort = null;
    }
  }
}
