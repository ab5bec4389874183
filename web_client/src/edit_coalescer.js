// Sends edits at the server's pace: at most one frame in flight; transforms (and light edits)
// submitted meanwhile wait in one slot per object or light, a newer one replacing the older, and
// leave together as the next frame. So a drag never queues stale frames, however fast the mouse moves.

export class EditCoalescer {
  // sendFrame(frame) → promise of the server's answer (and whatever follow-up the page needs);
  // onError(error, frame) for a frame that failed.
  constructor(sendFrame, { onError } = {}) {
    this.sendFrame = sendFrame;
    this.onError = onError || (() => {});
    this.pending = new Map(); // object id or "light:ID" → its latest edit
    this.inFlight = null;
    this.sent = 0;
    this.replaced = 0;
    this.waiters = [];
  }

  // Queues an absolute move of one object.
  move(objectId, transform) {
    this.queue(objectId, { op: 'move', id: objectId, transform });
  }

  // Queues a volume's new isovalue (set_volume; a newer one replaces it).
  setVolume(volumeId, isovalue) {
    this.queue(`volume:${volumeId}`, { op: 'set_volume', id: volumeId, isovalue });
  }

  // Queues a light's new polygon and/or radiance (fields of a set_light; a newer one replaces
  // an older one's fields, keeping those it does not name). `pose`: the light holder's transform
  // for DragLimit (not sent).
  setLight(lightId, fields, pose) {
    const key = `light:${lightId}`;
    const edit = { ...(this.pending.get(key) || {}), op: 'set_light', id: lightId, ...fields };
    delete edit.pose; // an older pose does not describe the new fields
    if (pose) edit.pose = pose;
    this.queue(key, edit);
  }

  queue(key, edit) {
    if (this.pending.has(key)) ++this.replaced;
    this.pending.set(key, edit);
    this.pump();
  }

  pump() {
    if (this.inFlight || this.pending.size === 0) {
      if (!this.inFlight) this.settle();
      return;
    }
    const edits = [...this.pending.values()];
    this.pending.clear();
    ++this.sent;
    this.inFlight = Promise.resolve()
      .then(() => this.sendFrame({ edits }))
      .catch((error) => this.onError(error, { edits }))
      .finally(() => {
        this.inFlight = null;
        this.pump();
      });
  }

  // Forgets an edit of `key` (an object id or "light:ID") not sent yet.
  discard(key) {
    this.pending.delete(key);
  }

  busy() {
    return this.inFlight !== null || this.pending.size > 0;
  }

  // Resolves once nothing is in flight or pending.
  idle() {
    if (!this.busy()) return Promise.resolve();
    return new Promise((resolve) => this.waiters.push(resolve));
  }

  settle() {
    const waiters = this.waiters;
    this.waiters = [];
    for (const resolve of waiters) resolve();
  }
}
