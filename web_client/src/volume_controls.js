// The page's volumes: their surface previews, the panel's note that the DM mesh has no volume
// occluders, the isovalue rows in a selected volume's inspector, and isovalue changes (the
// inspector's, undo's, other clients') sent as coalesced set_volume edits. It follows the hub:
// the stand-ins built (previews), the selection (rows), the server's isovalues taken in.
import { IsovalueCommand } from './commands.js';
import { appendVolumeRows } from './volume_inspector.js';
import { VolumePreviews } from './volume_previews.js';

export class VolumeControls {
  // page: {api, hub, objects, view, inspector, history, edits: SceneEdits, fail}; note: the panel's note.
  constructor({ api, hub, objects, view, inspector, history, edits, fail }, sceneId, note) {
    Object.assign(this, { objects, inspector, history, edits, note });
    this.rows = null; // the selected volume's isovalue rows
    this.previews = new VolumePreviews(api, sceneId, (id) => (objects.isVolume(id) ? objects.byId.get(id) : null),
      () => view.requestRender(), (error) => fail(error));
    hub.on('standIns', () => this.show());
    hub.on('selection', (id) => this.inspect(id));
    hub.on('synced', (scene) => this.sync(scene));
  }

  // After the stand-ins were built: each volume's preview; the note whenever the scene has a volume.
  show() {
    const volumes = this.objects.volumes();
    for (const [id] of volumes) this.previews.request(id, this.objects.json.get(id).isovalue);
    this.note.hidden = volumes.length === 0;
  }

  // The inspector now shows `id`: adds the isovalue rows when it is a volume.
  inspect(id) {
    const { objects } = this;
    this.rows = null;
    if (!id || !objects.isVolume(id)) return;
    const info = objects.byId.get(id).userData.info;
    this.rows = appendVolumeRows(this.inspector.root, info, objects.json.get(id).isovalue, {
      onInput: (value) => this.isovalueTo(id, value, true),
      onCommit: (before, after) => this.history.record(new IsovalueCommand(id, before, after)),
    });
  }

  // Takes a volume to a new isovalue: its preview at once, the server by a coalesced set_volume.
  // `typed`: from the inspector's own fields (they already show it, mid-gesture).
  isovalueTo(id, isovalue, typed = false) {
    const { objects } = this;
    const object = objects.json.get(id);
    if (!object || !objects.isVolume(id)) return;
    objects.json.set(id, { ...object, isovalue });
    this.previews.request(id, isovalue);
    this.edits.coalescer.setVolume(id, isovalue);
    if (!typed && this.inspector.id === id && this.rows) this.rows.update(isovalue);
  }

  // Volumes' isovalues from the server's scene (another client's edits, a refused frame).
  sync(scene) {
    const { objects } = this;
    for (const object of scene.objects) {
      if (object.type !== 'volume' || !objects.isVolume(object.id)) continue;
      if (objects.byId.get(object.id).userData.previewIsovalue === object.isovalue) continue;
      this.previews.request(object.id, object.isovalue);
      if (this.inspector.id === object.id && this.rows) this.rows.update(object.isovalue);
    }
  }

  busy() {
    return this.previews.busy();
  }

  idle() {
    return this.previews.idle();
  }
}
