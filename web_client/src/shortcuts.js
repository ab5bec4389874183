// The editor's keyboard shortcuts (keys typed into a text field are text, not commands) and the
// "?" sheet that lists the mouse's gestures (three.js OrbitControls and the gizmo) and the keys. W / E / R and Esc belong to the gizmo (selection_gizmo.js); they are
// listed here too.

export const MOUSE = [
  ['Click', 'select an object or a light (walls and floors once unlocked); drag its gizmo to move it'],
  ['Left drag on empty space, a wall or the floor', 'orbit around the view\'s centre (never under the floor)'],
  ['Right drag, or Shift + left drag', 'pan'],
  ['Wheel', 'zoom (move the camera nearer or farther)'],
];

export const SHORTCUTS = [
  ['W / E / R', 'move / rotate / scale the selection (an object or a light)'],
  ['Ctrl (held while dragging)', 'snap: 0.1 m, 15°, 0.1 (or tick "snap")'],
  ['F', 'focus the selection (nothing selected: frame all)'],
  ['A', 'frame all'],
  ['H', 'camera back to the scene\'s'],
  ['B', 'add a box'],
  ['Ctrl+D', 'duplicate the selection (a light: add a copy beside it)'],
  ['Delete / Backspace', 'delete the selection (a light too, unless it is the last)'],
  ['Ctrl+Z / Ctrl+Shift+Z (Ctrl+Y)', 'undo / redo'],
  ['Esc', 'deselect; close this sheet'],
  ['?', 'this sheet'],
];

const isTyping = (target) => target instanceof HTMLInputElement && !['checkbox', 'button', 'file'].includes(target.type);

// actions: {undo, redo, focus, frameAll, home, addBox, duplicate, remove, ready()}
export function installShortcuts(actions, help) {
  help.replaceChildren();
  for (const [heading, rows] of [['Mouse', MOUSE], ['Keys', SHORTCUTS]]) {
    const title = document.createElement('h2');
    title.textContent = heading;
    const table = document.createElement('table');
    table.dataset.sheet = heading.toLowerCase();
    for (const [keys, what] of rows) {
      const row = table.insertRow();
      row.insertCell().textContent = keys;
      row.insertCell().textContent = what;
    }
    help.append(title, table);
  }
  help.addEventListener('click', () => { help.hidden = true; });
  const toggleHelp = () => { help.hidden = !help.hidden; };

  window.addEventListener('keydown', (event) => {
    if (isTyping(event.target)) return;
    if (event.key === '?') { toggleHelp(); return; }
    if (event.key === 'Escape') help.hidden = true;
    if (!actions.ready()) return;
    const ctrl = event.ctrlKey || event.metaKey;
    const key = event.key.toLowerCase();
    let action = null;
    if (ctrl && key === 'z') action = event.shiftKey ? actions.redo : actions.undo;
    else if (ctrl && key === 'y') action = actions.redo;
    else if (ctrl && key === 'd') action = actions.duplicate;
    else if (!ctrl && !event.altKey) {
      action = { f: actions.focus, a: actions.frameAll, h: actions.home, b: actions.addBox, delete: actions.remove, backspace: actions.remove }[key] || null;
    }
    if (!action) return;
    event.preventDefault();
    action();
  });
  return toggleHelp;
}
