// Undo / redo: each entry is one finished gesture, either a move {id, before, after} (absolute
// transforms; undoing re-sends `before`, redoing `after`) or a structural change {frame: {redo,
// undo}, select, label} (edit lists; undoing sends frame.undo). Kept in this browser
// (localStorage, per scene) with the scene version it leads to, so that a reload keeps it; a
// history whose version is not the scene's when the page opens (another client edited, the
// server restarted) is dropped rather than applied to a scene it does not describe.

const KEEP = 200;

export class UndoHistory {
  constructor() {
    this.done = [];
    this.undone = [];
    this.storageKey = null;
  }

  push(entry) {
    this.done.push(entry);
    if (this.done.length > KEEP) this.done.shift();
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

  // Forgets every step (the scene is no longer the one they were made on).
  clear() {
    this.done = [];
    this.undone = [];
  }

  canUndo() { return this.done.length > 0; }
  canRedo() { return this.undone.length > 0; }

  // Takes back the history kept for scene `key` if it leads to `version`; from now on saves there.
  restore(key, version) {
    this.storageKey = `penumbra.history.${key}`;
    try {
      const kept = JSON.parse(localStorage.getItem(this.storageKey) || 'null');
      if (kept && kept.version === version) {
        this.done = kept.done;
        this.undone = kept.undone;
      }
    } catch {
      // Unreadable or no storage: start empty.
    }
  }

  // Saves the history as leading to scene version `version`.
  save(version) {
    if (!this.storageKey) return;
    try {
      localStorage.setItem(this.storageKey, JSON.stringify({ version, done: this.done, undone: this.undone }));
    } catch {
      // Storage full or disabled: the history lives until the page is left.
    }
  }
}
