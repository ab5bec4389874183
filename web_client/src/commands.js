// Undo steps as commands: each finished gesture is an object that can do and undo itself against
// the page's edit target ({moveTo(id, state), structural(edits, selectId) → promise,
// isovalueTo(id, value)}), and that saves as plain JSON (the history is kept in localStorage).
//   MoveCommand     an object's absolute transform, or a light's {polygon, radiance}, before and after
//   FrameCommand    a structural change: edit lists {redo, undo} sent as one frame, then a selection
//   IsovalueCommand a volume's isovalue before and after

export class MoveCommand {
  constructor(id, before, after) {
    Object.assign(this, { id, before, after });
  }

  do(target) { return target.moveTo(this.id, this.after); }
  undo(target) { return target.moveTo(this.id, this.before); }
  toJSON() { return { kind: 'move', id: this.id, before: this.before, after: this.after }; }
}

export class FrameCommand {
  // frame: {redo, undo} edit lists; select: {redo, undo} ids selected afterwards (or null).
  constructor(frame, label, select) {
    Object.assign(this, { frame, label, select });
  }

  do(target) { return target.structural(this.frame.redo, this.select.redo); }
  undo(target) { return target.structural(this.frame.undo, this.select.undo); }
  toJSON() { return { kind: 'frame', frame: this.frame, label: this.label, select: this.select }; }
}

export class IsovalueCommand {
  constructor(id, before, after) {
    Object.assign(this, { id, before, after });
  }

  do(target) { return target.isovalueTo(this.id, this.after); }
  undo(target) { return target.isovalueTo(this.id, this.before); }
  toJSON() { return { kind: 'isovalue', id: this.id, before: this.before, after: this.after }; }
}

// A command from its saved JSON (steps saved before commands had a kind are told by their shape:
// {frame}, {id, isovalue: {before, after}}, {id, before, after}); null for what is none of these.
export function commandFromJson(json) {
  if (!json || typeof json !== 'object') return null;
  const kind = json.kind || (json.frame ? 'frame' : json.isovalue ? 'isovalue-old' : 'move');
  if (kind === 'frame' && json.frame && json.select) return new FrameCommand(json.frame, json.label, json.select);
  if (kind === 'isovalue') return new IsovalueCommand(json.id, json.before, json.after);
  if (kind === 'isovalue-old') return new IsovalueCommand(json.id, json.isovalue.before, json.isovalue.after);
  if (kind === 'move' && typeof json.id === 'string' && json.before && json.after) return new MoveCommand(json.id, json.before, json.after);
  return null;
}
