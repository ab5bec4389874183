// Renaming a scene on the server (PATCH /api/scenes/ID {"name"}): what this browser keeps under the
// scene's id and name (its file at version 0 for "Reset to file", its undo history) moves to the
// new name.

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

// Renames scene `summary` ({id, name}) to `name`; resolves to the server's summary of it. The page
// on show follows by the hub's `renamed` (its caller's).
export async function renameScene(api, summary, name) {
  const answer = await api.json('PATCH', api.scenePath(summary.id), { name });
  moveKept(summary.id, summary.name, answer.name);
  return answer;
}
