// Keeps the page's copy of the lit mesh at the server's newest version: the whole binary mesh
// once, then `?since=<held version>` deltas. One fetch at a time; a request made during a fetch
// runs once more after it, so edits' answers and server events never fetch in parallel.
import { decodeMeshBinary } from './mesh_binary.js';

export class MeshSync {
  constructor(api, sceneId, onMesh) {
    this.api = api;
    this.sceneId = sceneId;
    this.onMesh = onMesh; // (decoded) → void, applies receivers
    this.version = null;
    this.running = null;
    this.again = false;
    this.lastBytes = 0;
    this.totalBytes = 0;
    this.fetches = 0;
  }

  async loadWhole() {
    const decoded = decodeMeshBinary(await this.api.meshBinary(this.sceneId));
    this.record(decoded);
    return decoded;
  }

  record(decoded) {
    this.lastBytes = decoded.bytes;
    this.totalBytes += decoded.bytes;
    ++this.fetches;
    this.version = decoded.sceneVersion;
    this.onMesh(decoded);
  }

  // Fetches what changed since the held version; resolves when the page holds at least `atLeast`.
  async refresh(atLeast = 0) {
    if (this.running) {
      this.again = true;
      await this.running;
      if (this.version >= atLeast) return;
      return this.refresh(atLeast);
    }
    this.running = (async () => {
      do {
        this.again = false;
        const buffer = await this.api.meshBinary(this.sceneId, this.version);
        const decoded = decodeMeshBinary(buffer);
        if (decoded.sceneVersion >= this.version) this.record(decoded);
      } while (this.again);
    })();
    try {
      await this.running;
    } finally {
      this.running = null;
    }
  }
}
