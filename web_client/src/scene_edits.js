// The page's edits on their way to the server and back: moves and light edits coalesced into
// frames at the server's pace (edit_coalescer.js), each answered frame's mesh followed, refused
// frames put back, structural frames (the object list changes) and the moves undo and the
// inspector ask for. It is also the target the undo history's commands act on (commands.js):
// moveTo, structural, isovalueTo.
import { EditCoalescer } from './edit_coalescer.js';
import { setLightEdit } from './light_shape.js';
import { applyTransform } from './scene_transform.js';

const isLight = (id) => !!id && id.startsWith('light:');

export class SceneEdits {
  // page: {api, state: SceneState, hub, history, objects, view, meshSync, dragLimit, banner, fail,
  //   reloadObjects(selectId) → promise, dragging() → bool, isovalueTo(id, value)}.
  constructor(page) {
    this.page = page;
    this.coalescer = new EditCoalescer((frame) => this.sendFrame(frame), { onError: (error, frame) => this.editFailed(error, frame) });
    this.ownVersions = new Set(); // versions this page made
    this.meshFollows = new Set(); // edits answered whose version's mesh the page does not hold yet
    this.running = new Set(); // structural changes under way
    this.announced = 0; // the newest version the event stream announced
  }

  // One frame: the edit, at the server's pace. Once it is answered the coalescer may send the
  // next edit while this one's mesh delta is fetched (MeshSync fetches one at a time and folds the
  // requests made meanwhile into its next fetch), so edits run at the rate of the slower of the two.
  async sendFrame(frame) {
    const { api, state, dragLimit, banner } = this.page;
    const start = performance.now();
    // A light edit's `pose` is the page's (DragLimit), not the server's.
    const result = await api.postEdits(state.id, { edits: frame.edits.map(({ pose, ...edit }) => edit) });
    const answered = performance.now();
    this.made(result.version);
    dragLimit.applied(frame.edits);
    banner.clearTransient();
    const follow = this.followMesh(result, start, answered);
    this.meshFollows.add(follow);
    follow.finally(() => this.meshFollows.delete(follow));
  }

  // A version this page made (an edit's, an upload's): the scene's known version from now on.
  made(version) {
    this.ownVersions.add(version);
    this.page.state.version = version;
    this.page.history.save(version); // the undo steps now lead to this version
  }

  // Waits until the page holds the edit's version; the round trip is edit sent → that mesh applied.
  async followMesh(result, start, answered) {
    const { meshSync, hub } = this.page;
    try {
      const fetched = await meshSync.refresh(Math.max(result.version, this.announced));
      const end = performance.now();
      hub.emit('edited', { result, roundTrip: (end - start) / 1000, bytes: fetched.bytes,
        phases: { edit: (answered - start) / 1000, mesh: (end - answered) / 1000 } });
      // The server's image waits for the drag's end: it would compete with the edits for the server.
      if (!this.page.dragging()) hub.emit('imageStale');
    } catch (error) {
      this.page.fail(error);
    }
  }

  // A refused frame leaves the server as it was: show why (once, until an edit succeeds), and put
  // the stand-ins back: a dragged object to its last accepted place, where it is held (DragLimit).
  async editFailed(error, frame) {
    const { api, state, hub, objects, view, dragLimit, banner } = this.page;
    const refused = error.status === 422;
    banner.show(error, { transient: refused, key: refused ? `${error.code}:${error.path}` : null,
      also: refused ? 'It stays at its last accepted place.' : '' });
    const held = refused && frame ? dragLimit.refused(frame.edits) : null;
    if (held) {
      this.coalescer.discard(held);
      const holder = objects.holderOf(held);
      if (holder && dragLimit.lastGood(held)) applyTransform(holder, dragLimit.lastGood(held));
      view.requestRender();
      return;
    }
    try {
      const wrapped = await api.getScene(state.id);
      state.adopt(wrapped);
      objects.syncTransforms(wrapped.scene, null);
      objects.syncLights(wrapped.scene, null);
      hub.emit('synced', wrapped.scene);
    } catch (again) {
      this.page.fail(again);
    }
  }

  // One structural frame (after the moves pending); on success the stand-ins are reloaded and
  // `selectId` selected.
  structural(edits, selectId) {
    const task = (async () => {
      await this.coalescer.idle();
      await this.sendFrame({ edits });
      await this.page.reloadObjects(selectId);
    })();
    return this.track(task);
  }

  // Counts `task` as work under way (the page is busy) until it ends.
  track(task) {
    this.running.add(task);
    const forget = () => this.running.delete(task);
    task.then(forget, forget);
    return task;
  }

  // Takes an object to a transform, or "light:ID" to {polygon, radiance}: the stand-in at once,
  // the server by the coalescer.
  moveTo(id, transform) {
    if (isLight(id)) return this.lightTo(id.slice(6), transform);
    const holder = this.page.objects.byId.get(id);
    if (!holder) return;
    applyTransform(holder, transform);
    this.coalescer.move(id, transform);
    this.page.hub.emit('moved', id, transform);
  }

  // A light to {polygon, radiance}: its stand-in at once, the server by one set_light naming
  // only what changed (a new radiance alone is the engine's cheap path).
  lightTo(lightId, light) {
    const { objects, hub, view } = this.page;
    const from = objects.lightJson.get(lightId);
    if (!from) return;
    const edit = setLightEdit(lightId, from, light);
    if (!edit.polygon && !edit.radiance) return;
    objects.setLight(lightId, light);
    const { op, id, ...fields } = edit;
    this.coalescer.setLight(lightId, fields);
    hub.emit('moved', `light:${lightId}`, light);
    view.requestRender();
  }

  isovalueTo(id, isovalue) {
    this.page.isovalueTo(id, isovalue);
  }

  busy() {
    return this.coalescer.busy() || this.meshFollows.size > 0 || this.running.size > 0;
  }

  // Resolves once no edit is pending or in flight and every answered one's mesh is held.
  async idle() {
    await this.coalescer.idle();
    await Promise.all([...this.meshFollows]);
    await Promise.allSettled([...this.running]);
  }
}
