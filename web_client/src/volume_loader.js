// "Load a volume": a .nrrd file picked in the panel is uploaded to the served scene
// (POST /api/scenes/ID/volumes, the file as the body: one frame, one version, journaled), placed
// at the view's centre on the floor, selected, and recorded for undo (undo removes it; redo adds
// it back by add_volume naming the file the server kept).
import * as THREE from 'three';
import { FrameCommand } from './commands.js';
import { addEdits } from './object_edits.js';
import { floorSpot } from './placement.js';

// The new volume's place: its grid box on the floor, in view, where no other object is (placement.js).
function placement(objects, view, info) {
  const box = new THREE.Box3();
  for (let c = 0; c < 8; ++c) {
    const p = new THREE.Vector3();
    info.axes.forEach((axis, k) => { if (c & (1 << k)) p.add(new THREE.Vector3(...axis)); });
    box.expandByPoint(p);
  }
  const centre = box.getCenter(new THREE.Vector3());
  if (objects.bounds.isEmpty()) return [-centre.x, 1e-3 - box.min.y, -centre.z];
  const spot = floorSpot(objects, view, box.getSize(new THREE.Vector3()));
  return [spot[0] - centre.x, spot[1] - centre.y, spot[2] - centre.z];
}

// page: {api, state, hub, history, edits: SceneEdits, objects, view, reloadObjects(selectId), fail}.
export function installVolumeLoader(input, { api, state, hub, history, edits, objects, view, reloadObjects, fail }) {
  input.addEventListener('change', async () => {
    const file = input.files && input.files[0];
    input.value = '';
    if (!file) return;
    const task = edits.track((async () => {
      await edits.coalescer.idle();
      const path = `${api.scenePath(state.id)}/volumes?name=${encodeURIComponent(file.name)}`;
      const response = await api.request('POST', path, { body: file, headers: { 'Content-Type': 'application/octet-stream' } });
      const result = await response.json();
      const { id } = result.volume;
      edits.made(result.version);
      await reloadObjects(id);
      // Centred in view: one move, part of the same undoable step.
      const object = state.json.objects.find((o) => o.id === id);
      const transform = { translate: placement(objects, view, result.volume), rotate_deg: [0, 0, 0], scale: [1, 1, 1] };
      edits.moveTo(id, transform);
      await edits.coalescer.idle();
      const placed = { ...object, transform };
      history.record(new FrameCommand(addEdits(placed), `load ${id}`, { redo: id, undo: null }));
      hub.emit('imageStale');
    })());
    try {
      await task;
    } catch (error) {
      fail(error);
    }
  });
}
