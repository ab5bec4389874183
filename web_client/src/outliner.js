// The outliner: the scene's lights and objects as a list; a click selects (a locked wall or floor
// only once "unlock walls and floors" is ticked), the selection is highlighted.

export class Outliner {
  // onPick(id): select `id` (an object id or "light:ID").
  constructor(root, onPick) {
    this.root = root;
    this.onPick = onPick;
    root.addEventListener('click', (event) => {
      const item = event.target.closest('li[data-id]');
      if (item && !item.classList.contains('locked')) this.onPick(item.dataset.id);
    });
  }

  // objects: SceneObjects; selected: the selection's id or null.
  render(objects, selected) {
    const items = [];
    const add = (id, label, locked) => {
      const item = document.createElement('li');
      item.dataset.id = id;
      item.textContent = label;
      if (locked) {
        item.classList.add('locked');
        item.title = 'locked: tick "unlock walls and floors" to select it';
      }
      if (id === selected) item.classList.add('selected');
      items.push(item);
    };
    for (const id of objects.lightJson.keys()) add(`light:${id}`, `☀ ${id}`, false);
    for (const [id, holder] of objects.byId) add(id, id, holder.userData.locked && !objects.unlocked);
    this.root.replaceChildren(...items);
  }

  highlight(selected) {
    for (const item of this.root.children) item.classList.toggle('selected', item.dataset.id === selected);
  }
}

// The outliner on the page (page: {hub, objects, select(id), selection()}): drawn again when the
// stand-ins are, its highlight following the selection.
export function installOutliner({ hub, objects, select, selection }) {
  const outliner = new Outliner(document.getElementById('outliner'), (id) => select(id));
  hub.on('standIns', () => outliner.render(objects, selection()));
  hub.on('selection', (id) => outliner.highlight(id));
  return outliner;
}
