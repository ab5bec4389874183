// Sends edits at the server's pace: at most one frame in flight; transforms submitted meanwhile
// wait in one slot per object, a newer one replacing the older, and leave together as the next
// frame. So a drag never queues stale frames, however fast the mouse moves.

export class EditCoalescer {
  // sendFrame(frame) → promise of the server's answer (and whatever follow-up the page needs);
  // onError(error, frame) for a frame that failed.
  constructor(sendFrame, { onError } = {}) {
    this.sendFrame = sendFrame;
    this.onError = onError || (() => {});
    this.pending = new Map(); // object id → latest absolute transform
    this.inFlight = null;
    this.sent = 0;
    this.replaced = 0;
    this.waiters = [];
  }

  // Queues an absolute move of one object.
  move(objectId, transform) {
    if (this.pending.has(objectId)) ++this.replaced;
    this.pending.set(objectId, transform);
    this.pump();
  }

  pump() {
    if (this.inFlight || this.pending.size === 0) {
      if (!this.inFlight) this.settle();
      return;
    }
    const edits = [...this.pending].map(([id, transform]) => ({ op: 'move', id, transform }));
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

  // Forgets a move of `objectId` not sent yet.
  discard(objectId) {
    this.pending.delete(objectId);
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
