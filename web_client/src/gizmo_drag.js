// Selecting and dragging in the view: the selection gizmo's click selects (the hub's
// `selection`); a drag moves the stand-in and sends its moves through the coalescer (held at the
// last accepted place past the edit volume, DragLimit), the inspector following (`moved`); the
// drag's end is one undo step (a MoveCommand) and asks for a new server image. The mode buttons
// show the gizmo's mode.
import { MoveCommand } from './commands.js';
import { applyTransform, sameTransform, transformOf } from './scene_transform.js';
import { SelectionGizmo } from './selection_gizmo.js';

const $ = (id) => document.getElementById(id);
const isLight = (id) => !!id && id.startsWith('light:');

const showMode = (mode) => {
  for (const m of ['translate', 'rotate', 'scale']) $(`mode-${m}`).classList.toggle('active', mode === m);
};

// What undo restores of a selection: an object's transform, a light's {polygon, radiance}.
function stateOf(objects, id) {
  if (!isLight(id)) return transformOf(objects.byId.get(id));
  const light = objects.lightJson.get(id.slice(6));
  return { polygon: light.polygon, radiance: light.radiance };
}

// page: {hub, view, objects, edits: SceneEdits, dragLimit, history}. Returns the SelectionGizmo.
export function installGizmo({ hub, view, objects, edits, dragLimit, history }) {
  let dragStart = null;
  const gizmo = new SelectionGizmo(view, objects, {
    onSelect: (id) => hub.emit('selection', id),
    onDragStart: (id) => {
      dragStart = { id, before: stateOf(objects, id) };
      dragLimit.start(id, transformOf(gizmo.holder()));
      view.setInteracting('drag', true);
    },
    onChange: (id) => {
      const transform = transformOf(gizmo.holder());
      // A light scaled to nothing or mirrored (it would face the other way) is held too.
      const flat = isLight(id) && !transform.scale.every((x) => x > 1e-3);
      if (!dragLimit.allows(id, transform) || flat) applyTransform(gizmo.holder(), dragLimit.lastGood(id)); // held at the last good place
      else if (isLight(id)) edits.coalescer.setLight(id.slice(6), { polygon: objects.lightPolygon(id.slice(6)) }, transform);
      else edits.coalescer.move(id, transform);
      // The inspector's fields follow the dragged holder (not yet the server's scene).
      hub.emit('moved', id, isLight(id) ? { polygon: objects.lightPolygon(id.slice(6)) } : transformOf(gizmo.holder()));
    },
    onDragEnd: (id) => {
      dragLimit.end();
      view.setInteracting('drag', false);
      hub.emit('imageStale');
      const start = dragStart;
      dragStart = null;
      if (!start || start.id !== id) return;
      let after;
      if (isLight(id)) {
        // The light's holder back at the new polygon's centre, unturned (the next drag starts there).
        after = { polygon: objects.lightPolygon(id.slice(6)), radiance: start.before.radiance };
        objects.setLight(id.slice(6), after);
      } else {
        after = transformOf(gizmo.holder());
      }
      if (!sameTransform(start.before, after)) history.record(new MoveCommand(id, start.before, after));
      else history.changed();
      hub.emit('moved', id, after);
    },
    onMode: showMode,
  });
  showMode('translate');
  return gizmo;
}
