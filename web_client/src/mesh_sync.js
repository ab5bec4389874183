// Keeps the page's copy of the lit mesh at the server's newest version: the whole binary mesh
// once, then `?since=<held version>` deltas. One fetch at a time; requests made during a fetch
// that it does not satisfy share one more fetch after it, so edits' answers and server events
// never fetch in parallel and a delta always applies to the version it was computed from.
import { decodeMeshBinary } from './mesh_binary.js';

export class MeshSync {
  constructor(api, sceneId, onMesh) {
    this.api = api;
    this.sceneId = sceneId;
    this.onMesh = onMesh; // (decoded) → void, applies parts
    this.version = null;
    this.running = null; // the fetch loop's promise (never rejects) while it runs
    this.waiters = []; // {atLeast, resolve, reject, asked: fetches begun since the request}
    this.lastBytes = 0;
    this.totalBytes = 0;
    this.fetches = 0;
  }

  // download: () → promise of the whole mesh's bytes (default: fetched here).
  async loadWhole(download = () => this.api.meshBinary(this.sceneId)) {
    const decoded = decodeMeshBinary(await download());
    this.record(decoded);
    return decoded;
  }

  // The whole mesh again, whatever version the page held (the server came back, perhaps restarted).
  async reload() {
    while (this.running) await this.running;
    this.version = null;
    return this.loadWhole();
  }

  record(decoded) {
    this.lastBytes = decoded.bytes;
    this.totalBytes += decoded.bytes;
    ++this.fetches;
    if (decoded.sceneVersion < this.version) return; // a stale answer: keep the newer mesh
    if (decoded.delta && decoded.since !== this.version)
      throw new Error(`binary mesh: a delta since version ${decoded.since} but the page holds version ${this.version}`);
    this.version = decoded.sceneVersion;
    this.onMesh(decoded);
  }

  // Fetches what changed since the held version. Resolves, right after the fetch that brought
  // the page to at least `atLeast` (a version the server answered or announced), with {version,
  // bytes} of that fetch.
  refresh(atLeast = 0) {
    return new Promise((resolve, reject) => {
      this.waiters.push({ atLeast, resolve, reject, asked: 0 });
      if (!this.running) this.running = this.run();
    });
  }

  async run() {
    try {
      while (this.waiters.length) {
        for (const w of this.waiters) ++w.asked;
        const decoded = decodeMeshBinary(await this.api.meshBinary(this.sceneId, this.version));
        this.record(decoded);
        const done = { version: this.version, bytes: decoded.bytes };
        const waiting = [];
        for (const w of this.waiters) {
          if (w.atLeast <= this.version) w.resolve(done);
          // A fetch begun after the server answered or announced `atLeast` reaches it; allow a
          // retry, then say so rather than poll forever.
          else if (w.asked >= 2) w.reject(new Error(`the server serves version ${this.version}, older than the ${w.atLeast} it announced`));
          else waiting.push(w);
        }
        this.waiters = waiting;
      }
    } catch (error) {
      const waiters = this.waiters;
      this.waiters = [];
      for (const w of waiters) w.reject(error);
    } finally {
      this.running = null; // in the same tick as the loop's last check, so no request is missed
    }
  }
}
