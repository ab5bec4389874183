// The side panel's buttons and boxes wired to the page's parts and the editor's commands, the
// undo and redo buttons following the undo history, plus the keyboard shortcuts.
import { installShortcuts } from './shortcuts.js';

const $ = (id) => document.getElementById(id);

// page: {hub, api, state, history, editor, gizmo, view, objects, receivers, outliner, renderPanel,
//   bakedIndirect, undo(), redo(), fail(error)}.
export function installPanelControls(page) {
  const { hub, api, state, history, editor, gizmo, view, objects, receivers, outliner, renderPanel, bakedIndirect, fail } = page;
  const click = (id, action) => $(id).addEventListener('click', () => action());
  click('mode-translate', () => gizmo.setMode('translate'));
  click('mode-rotate', () => gizmo.setMode('rotate'));
  click('mode-scale', () => gizmo.setMode('scale'));
  click('undo', () => page.undo());
  click('redo', () => page.redo());
  const undoButtons = () => {
    $('undo').disabled = !history.canUndo();
    $('redo').disabled = !history.canRedo();
  };
  hub.on('history', undoButtons);
  undoButtons();
  click('add-box', () => editor.addBox());
  click('add-primitive', () => editor.addPrimitive($('primitive').value));
  click('add-light', () => editor.addLight());
  click('duplicate', () => editor.duplicate());
  click('delete', () => editor.deleteSelected());
  click('focus', () => editor.focus());
  click('frame-all', () => editor.frameAll());
  click('camera-home', () => view.goHome());
  click('reset-scene', () => editor.resetToFile());
  click('download-json', () => editor.downloadJson());
  click('download-glb', () => editor.downloadGlb());
  click('download-png', () => editor.downloadPng($('png-size').value));
  $('snap').addEventListener('change', (event) => gizmo.setSnap(event.target.checked));
  $('unlock-shell').addEventListener('change', (event) => {
    objects.unlocked = event.target.checked;
    outliner.render(objects, gizmo.selected);
    if (!event.target.checked && gizmo.selected && objects.byId.get(gizmo.selected)?.userData.locked) gizmo.select(null);
  });
  $('toggle-edges').addEventListener('change', (event) => {
    receivers.setEdgesVisible(event.target.checked);
    view.requestRender();
    $('edge-legend').hidden = !event.target.checked;
  });
  // Bounced light: by sensors in the server's image, baked per vertex on the mesh (both off at first).
  $('toggle-gi').addEventListener('change', (event) => renderPanel.setGi(event.target.checked));
  $('toggle-indirect').addEventListener('change', (event) => bakedIndirect.setOn(event.target.checked));
  $('rebuild').addEventListener('click', async () => {
    $('rebuild').disabled = true;
    try {
      hub.emit('built', await api.rebuild(state.id), true);
    } catch (error) {
      fail(error);
    } finally {
      $('rebuild').disabled = false;
    }
  });
  const toggleHelp = installShortcuts({
    ready: () => !gizmo.dragging,
    undo: () => page.undo(), redo: () => page.redo(),
    focus: () => editor.focus(), frameAll: () => editor.frameAll(), home: () => view.goHome(),
    addBox: () => editor.addBox(), duplicate: () => editor.duplicate(), remove: () => editor.deleteSelected(),
  }, $('help'));
  click('show-help', toggleHelp);
}
