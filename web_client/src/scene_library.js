// Scenes the server holds (GET /api/scenes): a list to open one (?scene=ID) or delete it
// (DELETE, after a confirm); downloads of the current scene (its JSON, the lit mesh as GLB, the
// server's render as PNG); and the scene as first seen at version 0, kept in this browser
// (localStorage), for "Reset to file".

import { describeBuild } from './build_progress.js';
import { ElapsedCounter } from './elapsed_counter.js';

const sourceKey = (id, name) => `penumbra.source.${id}.${name}`;

// Keeps the scene JSON of version 0 (the file as the server built it) for a later reset.
export function rememberSource(id, name, version, scene) {
  if (version !== 0) return;
  try {
    localStorage.setItem(sourceKey(id, name), JSON.stringify(scene));
  } catch {
    // Storage full or disabled: reset stays unavailable for this scene.
  }
}

export function sourceOf(id, name) {
  try {
    const text = localStorage.getItem(sourceKey(id, name));
    return text ? JSON.parse(text) : null;
  } catch {
    return null;
  }
}

export function forgetSource(id, name) {
  try { localStorage.removeItem(sourceKey(id, name)); } catch { /* nothing kept */ }
}

// Saves `text` as a file named `name` through a temporary link.
export function download(name, blob) {
  const url = URL.createObjectURL(blob);
  const a = document.createElement('a');
  a.href = url;
  a.download = name;
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 1000);
}

export class SceneList {
  // onDelete(summary) → promise; onRename(summary, name) → promise; pageUrl(id) → the URL that opens a scene.
  constructor(root, { onDelete, onRename, pageUrl }) {
    Object.assign(this, { root, onDelete, onRename, pageUrl });
    this.counters = new Map(); // building scene id → its entry's seconds, counting between events
  }

  render(scenes, currentId) {
    for (const counter of this.counters.values()) counter.stop();
    this.counters.clear();
    this.root.replaceChildren(...scenes.map((summary) => {
      if (summary.state === 'building') return this.building(summary);
      const item = document.createElement('li');
      item.dataset.scene = summary.id;
      const link = document.createElement('a');
      link.href = this.pageUrl(summary.id);
      link.textContent = summary.id;
      if (summary.id === currentId) link.className = 'current';
      const info = document.createElement('span');
      info.className = 'muted';
      info.textContent = ` ${summary.name} · v${summary.version} · ${summary.objects} objects`;
      const remove = document.createElement('button');
      remove.type = 'button';
      remove.textContent = 'Delete';
      remove.dataset.action = 'delete';
      remove.title = `DELETE /api/scenes/${summary.id}`;
      remove.addEventListener('click', () => {
        if (window.confirm(`Delete scene ${summary.id} (${summary.name}) from the server?`)) this.onDelete(summary);
      });
      const rename = document.createElement('button');
      rename.type = 'button';
      rename.textContent = 'Rename';
      rename.dataset.action = 'rename';
      rename.title = `Give scene ${summary.id} a new name (PATCH /api/scenes/${summary.id}; kept across restarts)`;
      rename.addEventListener('click', () => {
        const name = window.prompt(`New name for scene ${summary.id}:`, summary.name);
        if (name !== null && name !== summary.name) this.onRename(summary, name);
      });
      item.append(link, info, rename, remove);
      return item;
    }));
  }

  // While the list holds a build (url: the builds event stream; null: none), its entry follows the
  // stream's `event: build`; a build that ended, or one not listed yet, asks refresh() for the
  // list again, as does a stream refused (after a second: polling while it is down).
  followBuilds(url, refresh) {
    if (!url) {
      if (this.builds) this.builds.close();
      this.builds = null;
      return;
    }
    if (this.builds) return;
    const source = new EventSource(url);
    this.builds = source;
    const again = () => { // one list request at a time
      if (!this.asking) this.asking = Promise.resolve(refresh()).finally(() => { this.asking = null; });
    };
    source.addEventListener('build', (event) => {
      let build;
      try {
        build = JSON.parse(event.data);
      } catch {
        return;
      }
      const item = this.root.querySelector(`li[data-state="building"][data-scene="${CSS.escape(build.id)}"]`);
      if (build.state === 'building' && item) item.replaceWith(this.building(build));
      else again();
    });
    source.addEventListener('error', () => {
      if (source.readyState !== EventSource.CLOSED || this.builds !== source) return;
      this.builds = null;
      setTimeout(again, 1000);
    });
  }

  // A scene the server is still building: its stage and fraction, and Cancel (DELETE).
  building(summary) {
    const item = document.createElement('li');
    item.dataset.scene = summary.id;
    item.dataset.state = 'building';
    const info = document.createElement('span');
    info.className = 'muted';
    // The stream sends the entry when its stage or counts change; the seconds count on here.
    this.counters.get(summary.id)?.stop();
    const counter = new ElapsedCounter((text) => { info.textContent = text; });
    counter.start(`${summary.id} · building: ${describeBuild(summary.progress)} ·`, summary.progress.elapsed_seconds);
    this.counters.set(summary.id, counter);
    const cancel = document.createElement('button');
    cancel.type = 'button';
    cancel.textContent = 'Cancel';
    cancel.title = `DELETE /api/scenes/${summary.id}: stops its build`;
    cancel.addEventListener('click', () => this.onDelete(summary));
    item.append(info, cancel);
    return item;
  }
}
