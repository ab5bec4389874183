// Undo / redo of object transforms: each entry is one finished gesture {id, before, after}
// (absolute transforms); undoing re-sends `before`, redoing re-sends `after`.

export class UndoHistory {
  constructor() {
    this.done = [];
    this.undone = [];
  }

  push(entry) {
    this.done.push(entry);
    this.undone = [];
  }

  // The entry to apply backwards (send entry.before), or null.
  undo() {
    const entry = this.done.pop();
    if (entry) this.undone.push(entry);
    return entry || null;
  }

  // The entry to apply again (send entry.after), or null.
  redo() {
    const entry = this.undone.pop();
    if (entry) this.done.push(entry);
    return entry || null;
  }

  canUndo() { return this.done.length > 0; }
  canRedo() { return this.undone.length > 0; }
}
