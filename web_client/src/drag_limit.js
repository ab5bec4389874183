// Keeps a drag where the server accepts it. The server refuses (422) a move that takes an object
// out of its edit volume, which the page does not know; so the page remembers the last transform
// the server accepted for each object, and after a refusal during a drag holds the object there:
// moves at least as far from the drag's start as the refused one are not sent (the gizmo stays at
// the last good place), nearer ones are (a refusal among them narrows the bound). A drag past the
// volume so costs one refused frame, or a few, instead of one per pointer move.

// How far a transform is from another: metres, plus degrees / 90, plus scale change.
function distance(a, b) {
  const d = (key, weight) => Math.hypot(...(a[key] || [0, 0, 0]).map((x, i) => (x - ((b[key] || [0, 0, 0])[i])) * weight));
  return d('translate', 1) + d('rotate_deg', 1 / 90) + d('scale', 1);
}

export class DragLimit {
  constructor() {
    this.accepted = new Map(); // object id → the last transform the server accepted
    this.drag = null; // {id, start, bound: distance of the nearest refused move, or Infinity}
  }

  // A drag of object `id` begins at transform `start` (the server's current one: another
  // client may have moved it since this page's last accepted move).
  start(id, start) {
    this.drag = { id, start, bound: Infinity };
    this.accepted.set(id, start);
  }

  end() {
    this.drag = null;
  }

  // Whether a move of `id` to `transform` may be sent (false: hold the object at lastGood(id)).
  allows(id, transform) {
    return !this.drag || this.drag.id !== id || distance(transform, this.drag.start) < this.drag.bound;
  }

  lastGood(id) {
    return this.accepted.get(id) || null;
  }

  // The server applied a frame: its moves are the objects' accepted places, and a light's
  // set_light its holder's (the `pose` the page attached to it, "light:ID").
  applied(edits) {
    for (const edit of edits) {
      if (edit.op === 'move') this.accepted.set(edit.id, edit.transform);
      else if (edit.op === 'set_light' && edit.pose) this.accepted.set(`light:${edit.id}`, edit.pose);
    }
  }

  // The server refused a frame. Returns the dragged object's (or light's) id when the refusal was
  // of the drag (it is now held at its last good place), else null.
  refused(edits) {
    if (!this.drag) return null;
    const edit = edits.find((e) => (e.op === 'move' && e.id === this.drag.id) || (e.op === 'set_light' && e.pose && `light:${e.id}` === this.drag.id));
    if (!edit) return null;
    this.drag.bound = Math.min(this.drag.bound, distance(edit.transform || edit.pose, this.drag.start));
    return this.drag.id;
  }
}
