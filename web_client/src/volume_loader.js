// "Load a volume": a .nrrd file picked in the panel is uploaded to the served scene
// (POST /api/scenes/ID/volumes, the file as the body: one frame, one version, journaled), placed
// at the view's centre on the floor, selected, and recorded for undo (undo removes it; redo adds
// it back by add_volume naming the file the server kept).
import * as THREE from 'three';
import { addEdits } from './object_edits.js';

// The new volume's place: its grid box's centre under the view's target, its bottom on the floor.
function placement(app, info) {
  const box = new THREE.Box3();
  for (let c = 0; c < 8; ++c) {
    const p = new THREE.Vector3();
    info.axes.forEach((axis, k) => { if (c & (1 << k)) p.add(new THREE.Vector3(...axis)); });
    box.expandByPoint(p);
  }
  const centre = box.getCenter(new THREE.Vector3());
  const target = app.view.controls.target;
  const floor = app.objects.bounds.isEmpty() ? 0 : app.objects.bounds.min.y;
  return [target.x - centre.x, floor + 1e-3 - box.min.y, target.z - centre.z];
}

export function installVolumeLoader(input, app, editor) {
  input.addEventListener('change', async () => {
    const file = input.files && input.files[0];
    input.value = '';
    if (!file) return;
    const task = (async () => {
      await app.coalescer.idle();
      const path = `${app.api.scenePath(app.sceneId)}/volumes?name=${encodeURIComponent(file.name)}`;
      const response = await app.api.request('POST', path, { body: file, headers: { 'Content-Type': 'application/octet-stream' } });
      const result = await response.json();
      const { id } = result.volume;
      app.ownVersions.add(result.version);
      app.knownVersion = result.version;
      await app.reloadObjects(id);
      // Centred in view: one move, part of the same undoable step.
      const object = app.sceneJson.objects.find((o) => o.id === id);
      const transform = { translate: placement(app, result.volume), rotate_deg: [0, 0, 0], scale: [1, 1, 1] };
      app.moveTo(id, transform);
      await app.coalescer.idle();
      const placed = { ...object, transform };
      app.history.push({ frame: addEdits(placed), label: `load ${id}`, select: { redo: id, undo: null } });
      app.updateUndoButtons();
      app.renderPanel.schedule();
    })();
    editor.running.add(task);
    try {
      await task;
    } catch (error) {
      app.fail(error);
    } finally {
      editor.running.delete(task);
    }
  });
}
