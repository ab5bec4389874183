// The page's wiring: picks the scene (?scene=ID, else the first served), loads it and its mesh
// (behind the loading overlay), and connects the view, selection gizmo, edit coalescer, drag
// limit, undo history, editor commands, inspector, volumes (volume_controls.js), outliner, server
// render, timings and plot, events, connection bar and error banner. Each concept lives in its own module beside this one.
import { ApiClient } from './api_client.js';
import { ConnectionStatus } from './connection_status.js';
import { DragLimit } from './drag_limit.js';
import { EditPlot } from './edit_plot.js';
import { setLightEdit } from './light_shape.js';
import { EditorActions } from './editor_actions.js';
import { Inspector } from './inspector.js';
import { Outliner } from './outliner.js';
import { hasPhysicalMaterials } from './physical_materials.js';
import { installPanelControls } from './panel_controls.js';
import { ErrorBanner } from './error_banner.js';
import { EditCoalescer } from './edit_coalescer.js';
import { EventSync } from './event_sync.js';
import { GlossyLayer } from './glossy_layer.js';
import { LoadingIndicator } from './loading_indicator.js';
import { MeshSync } from './mesh_sync.js';
import { receiverKey } from './mesh_binary.js';
import { ReceiverLayer } from './receiver_layer.js';
import { RenderPanel } from './render_panel.js';
import { BakedIndirect } from './baked_indirect.js';
import { SceneObjects } from './scene_objects.js';
import { showImportReport } from './import_report_panel.js';
import { installSceneFileLoader } from './scene_file_loader.js';
import { applyTransform, sameTransform, transformOf } from './scene_transform.js';
import { SceneView } from './scene_view.js';
import { SelectionGizmo } from './selection_gizmo.js';
import { installTestHook } from './test_hook.js';
import { TimingsPanel } from './timings_panel.js';
import { ToneMap } from './tone_map.js';
import { UndoHistory } from './undo_history.js';
import { ViewLook } from './view_look.js';
import { VolumeControls } from './volume_controls.js';
import { installVolumeLoader } from './volume_loader.js';

const $ = (id) => document.getElementById(id);
const isLight = (id) => !!id && id.startsWith('light:');
const MOTION_HOLD_MS = 100;

class App {
  constructor() {
    this.api = new ApiClient('', new URLSearchParams(window.location.search).get('token'));
    this.banner = new ErrorBanner($('error-banner'), $('error-text'), $('error-close'));
    this.loading = new LoadingIndicator($('loading'), $('loading-text'), $('loading-progress'), $('controls'), $('loading-cancel'));
    // ?antialias=on|off and ?drag_scale=0.25..1 override the choices by GL renderer (to compare frame times).
    const query = new URLSearchParams(window.location.search);
    const antialias = query.get('antialias');
    this.view = new SceneView($('viewport'), { antialias: ['on', 'off'].includes(antialias) ? antialias : 'auto',
      dragScale: query.get('drag_scale') || 'auto' });
    this.objects = new SceneObjects(this.view.scene);
    this.receivers = new ReceiverLayer(this.view.scene);
    // Microfacet materials' glossy part over the DM colours, rebuilt with the stand-ins.
    this.glossy = new GlossyLayer(this.objects, this.receivers);
    this.objects.onBuilt = (scene) => this.glossy.build(scene).then(() => this.view.requestRender(), (e) => this.fail(e));
    this.objects.onLight = (id, light) => this.glossy.setLight(id, light);
    // keys: the receivers whose parts changed (null: all, after a whole mesh).
    this.receivers.onColours = (keys) => {
      if (!keys) {
        const means = this.receivers.meanColours();
        this.objects.recolour((id) => this.toneMap.ambientColour(id), (id, face) => means.get(receiverKey(id, face)) || null);
        return;
      }
      for (const key of keys) {
        const [object, face] = key.split('/');
        this.objects.setFaceColour(object, Number(face), this.receivers.meanColour(key));
      }
    };
    this.timings = new TimingsPanel($('timings'));
    this.timings.gl = this.view.gl;
    this.timings.draw();
    this.plot = new EditPlot($('edit-plot'), $('edit-ratio'));
    this.connection = new ConnectionStatus($('connection'));
    this.dragLimit = new DragLimit();
    this.history = new UndoHistory();
    this.editor = new EditorActions(this);
    this.inspector = new Inspector($('inspector'), (id, transform) => this.editor.typedTransform(id, transform),
      (lightId, light) => this.editor.typedLight(lightId, light), {
        onRename: (id, name) => this.editor.rename(id, name),
        onMaterial: (id, material) => this.editor.setMaterial(id, material),
        materials: () => Object.entries((this.sceneJson && this.sceneJson.materials) || {}),
        materialOf: (id) => (this.objects.json.get(id) || {}).material,
        onPaint: (id, change) => this.editor.paint(id, change),
        paintable: (id) => { const o = this.objects.json.get(id); return !!o && o.type !== 'volume'; },
      });
    this.outliner = new Outliner($('outliner'), (id) => this.gizmo && this.gizmo.select(id));
    this.ownVersions = new Set();
    this.dragStart = null;
    this.meshFollows = new Set(); // edits answered whose version's mesh the page does not hold yet
    this.announced = 0; // the newest version the event stream announced
    // While a drag's edit is on its way on a software GL, a moved stand-in's frame waits (up to
    // MOTION_HOLD_MS) for that edit's shadows, so the two are drawn together in one frame.
    this.view.motionHold = () => (this.view.gl.software && this.view.interactions.has('drag') && this.busy() ? MOTION_HOLD_MS : 0);
    this.fail = (error) => this.banner.show(error);
    installSceneFileLoader($('scene-file'), this.api, this.fail, { scale: $('import-scale'), radiance: $('import-radiance') }, this.loading);
  }

  async start() {
    performance.mark('penumbra:start');
    const requested = new URLSearchParams(window.location.search).get('scene');
    let sceneId = requested;
    this.loading.step('Loading the scene…');
    if (!sceneId) {
      const scenes = (await this.api.listScenes()).scenes.filter((s) => s.state !== 'building');
      if (!scenes.length) throw new Error('the server serves no scene: load a .scene.json file');
      sceneId = scenes[0].id;
    }
    this.sceneId = sceneId;
    // prefetch.js asked for the scene and its mesh while the modules loaded.
    const prefetch = window.penumbraPrefetch && window.penumbraPrefetch.sceneId === sceneId ? window.penumbraPrefetch : null;
    const meshResponse = prefetch ? this.api.adopt(prefetch.mesh, 'GET mesh')
      : this.api.request('GET', `${this.api.scenePath(sceneId)}/mesh?format=bin`);
    meshResponse.catch(() => {}); // reported when awaited below
    const wrapped = prefetch ? await (await this.api.adopt(prefetch.scene, 'GET scene')).json() : await this.api.getScene(sceneId);
    performance.mark('penumbra:scene');
    $('scene-name').textContent = `${wrapped.id} (${wrapped.name})`;
    showImportReport($('import-report'), sceneId, wrapped.name);
    this.adopt(wrapped);
    this.sceneName = wrapped.name;
    this.editor.remember(wrapped);
    this.knownVersion = wrapped.version;
    this.history.restore(`${wrapped.id}.${wrapped.name}`, wrapped.version);

    this.volumes = new VolumeControls(this, sceneId, $('volume-note'));
    this.objects.build(wrapped.scene);
    this.volumes.show();
    this.toneMap = new ToneMap(wrapped.scene, this.objects.bounds);
    this.look = new ViewLook(this, sceneId, wrapped.name);
    this.view.setCamera(wrapped.scene.camera, this.objects.bounds, this.objects);

    this.meshSync = new MeshSync(this.api, sceneId, (decoded) => {
      // The exposure is taken from the first whole mesh (or kept), before its colours are made.
      this.look.beforeMesh(decoded);
      this.glossy.setExposure(this.toneMap.exposure);
      this.receivers.apply(decoded, this.toneMap);
      this.look.afterMesh();
      if (this.bakedIndirect) this.bakedIndirect.schedule(); // a new version: bake it once edits pause
      $('version').textContent = String(decoded.sceneVersion);
      this.view.requestRender();
    });
    await this.meshSync.loadWhole(async () => ApiClient.bytesWithProgress(await meshResponse,
      (loaded, total) => this.loading.bytes('Downloading the lit mesh', loaded, total)));
    performance.mark('penumbra:mesh');
    this.loading.step('Drawing…');
    this.outliner.render(this.objects, null);

    this.coalescer = new EditCoalescer((frame) => this.sendFrame(frame), { onError: (error, frame) => this.editFailed(error, frame) });
    this.gizmo = new SelectionGizmo(this.view, this.objects, {
      onSelect: (id) => this.selected(id),
      onDragStart: (id) => {
        this.dragStart = { id, before: this.stateOf(id) };
        this.dragLimit.start(id, transformOf(this.gizmo.holder()));
        this.view.setInteracting('drag', true);
      },
      onChange: (id) => {
        const transform = transformOf(this.gizmo.holder());
        // A light scaled to nothing or mirrored (it would face the other way) is held too.
        const flat = isLight(id) && !transform.scale.every((x) => x > 1e-3);
        if (!this.dragLimit.allows(id, transform) || flat) applyTransform(this.gizmo.holder(), this.dragLimit.lastGood(id)); // held at the last good place
        else if (isLight(id)) this.coalescer.setLight(id.slice(6), { polygon: this.objects.lightPolygon(id.slice(6)) }, transform);
        else this.coalescer.move(id, transform);
        this.followDrag(id);
      },
      onDragEnd: (id) => this.dragEnded(id),
      onMode: (mode) => this.showMode(mode),
    });
    this.showMode('translate');
    this.renderPanel = new RenderPanel(this.api, sceneId, this.view, $('render'), $('render-info'), $('render-progress'), this.fail,
      () => hasPhysicalMaterials(this.sceneJson));
    this.view.onCameraChange(() => this.renderPanel.schedule());
    this.bakedIndirect = new BakedIndirect(this.api, sceneId, (indirect) => {
      this.receivers.setIndirect(indirect, this.toneMap);
      const { version, seconds } = this.bakedIndirect;
      $('indirect-info').textContent = indirect ? `v${version} baked in ${(seconds * 1000).toFixed(0)} ms` : '';
      this.view.requestRender();
    }, this.fail);
    this.events = new EventSync(this.api.eventsUrl(sceneId), {
      onVersion: (version) => this.versionAnnounced(version),
      onError: this.fail,
      onConnection: (state, previous) => {
        this.connection.set(state);
        if (state === 'connected' && (previous === 'reconnecting' || previous === 'refused')) {
          this.resyncing = this.resync().finally(() => { this.resyncing = null; });
        }
      },
    });
    this.installControls();
    installVolumeLoader($('volume-file'), this, this.editor);
    this.editor.updateReset();
    this.editor.refreshScenes();
    this.selected(null);
    this.api.stats(sceneId).then((stats) => {
      this.timings.initialBuild = stats.build && stats.build.seconds ? stats.build.seconds.total : null;
      this.timings.draw();
      if (!this.timings.rebuild) this.plot.setBuild(this.timings.initialBuild, 'at load', false);
    }).catch(this.fail);

    this.renderPanel.schedule();
    this.view.requestRender();
    performance.mark('penumbra:ready');
    this.loading.done();
  }

  installControls() {
    installPanelControls(this, this.editor);
    this.updateUndoButtons();
  }

  showMode(mode) {
    for (const m of ['translate', 'rotate', 'scale']) $(`mode-${m}`).classList.toggle('active', mode === m);
  }

  // One frame: the edit, at the server's pace. Once it is answered the coalescer may send the
  // next edit while this one's mesh delta is fetched (MeshSync fetches one at a time and folds the
  // requests made meanwhile into its next fetch), so edits run at the rate of the slower of the two.
  async sendFrame(frame) {
    const start = performance.now();
    // A light edit's `pose` is the page's (DragLimit), not the server's.
    const result = await this.api.postEdits(this.sceneId, { edits: frame.edits.map(({ pose, ...edit }) => edit) });
    const answered = performance.now();
    this.ownVersions.add(result.version);
    this.knownVersion = result.version;
    this.history.save(result.version);
    this.dragLimit.applied(frame.edits);
    this.banner.clearTransient();
    const follow = this.followMesh(result, start, answered);
    this.meshFollows.add(follow);
    follow.finally(() => this.meshFollows.delete(follow));
  }

  // Waits until the page holds the edit's version; the round trip is edit sent → that mesh applied.
  async followMesh(result, start, answered) {
    try {
      const fetched = await this.meshSync.refresh(Math.max(result.version, this.announced));
      const end = performance.now();
      this.timings.edited(result, (end - start) / 1000, fetched.bytes, { edit: (answered - start) / 1000, mesh: (end - answered) / 1000 });
      this.plot.add(result.seconds ? result.seconds.total : 0, result.mesh_seconds || 0, (end - start) / 1000);
      // The server's image waits for the drag's end: it would compete with the edits for the server.
      if (!this.gizmo.dragging) this.renderPanel.schedule();
    } catch (error) {
      this.fail(error);
    }
  }

  // A refused frame leaves the server as it was: show why (once, until an edit succeeds), and put
  // the stand-ins back: a dragged object to its last accepted place, where it is held (DragLimit).
  async editFailed(error, frame) {
    const refused = error.status === 422;
    this.banner.show(error, { transient: refused, key: refused ? `${error.code}:${error.path}` : null,
      also: refused ? 'It stays at its last accepted place.' : '' });
    const held = refused && frame ? this.dragLimit.refused(frame.edits) : null;
    if (held) {
      this.coalescer.discard(held);
      const holder = this.objects.holderOf(held);
      if (holder && this.dragLimit.lastGood(held)) applyTransform(holder, this.dragLimit.lastGood(held));
      this.view.requestRender();
      return;
    }
    try {
      const wrapped = await this.api.getScene(this.sceneId);
      this.adopt(wrapped);
      this.objects.syncTransforms(wrapped.scene, null);
      this.objects.syncLights(wrapped.scene, null);
      this.volumes.sync(wrapped.scene);
      this.refreshInspector();
    } catch (again) {
      this.fail(again);
    }
  }

  dragEnded(id) {
    this.dragLimit.end();
    this.view.setInteracting('drag', false);
    this.renderPanel.schedule();
    const start = this.dragStart;
    this.dragStart = null;
    if (!start || start.id !== id) return;
    if (isLight(id)) {
      // The light's holder back at the new polygon's centre, unturned (the next drag starts there).
      const after = { polygon: this.objects.lightPolygon(id.slice(6)), radiance: start.before.radiance };
      this.objects.setLight(id.slice(6), after);
      if (!sameTransform(start.before, after)) this.history.push({ id, before: start.before, after });
    } else {
      const after = transformOf(this.gizmo.holder());
      if (!sameTransform(start.before, after)) this.history.push({ id, before: start.before, after });
    }
    this.updateUndoButtons();
    this.refreshInspector();
  }

  // What undo restores of a selection: an object's transform, a light's {polygon, radiance}.
  stateOf(id) {
    if (!isLight(id)) return transformOf(this.objects.byId.get(id));
    const light = this.objects.lightJson.get(id.slice(6));
    return { polygon: light.polygon, radiance: light.radiance };
  }

  // The inspector's fields follow a drag as it goes (the dragged holder, not yet the server's scene).
  followDrag(id) {
    if (this.inspector.id !== id) return;
    if (isLight(id)) this.inspector.update({ ...this.objects.lightJson.get(id.slice(6)), polygon: this.objects.lightPolygon(id.slice(6)) });
    else this.inspector.update(transformOf(this.gizmo.holder()));
  }

  refreshInspector() {
    const id = this.inspector.id;
    if (id && isLight(id)) this.inspector.update(this.objects.lightJson.get(id.slice(6)));
    else if (id && this.objects.byId.get(id)) this.inspector.update(transformOf(this.objects.byId.get(id)));
  }

  // Takes a light to {polygon, radiance}: its stand-in at once, the server by one set_light naming
  // only what changed (a new radiance alone is the engine's cheap path).
  lightTo(lightId, light) {
    const from = this.objects.lightJson.get(lightId);
    if (!from) return;
    const edit = setLightEdit(lightId, from, light);
    if (!edit.polygon && !edit.radiance) return;
    this.objects.setLight(lightId, light);
    const { op, id, ...fields } = edit;
    this.coalescer.setLight(lightId, fields);
    this.refreshInspector();
    this.view.requestRender();
  }

  moveTo(id, transform) {
    if (isLight(id)) return this.lightTo(id.slice(6), transform);
    const holder = this.objects.byId.get(id);
    if (!holder) return;
    applyTransform(holder, transform);
    this.coalescer.move(id, transform);
    if (this.inspector.id === id) this.inspector.update(transform);
  }

  // A move entry re-sends a transform; a structural one ({frame: {redo, undo}}) its frame.
  undo() {
    if (this.gizmo.dragging) return;
    const entry = this.history.undo();
    if (entry && entry.frame) this.editor.sendStructural(entry.frame.undo, entry.select.undo).catch(this.fail);
    else if (entry && entry.isovalue) this.volumes.isovalueTo(entry.id, entry.isovalue.before);
    else if (entry) this.moveTo(entry.id, entry.before);
    this.updateUndoButtons();
  }

  redo() {
    if (this.gizmo.dragging) return;
    const entry = this.history.redo();
    if (entry && entry.frame) this.editor.sendStructural(entry.frame.redo, entry.select.redo).catch(this.fail);
    else if (entry && entry.isovalue) this.volumes.isovalueTo(entry.id, entry.isovalue.after);
    else if (entry) this.moveTo(entry.id, entry.after);
    this.updateUndoButtons();
  }

  selected(id) {
    $('selection').textContent = id ? `selected ${id}` : 'click an object';
    this.outliner.highlight(id);
    const light = id && isLight(id) ? this.objects.lightJson.get(id.slice(6)) : null;
    this.inspector.show(id, light || (id ? transformOf(this.objects.byId.get(id)) : null));
    this.volumes.inspect(id);
    for (const button of ['duplicate', 'delete', 'focus']) $(button).disabled = !id;
    // A scene keeps at least one light.
    const lastLight = !!light && !this.editor.canDeleteLight();
    $('delete').disabled ||= lastLight;
    $('delete').title = lastLight ? 'The scene\'s last light cannot be deleted' : 'Delete the selection (Delete)';
    $('duplicate').title = light ? 'Add a copy of this light beside it (Ctrl+D)' : 'Duplicate the selection (Ctrl+D)';
  }

  // The stand-ins again from the server's scene (its object list changed), selecting `selectId`.
  async reloadObjects(selectId) {
    const wrapped = await this.api.getScene(this.sceneId);
    this.adopt(wrapped);
    this.gizmo.select(null);
    this.toneMap.learnObjects(wrapped.scene);
    this.receivers.recolourAll(this.toneMap); // a material's new colour changes no irradiance
    this.buildStandIns(wrapped.scene);
    if (selectId) this.gizmo.select(selectId);
    this.view.requestRender();
  }

  updateUndoButtons() {
    this.history.save(this.knownVersion);
    $('undo').disabled = !this.history.canUndo();
    $('redo').disabled = !this.history.canRedo();
  }

  async versionAnnounced(version) {
    this.announced = Math.max(this.announced, version);
    try {
      // While a frame of ours is in flight, its own refresh fetches up to `announced`; our own
      // versions are fetched by the frames that made them.
      if (this.meshSync.version === null || version <= this.meshSync.version || this.coalescer.busy()
          || this.ownVersions.has(version)) return;
      await this.meshSync.refresh(version);
      this.renderPanel.schedule();
      if (this.ownVersions.has(version) || this.coalescer.busy()) return;
      // Another client's edit: follow its transforms (a changed object list reloads the page's stand-ins).
      const wrapped = await this.api.getScene(this.sceneId);
      this.adopt(wrapped);
      this.toneMap.learnObjects(wrapped.scene);
      if (this.objects.sameObjects(wrapped.scene)) {
        const dragged = this.gizmo.dragging ? this.gizmo.selected : null;
        this.objects.syncTransforms(wrapped.scene, dragged);
        this.volumes.sync(wrapped.scene);
        this.objects.syncLights(wrapped.scene, dragged && isLight(dragged) ? dragged.slice(6) : null);
        this.look.afterMesh(); // another client's new light power: the exposure follows
        this.refreshInspector();
      } else {
        this.gizmo.select(null);
        this.buildStandIns(wrapped.scene);
      }
      this.view.requestRender(); // the stand-ins and lights moved after the mesh was drawn
    } catch (error) {
      this.fail(error);
    }
  }

  // The objects' stand-ins, each face in its lit mesh's mean colour (ambient where none is held).
  buildStandIns(scene) {
    const means = this.receivers.meanColours();
    this.objects.build(scene, (id) => this.toneMap.ambientColour(id), (id, face) => means.get(receiverKey(id, face)) || null);
    this.outliner.render(this.objects, this.gizmo ? this.gizmo.selected : null);
    this.volumes.show();
  }

  // The scene as the server sent it ({scene, volumes: the volumes' grid info}).
  adopt(wrapped) {
    this.sceneJson = wrapped.scene;
    this.objects.volumeInfo = new Map((wrapped.volumes || []).map((v) => [v.id, v]));
  }

  // After the server came back: the scene and its whole mesh again (it may have restarted, and
  // without a journal be back at version 0).
  async resync() {
    try {
      const wrapped = await this.api.getScene(this.sceneId);
      // The undo steps lead to the version held; a server at another one (restarted without a
      // journal, or edited meanwhile) has a scene they do not describe.
      if (wrapped.version !== this.meshSync.version) {
        this.history.clear();
        this.knownVersion = wrapped.version;
        this.updateUndoButtons();
      }
      this.gizmo.select(null);
      this.adopt(wrapped);
      this.buildStandIns(wrapped.scene);
      this.ownVersions.clear();
      await this.meshSync.reload();
      this.banner.serverBack();
      this.announced = this.meshSync.version;
      this.renderPanel.schedule();
      this.view.requestRender();
    } catch (error) {
      this.fail(error);
    }
  }

  busy() {
    return !!(this.coalescer && this.coalescer.busy()) || !!(this.meshSync && this.meshSync.running) || this.meshFollows.size > 0
      || !!this.resyncing || this.editor.running.size > 0 || !!(this.volumes && this.volumes.busy());
  }

  // Resolves once no edit is pending or in flight and the page holds (and has timed) every version it made.
  async idle() {
    while (this.busy()) {
      await this.coalescer.idle();
      if (this.meshSync.running) await this.meshSync.running;
      await Promise.all([...this.meshFollows]);
      if (this.resyncing) await this.resyncing;
      await Promise.allSettled([...this.editor.running]);
      if (this.volumes) await this.volumes.idle();
    }
  }
}

const app = new App();
const hook = installTestHook(app);
app.start().then(() => { hook.ready = true; }).catch((error) => {
  app.banner.show(error);
  app.loading.failed(`The scene did not load: ${error.message || error}`);
});
