// The server's rendering of the page's current view (GET /image with the camera as query
// parameters), refreshed a short while after the camera or the scene version stops changing;
// a newer request aborts the older one.

const DEBOUNCE_MS = 250;
const WIDTH = 320;

export class RenderPanel {
  constructor(api, sceneId, view, img, info, onError) {
    Object.assign(this, { api, sceneId, view, img, info, onError });
    this.timer = null;
    this.abort = null;
    this.url = null;
    this.renders = 0;
    this.lastVersion = null;
  }

  schedule() {
    clearTimeout(this.timer);
    this.timer = setTimeout(() => this.refresh(), DEBOUNCE_MS);
  }

  async refresh() {
    if (this.abort) this.abort.abort();
    const abort = new AbortController();
    this.abort = abort;
    const width = WIDTH;
    const height = Math.max(1, Math.round(WIDTH / this.view.aspect()));
    try {
      const { blob, version, seconds } = await this.api.image(this.sceneId, width, height, this.view.cameraQuery(), abort.signal);
      if (this.url) URL.revokeObjectURL(this.url);
      this.url = URL.createObjectURL(blob);
      this.img.src = this.url;
      this.lastVersion = version;
      ++this.renders;
      this.info.textContent = `v${version}, ${width}×${height}, ${(seconds * 1000).toFixed(0)} ms`;
    } catch (error) {
      if (error.name !== 'AbortError') this.onError(error);
    } finally {
      if (this.abort === abort) this.abort = null;
    }
  }
}
