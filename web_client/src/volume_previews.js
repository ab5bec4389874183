// Fetches volumes' isosurface previews (GET .../volumes/ID/preview?isovalue=v) at the page's pace:
// one request in flight per volume, and the newest isovalue asked for meanwhile goes next, so a
// slider dragged fast never queues stale previews.
import { setVolumeSurface } from './volume_stand_ins.js';

export class VolumePreviews {
  // holderOf(id): the volume's holder (or null once it left); onDrawn(): redraw the view.
  constructor(api, sceneId, holderOf, onDrawn, onError) {
    this.api = api;
    this.sceneId = sceneId;
    this.holderOf = holderOf;
    this.onDrawn = onDrawn;
    this.onError = onError;
    this.wanted = new Map(); // volume id → isovalue still to fetch
    this.running = new Map(); // volume id → promise of the fetch in flight
    this.fetches = 0;
  }

  request(id, isovalue) {
    this.wanted.set(id, isovalue);
    if (!this.running.has(id)) this.pump(id);
  }

  pump(id) {
    if (!this.wanted.has(id)) return;
    const isovalue = this.wanted.get(id);
    this.wanted.delete(id);
    const path = `${this.api.scenePath(this.sceneId)}/volumes/${encodeURIComponent(id)}/preview?isovalue=${isovalue}`;
    ++this.fetches;
    const task = this.api.json('GET', path).then((preview) => {
      const holder = this.holderOf(id);
      if (holder) setVolumeSurface(holder, preview);
      this.onDrawn();
    }, (error) => { if (error.status !== 404) this.onError(error); })
      .finally(() => {
        this.running.delete(id);
        this.pump(id);
      });
    this.running.set(id, task);
  }

  busy() {
    return this.running.size > 0 || this.wanted.size > 0;
  }

  async idle() {
    while (this.busy()) await Promise.allSettled([...this.running.values()]);
  }
}
