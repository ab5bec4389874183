// Renaming a scene on the server (PATCH /api/scenes/ID {"name"}): what this browser keeps under the
// scene's id and name (its file at version 0 for "Reset to file", its undo history) moves to the
// new name, and the page's header follows when it is the scene on show.

const KEPT = ['penumbra.source', 'penumbra.history', 'penumbra.look'];

function moveKept(id, from, to) {
  try {
    for (const prefix of KEPT) {
      const text = localStorage.getItem(`${prefix}.${id}.${from}`);
      if (text === null) continue;
      localStorage.setItem(`${prefix}.${id}.${to}`, text);
      localStorage.removeItem(`${prefix}.${id}.${from}`);
    }
  } catch {
    // No storage: nothing was kept.
  }
}

// Renames scene `summary` ({id, name}) to `name`; resolves to the server's summary of it.
export async function renameScene(app, summary, name) {
  const answer = await app.api.json('PATCH', app.api.scenePath(summary.id), { name });
  moveKept(summary.id, summary.name, answer.name);
  if (summary.id === app.sceneId) {
    app.sceneName = answer.name;
    app.history.storageKey = `penumbra.history.${summary.id}.${answer.name}`;
    if (app.look) app.look.setting.key = `penumbra.look.${summary.id}.${answer.name}`;
    document.getElementById('scene-name').textContent = `${summary.id} (${answer.name})`;
  }
  return answer;
}
