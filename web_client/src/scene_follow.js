// The page following the server's scene: versions the event stream announces (another client's
// edits: their mesh, then their transforms, or the stand-ins again when the object list changed),
// the scene and whole mesh again once the server is back after a break, and the stand-ins rebuilt
// after a structural change of this page's.
import { receiverKey } from './mesh_binary.js';

const isLight = (id) => !!id && id.startsWith('light:');
// What the objects' looks come from: the materials and which object uses which.
const looksOf = (scene) => JSON.stringify([scene.materials || {}, (scene.objects || []).map((o) => o.material || '')]);

export class SceneFollow {
  // page: {api, state, hub, history, edits, objects, receivers, view, banner, fail, and once the
  //   scene is loaded: meshSync, toneMap, look, gizmo} (read when used).
  constructor(page) {
    this.page = page;
    this.resyncing = null; // the resync under way
    this.looksStale = false; // another client changed materials while a drag of ours was on
  }

  // The event stream's state changed: a stream back after a break resyncs.
  connection(now, previous) {
    if (now === 'connected' && (previous === 'reconnecting' || previous === 'refused')) {
      this.resyncing = this.resync().finally(() => { this.resyncing = null; });
    }
  }

  async versionAnnounced(version) {
    const { api, state, hub, edits, objects, meshSync, toneMap, look, gizmo, view } = this.page;
    edits.announced = Math.max(edits.announced, version);
    try {
      // While a frame of ours is in flight, its own refresh fetches up to `announced`; our own
      // versions are fetched by the frames that made them.
      if (meshSync.version === null || version <= meshSync.version || edits.coalescer.busy()
          || edits.ownVersions.has(version)) return;
      await meshSync.refresh(version);
      hub.emit('imageStale');
      if (edits.ownVersions.has(version) || edits.coalescer.busy()) return;
      // Another client's edit: follow its transforms (a changed object list reloads the page's stand-ins).
      const wrapped = await api.getScene(state.id);
      const looksBefore = state.json ? looksOf(state.json) : null;
      state.adopt(wrapped);
      toneMap.learnObjects(wrapped.scene);
      if (objects.sameObjects(wrapped.scene)) {
        const dragged = gizmo.dragging ? gizmo.selected : null;
        objects.syncTransforms(wrapped.scene, dragged);
        objects.syncLights(wrapped.scene, dragged && isLight(dragged) ? dragged.slice(6) : null);
        look.afterMesh(); // another client's new light power: the exposure follows
        // Another client's material edit: the mesh's colours and the glossy layer (metal, glass)
        // follow, as after one of ours. Not in the middle of a drag of ours (the stand-ins are
        // rebuilt): then at the next version of another client's the page follows.
        this.looksStale = this.looksStale || looksOf(wrapped.scene) !== looksBefore;
        if (this.looksStale && !gizmo.dragging) this.restyle(wrapped.scene);
        hub.emit('synced', wrapped.scene);
      } else {
        gizmo.select(null);
        this.buildStandIns(wrapped.scene);
      }
      view.requestRender(); // the stand-ins and lights moved after the mesh was drawn
    } catch (error) {
      this.page.fail(error);
    }
  }

  // The stand-ins again from the server's scene (its object list changed), selecting `selectId`.
  async reloadObjects(selectId) {
    const { api, state, toneMap, receivers, gizmo, view } = this.page;
    const wrapped = await api.getScene(state.id);
    state.adopt(wrapped);
    gizmo.select(null);
    toneMap.learnObjects(wrapped.scene);
    receivers.recolourAll(toneMap); // a material's new colour changes no irradiance
    this.buildStandIns(wrapped.scene);
    if (selectId) gizmo.select(selectId);
    view.requestRender();
  }

  // The objects' looks again from `scene` (its materials changed), keeping the selection.
  restyle(scene) {
    const { receivers, toneMap, gizmo } = this.page;
    this.looksStale = false;
    receivers.recolourAll(toneMap); // a material's new colour changes no irradiance
    const selected = gizmo.selected;
    gizmo.select(null);
    this.buildStandIns(scene); // the glossy layer follows the stand-ins
    if (selected) gizmo.select(selected);
  }

  // The objects' stand-ins, each face in its lit mesh's mean colour (ambient where none is held).
  buildStandIns(scene) {
    const { objects, receivers, toneMap, hub } = this.page;
    const means = receivers.meanColours();
    objects.build(scene, (id) => toneMap.ambientColour(id), (id, face) => means.get(receiverKey(id, face)) || null);
    hub.emit('standIns', scene);
  }

  // After the server came back: the scene and its whole mesh again (it may have restarted, and
  // without a journal be back at version 0).
  async resync() {
    const { api, state, hub, history, edits, meshSync, gizmo, banner, view } = this.page;
    try {
      const wrapped = await api.getScene(state.id);
      // The undo steps lead to the version held; a server at another one (restarted without a
      // journal, or edited meanwhile) has a scene they do not describe.
      if (wrapped.version !== meshSync.version) {
        state.version = wrapped.version;
        history.clear();
      }
      gizmo.select(null);
      state.adopt(wrapped);
      this.buildStandIns(wrapped.scene);
      edits.ownVersions.clear();
      await meshSync.reload();
      banner.serverBack();
      edits.announced = meshSync.version;
      hub.emit('imageStale');
      view.requestRender();
    } catch (error) {
      this.page.fail(error);
    }
  }
}
