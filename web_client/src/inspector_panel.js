// The inspector on the page: what it shows follows the hub (the selection; an object or light the
// page moved, a drag included; the server's transforms taken in), and what is typed in it goes to
// the editor's commands (one undo step each).
import { Inspector } from './inspector.js';
import { transformOf } from './scene_transform.js';

const $ = (id) => document.getElementById(id);
const isLight = (id) => !!id && id.startsWith('light:');

// page: {hub, objects, state, editor, view}.
export function installInspector({ hub, objects, state, editor, view }) {
  const inspector = new Inspector($('inspector'), (id, transform) => editor.typedTransform(id, transform),
    (lightId, light) => editor.typedLight(lightId, light), {
      onRename: (id, name) => editor.rename(id, name),
      onMaterial: (id, material) => editor.setMaterial(id, material),
      materials: () => Object.entries((state.json && state.json.materials) || {}),
      materialOf: (id) => (objects.json.get(id) || {}).material,
      onPaint: (id, change) => editor.paint(id, change),
      paintable: (id) => { const o = objects.json.get(id); return !!o && o.type !== 'volume'; },
    });
  hub.on('selection', (id) => {
    const light = isLight(id) ? objects.lightJson.get(id.slice(6)) : null;
    inspector.show(id, light || (id ? transformOf(objects.byId.get(id)) : null));
  });
  // moved: an object's transform, or a light's fields that changed ({polygon} while dragged).
  const show = (id, moved) => {
    if (inspector.id !== id) return;
    if (isLight(id)) inspector.update({ ...objects.lightJson.get(id.slice(6)), ...moved });
    else inspector.update(moved);
  };
  // During a drag the fields change with the view's frames, not with each step: a change of the
  // page's text makes the browser composite a frame of its own (on a software GL ~15 ms of CPU,
  // whatever changed), and a drag's steps come faster than its frames.
  let pending = null;
  view.onDraw(() => {
    if (!pending) return;
    const [id, moved] = pending;
    pending = null;
    show(id, moved);
  });
  hub.on('moved', (id, moved) => {
    if (view.interactions.has('drag')) pending = [id, moved];
    else {
      pending = null;
      show(id, moved);
    }
  });
  hub.on('synced', () => {
    const { id } = inspector;
    if (isLight(id)) inspector.update(objects.lightJson.get(id.slice(6)));
    else if (id && objects.byId.get(id)) inspector.update(transformOf(objects.byId.get(id)));
  });
  return inspector;
}
