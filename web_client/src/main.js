// The page's wiring: picks the scene (?scene=ID, else the first served), loads it and its mesh
// (behind the loading overlay), and connects the parts. Each concept lives in its own module; they
// talk through the event hub (event_hub.js: selection, scene, version, stand-ins, history, …) and
// are given `page`, the members they name, instead of this App. Undo steps are commands
// (commands.js) done against the page's edits (scene_edits.js). A panel is one module with an
// install(page) that subscribes to the hub, and one line in PANELS.
import { ApiClient } from './api_client.js';
import { installConnectionStatus } from './connection_status.js';
import { DragLimit } from './drag_limit.js';
import { installEditPlot } from './edit_plot.js';
import { EditorActions } from './editor_actions.js';
import { EventHub } from './event_hub.js';
import { installInspector } from './inspector_panel.js';
import { installOutliner } from './outliner.js';
import { hasPhysicalMaterials } from './physical_materials.js';
import { installPanelControls } from './panel_controls.js';
import { ErrorBanner } from './error_banner.js';
import { EventSync } from './event_sync.js';
import { installGizmo } from './gizmo_drag.js';
import { GlossyLayer } from './glossy_layer.js';
import { LoadingIndicator } from './loading_indicator.js';
import { installMeshBound } from './mesh_bound.js';
import { MeshSync } from './mesh_sync.js';
import { receiverKey } from './mesh_binary.js';
import { ReceiverLayer } from './receiver_layer.js';
import { RenderPanel } from './render_panel.js';
import { BakedIndirect } from './baked_indirect.js';
import { SceneEdits } from './scene_edits.js';
import { SceneFollow } from './scene_follow.js';
import { SceneObjects } from './scene_objects.js';
import { SceneState } from './scene_state.js';
import { showImportReport } from './import_report_panel.js';
import { installSceneFileLoader } from './scene_file_loader.js';
import { installSelectionPanel } from './selection_panel.js';
import { SceneView } from './scene_view.js';
import { installTestHook } from './test_hook.js';
import { installTimings } from './timings_panel.js';
import { ToneMap } from './tone_map.js';
import { UndoHistory } from './undo_history.js';
import { ViewLook } from './view_look.js';
import { VolumeControls } from './volume_controls.js';
import { installVolumeLoader } from './volume_loader.js';

const $ = (id) => document.getElementById(id);
const MOTION_HOLD_MS = 100;

// The side panel's parts: [name on page, install(page) → the part]. Installed in this order (the
// order their handlers of one event run in).
const PANELS = [
  ['selectionPanel', installSelectionPanel],
  ['outliner', installOutliner],
  ['inspector', installInspector],
  ['timings', installTimings],
  ['plot', installEditPlot],
  ['connection', installConnectionStatus],
  ['meshBound', installMeshBound],
];

class App {
  constructor() {
    const query = new URLSearchParams(window.location.search);
    this.hub = new EventHub();
    this.api = new ApiClient('', query.get('token'));
    this.state = new SceneState(this.hub);
    this.banner = new ErrorBanner($('error-banner'), $('error-text'), $('error-close'));
    this.loading = new LoadingIndicator($('loading'), $('loading-text'), $('loading-progress'), $('controls'), $('loading-cancel'));
    // ?antialias=on|off and ?drag_scale=0.25..1 override the choices by GL renderer, ?frame_cache=off
    // draws a drag's frames whole (to compare frame times).
    const antialias = query.get('antialias');
    this.view = new SceneView($('viewport'), { antialias: ['on', 'off'].includes(antialias) ? antialias : 'auto',
      dragScale: query.get('drag_scale') || 'auto', frameCache: query.get('frame_cache') !== 'off' });
    this.objects = new SceneObjects(this.view.scene);
    this.receivers = new ReceiverLayer(this.view.scene);
    // Microfacet materials' glossy part over the DM colours, rebuilt with the stand-ins.
    this.glossy = new GlossyLayer(this.objects, this.receivers);
    this.fail = (error) => this.banner.show(error);
    this.connectLayers();
    this.dragLimit = new DragLimit();
    this.history = new UndoHistory(this.hub);
    this.hub.on('history', () => this.history.save(this.state.version));
    this.hub.on('scene', (wrapped) => { this.objects.volumeInfo = new Map((wrapped.volumes || []).map((v) => [v.id, v])); });
    this.hub.on('version', (decoded) => { $('version').textContent = String(decoded.sceneVersion); });
    this.page = {
      hub: this.hub, api: this.api, state: this.state, history: this.history, banner: this.banner, loading: this.loading,
      objects: this.objects, receivers: this.receivers, glossy: this.glossy, view: this.view, dragLimit: this.dragLimit, fail: this.fail,
      selection: () => (this.gizmo ? this.gizmo.selected : null),
      select: (id) => this.gizmo && this.gizmo.select(id),
      dragging: () => !!this.gizmo && this.gizmo.dragging,
      reloadObjects: (selectId) => this.follow.reloadObjects(selectId),
      isovalueTo: (id, isovalue) => this.volumes.isovalueTo(id, isovalue),
      undo: () => this.undo(), redo: () => this.redo(),
    };
    this.part('edits', new SceneEdits(this.page));
    this.part('follow', new SceneFollow(this.page));
    this.part('editor', new EditorActions(this.page));
    for (const [name, install] of PANELS) this.part(name, install(this.page));
    // While a drag's edit is on its way on a software GL, a moved stand-in's frame waits (up to
    // MOTION_HOLD_MS) for that edit's shadows, so the two are drawn together in one frame.
    this.view.motionHold = () => (this.view.gl.software && this.view.interactions.has('drag') && this.busy() ? MOTION_HOLD_MS : 0);
    installSceneFileLoader($('scene-file'), this.api, this.fail, { scale: $('import-scale'), radiance: $('import-radiance') }, this.loading);
  }

  // A part of the page, kept here and handed to the parts installed after it.
  part(name, value) {
    this[name] = value;
    this.page[name] = value;
    return value;
  }

  // The view's layers: the glossy layer follows the stand-ins and lights; the stand-ins' faces
  // take the lit mesh's mean colours (keys: the receivers whose parts changed; null: all).
  connectLayers() {
    this.objects.onBuilt = (scene) => this.glossy.build(scene).then(() => this.view.requestRender(), (e) => this.fail(e));
    this.objects.onLight = (id, light) => this.glossy.setLight(id, light);
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
  }

  async start() {
    performance.mark('penumbra:start');
    const { api, state, hub } = this;
    state.id = new URLSearchParams(window.location.search).get('scene');
    this.loading.step('Loading the scene…');
    if (!state.id) {
      const scenes = (await api.listScenes()).scenes.filter((s) => s.state !== 'building');
      if (!scenes.length) throw new Error('the server serves no scene: load a .scene.json file');
      state.id = scenes[0].id;
    }
    const sceneId = state.id;
    // prefetch.js asked for the scene and its mesh while the modules loaded.
    const prefetch = window.penumbraPrefetch && window.penumbraPrefetch.sceneId === sceneId ? window.penumbraPrefetch : null;
    const meshResponse = prefetch ? api.adopt(prefetch.mesh, 'GET mesh')
      : api.request('GET', `${api.scenePath(sceneId)}/mesh?format=bin`);
    meshResponse.catch(() => {}); // reported when awaited below
    const wrapped = prefetch ? await (await api.adopt(prefetch.scene, 'GET scene')).json() : await api.getScene(sceneId);
    performance.mark('penumbra:scene');
    this.takeScene(wrapped);

    this.part('meshSync', new MeshSync(api, sceneId, (decoded) => this.meshApplied(decoded)));
    await this.meshSync.loadWhole(async () => ApiClient.bytesWithProgress(await meshResponse,
      (loaded, total) => this.loading.bytes('Downloading the lit mesh', loaded, total)));
    performance.mark('penumbra:mesh');
    this.loading.step('Drawing…');
    this.installSceneParts(sceneId);
    this.editor.updateReset();
    this.editor.refreshScenes();
    hub.emit('selection', null);
    api.stats(sceneId).then((stats) => hub.emit('built', stats, false)).catch(this.fail);

    this.renderPanel.schedule();
    this.view.requestRender();
    performance.mark('penumbra:ready');
    this.loading.done();
  }

  // The scene as first loaded: its header, undo history, stand-ins, tone map, look and camera.
  takeScene(wrapped) {
    const { state, hub } = this;
    const sceneId = state.id;
    $('scene-name').textContent = `${wrapped.id} (${wrapped.name})`;
    showImportReport($('import-report'), sceneId, wrapped.name);
    state.adopt(wrapped);
    state.name = wrapped.name;
    state.version = wrapped.version;
    this.editor.remember(wrapped);
    this.history.restore(`${wrapped.id}.${wrapped.name}`, wrapped.version);
    hub.on('renamed', (name) => {
      this.history.storageKey = `penumbra.history.${sceneId}.${name}`;
      if (this.look) this.look.setting.key = `penumbra.look.${sceneId}.${name}`;
      $('scene-name').textContent = `${sceneId} (${name})`;
    });

    this.part('volumes', new VolumeControls(this.page, sceneId, $('volume-note')));
    this.objects.build(wrapped.scene);
    hub.emit('standIns', wrapped.scene);
    this.part('toneMap', new ToneMap(wrapped.scene, this.objects.bounds));
    this.part('look', new ViewLook(this.page, sceneId, wrapped.name));
    this.view.setCamera(wrapped.scene.camera, this.objects.bounds, this.objects);
  }

  // The parts bound to the loaded scene: gizmo, server render, baked indirect light, the event
  // stream, the panel's controls and the volume loader.
  installSceneParts(sceneId) {
    const { api, state, hub } = this;
    this.part('gizmo', installGizmo(this.page));
    this.part('renderPanel', new RenderPanel(api, sceneId, this.view, $('render'), $('render-info'), $('render-progress'), this.fail,
      () => hasPhysicalMaterials(state.json)));
    this.view.onCameraChange(() => this.renderPanel.schedule());
    hub.on('imageStale', () => this.renderPanel.schedule());
    hub.on('render', (job) => this.renderPanel.job.report(job));
    hub.on('connection', (now) => this.renderPanel.job.setStreaming(now === 'connected'));
    this.part('bakedIndirect', new BakedIndirect(api, sceneId, (indirect) => {
      this.receivers.setIndirect(indirect, this.toneMap);
      const { version, seconds } = this.bakedIndirect;
      $('indirect-info').textContent = indirect ? `v${version} baked in ${(seconds * 1000).toFixed(0)} ms` : '';
      this.view.requestRender();
    }, this.fail));
    hub.on('version', () => this.bakedIndirect.schedule()); // a new version: bake it once edits pause
    this.part('events', new EventSync(api.eventsUrl(sceneId), {
      onVersion: (version) => this.follow.versionAnnounced(version),
      onRender: (job) => hub.emit('render', job),
      onError: this.fail,
      onConnection: (now, previous) => {
        hub.emit('connection', now, previous);
        this.follow.connection(now, previous);
      },
    }));
    installPanelControls(this.page);
    installVolumeLoader($('volume-file'), this.page);
  }

  // A mesh version applied: the exposure is taken from the first whole mesh (or kept), before its
  // colours are made.
  meshApplied(decoded) {
    this.look.beforeMesh(decoded);
    this.glossy.setExposure(this.toneMap.exposure);
    this.receivers.apply(decoded, this.toneMap);
    this.look.afterMesh();
    this.hub.emit('version', decoded);
    this.view.requestRender();
  }

  undo() {
    if (this.gizmo.dragging) return;
    this.history.undo(this.edits)?.catch(this.fail);
  }

  redo() {
    if (this.gizmo.dragging) return;
    this.history.redo(this.edits)?.catch(this.fail);
  }

  busy() {
    return this.edits.busy() || !!(this.meshSync && this.meshSync.running) || !!this.follow.resyncing
      || !!(this.volumes && this.volumes.busy()) || !!this.glossy.building;
  }

  // Resolves once no edit is pending or in flight, the page holds (and has timed) every version it
  // made, and the glossy layer shows the materials of the stand-ins built.
  async idle() {
    while (this.busy()) {
      await this.edits.idle();
      if (this.meshSync.running) await this.meshSync.running;
      if (this.follow.resyncing) await this.follow.resyncing;
      if (this.volumes) await this.volumes.idle();
      await this.glossy.idle();
    }
  }
}

const app = new App();
const hook = installTestHook(app);
app.start().then(() => { hook.ready = true; }).catch((error) => {
  app.banner.show(error);
  app.loading.failed(`The scene did not load: ${error.message || error}`);
});
