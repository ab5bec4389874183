// The page's volumes (issue 15): their surface previews, the panel's note that the DM mesh has no
// volume occluders, the isovalue rows in a selected volume's inspector, and isovalue changes (the
// inspector's, undo's, other clients') sent as coalesced set_volume edits.
import { appendVolumeRows } from './volume_inspector.js';
import { VolumePreviews } from './volume_previews.js';

export class VolumeControls {
  // app: the page (objects, coalescer, inspector, history, view, sceneJson); note: the panel's note.
  constructor(app, sceneId, note) {
    this.app = app;
    this.note = note;
    this.rows = null; // the selected volume's isovalue rows
    this.previews = new VolumePreviews(app.api, sceneId, (id) => (app.objects.isVolume(id) ? app.objects.byId.get(id) : null),
      () => app.view.requestRender(), (error) => app.fail(error));
  }

  // After the stand-ins were built: each volume's preview; the note whenever the scene has a volume.
  show() {
    const volumes = this.app.objects.volumes();
    for (const [id] of volumes) this.previews.request(id, this.app.objects.json.get(id).isovalue);
    this.note.hidden = volumes.length === 0;
  }

  // The inspector now shows `id`: adds the isovalue rows when it is a volume.
  inspect(id) {
    const { app } = this;
    this.rows = null;
    if (!id || !app.objects.isVolume(id)) return;
    const info = app.objects.byId.get(id).userData.info;
    this.rows = appendVolumeRows(app.inspector.root, info, app.objects.json.get(id).isovalue, {
      onInput: (value) => this.isovalueTo(id, value, true),
      onCommit: (before, after) => {
        app.history.push({ id, isovalue: { before, after } });
        app.updateUndoButtons();
      },
    });
  }

  // Takes a volume to a new isovalue: its preview at once, the server by a coalesced set_volume.
  // `typed`: from the inspector's own fields (they already show it, mid-gesture).
  isovalueTo(id, isovalue, typed = false) {
    const { objects } = this.app;
    const object = objects.json.get(id);
    if (!object || !objects.isVolume(id)) return;
    objects.json.set(id, { ...object, isovalue });
    this.previews.request(id, isovalue);
    this.app.coalescer.setVolume(id, isovalue);
    if (!typed && this.app.inspector.id === id && this.rows) this.rows.update(isovalue);
  }

  // Volumes' isovalues from the server's scene (another client's edits, a refused frame).
  sync(scene) {
    const { objects } = this.app;
    for (const object of scene.objects) {
      if (object.type !== 'volume' || !objects.isVolume(object.id)) continue;
      if (objects.byId.get(object.id).userData.previewIsovalue === object.isovalue) continue;
      this.previews.request(object.id, object.isovalue);
      if (this.app.inspector.id === object.id && this.rows) this.rows.update(object.isovalue);
    }
  }

  busy() {
    return this.previews.busy();
  }

  idle() {
    return this.previews.idle();
  }
}
