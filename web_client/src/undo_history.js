// Undo / redo: each step is one finished gesture as a command (commands.js) that does and undoes
// itself against the page's edit target. Kept in this browser (localStorage, per scene) with the
// scene version it leads to, so that a reload keeps it; a history whose version is not the
// scene's when the page opens (another client edited, the server restarted) is dropped rather
// than applied to a scene it does not describe. Every change is announced as the hub's `history`.
import { commandFromJson } from './commands.js';

const KEEP = 200;

export class UndoHistory {
  // hub: the page's EventHub (or null: nobody is told).
  constructor(hub = null) {
    this.hub = hub;
    this.done = [];
    this.undone = [];
    this.storageKey = null;
  }

  // Does `command` against `target` and, once it has succeeded, records it.
  async execute(command, target) {
    await command.do(target);
    this.record(command);
  }

  // Records a command already done (a drag that has moved its object).
  record(command) {
    this.done.push(command);
    if (this.done.length > KEEP) this.done.shift();
    this.undone = [];
    this.changed();
  }

  // Undoes the last step against `target`: null when there is none, else a promise that settles
  // once it is undone (at once for a move; a frame once the server answered).
  undo(target) {
    const command = this.done.pop();
    if (!command) return null;
    this.undone.push(command);
    this.changed();
    return Promise.resolve(command.undo(target));
  }

  // Does the last undone step again against `target` (null or a promise, as undo).
  redo(target) {
    const command = this.undone.pop();
    if (!command) return null;
    this.done.push(command);
    this.changed();
    return Promise.resolve(command.do(target));
  }

  // Forgets every step (the scene is no longer the one they were made on).
  clear() {
    this.done = [];
    this.undone = [];
    this.changed();
  }

  canUndo() { return this.done.length > 0; }
  canRedo() { return this.undone.length > 0; }

  changed() {
    if (this.hub) this.hub.emit('history', this);
  }

  // Takes back the history kept for scene `key` if it leads to `version`; from now on saves there.
  restore(key, version) {
    this.storageKey = `penumbra.history.${key}`;
    try {
      const kept = JSON.parse(localStorage.getItem(this.storageKey) || 'null');
      if (kept && kept.version === version) {
        this.done = kept.done.map(commandFromJson).filter(Boolean);
        this.undone = kept.undone.map(commandFromJson).filter(Boolean);
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
