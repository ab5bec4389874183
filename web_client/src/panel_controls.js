// The side panel's buttons and boxes wired to the page (app) and the editor's commands (editor),
// plus the keyboard shortcuts.
import { installShortcuts } from './shortcuts.js';

const $ = (id) => document.getElementById(id);

export function installPanelControls(app, editor) {
  const click = (id, action) => $(id).addEventListener('click', () => action());
  click('mode-translate', () => app.gizmo.setMode('translate'));
  click('mode-rotate', () => app.gizmo.setMode('rotate'));
  click('mode-scale', () => app.gizmo.setMode('scale'));
  click('undo', () => app.undo());
  click('redo', () => app.redo());
  click('add-box', () => editor.addBox());
  click('add-primitive', () => editor.addPrimitive($('primitive').value));
  click('add-light', () => editor.addLight());
  click('duplicate', () => editor.duplicate());
  click('delete', () => editor.deleteSelected());
  click('focus', () => editor.focus());
  click('frame-all', () => editor.frameAll());
  click('camera-home', () => app.view.goHome());
  click('reset-scene', () => editor.resetToFile());
  click('download-json', () => editor.downloadJson());
  click('download-glb', () => editor.downloadGlb());
  click('download-png', () => editor.downloadPng($('png-size').value));
  $('snap').addEventListener('change', (event) => app.gizmo.setSnap(event.target.checked));
  $('unlock-shell').addEventListener('change', (event) => {
    app.objects.unlocked = event.target.checked;
    app.outliner.render(app.objects, app.gizmo.selected);
    if (!event.target.checked && app.gizmo.selected && app.objects.byId.get(app.gizmo.selected)?.userData.locked) app.gizmo.select(null);
  });
  $('toggle-edges').addEventListener('change', (event) => {
    app.receivers.setEdgesVisible(event.target.checked);
    app.view.requestRender();
    $('edge-legend').hidden = !event.target.checked;
  });
  // Bounced light: by sensors in the server's image, baked per vertex on the mesh (both off at first).
  $('toggle-gi').addEventListener('change', (event) => app.renderPanel.setGi(event.target.checked));
  $('toggle-indirect').addEventListener('change', (event) => app.bakedIndirect.setOn(event.target.checked));
  $('rebuild').addEventListener('click', async () => {
    $('rebuild').disabled = true;
    try {
      app.timings.rebuild = await app.api.rebuild(app.sceneId);
      app.timings.draw();
      app.plot.setBuild(app.timings.rebuild.seconds.total, `rebuild of v${app.timings.rebuild.version}`, true);
    } catch (error) {
      app.fail(error);
    } finally {
      $('rebuild').disabled = false;
    }
  });
  const toggleHelp = installShortcuts({
    ready: () => !!app.gizmo && !app.gizmo.dragging,
    undo: () => app.undo(), redo: () => app.redo(),
    focus: () => editor.focus(), frameAll: () => editor.frameAll(), home: () => app.view.goHome(),
    addBox: () => editor.addBox(), duplicate: () => editor.duplicate(), remove: () => editor.deleteSelected(),
  }, $('help'));
  click('show-help', toggleHelp);
}
