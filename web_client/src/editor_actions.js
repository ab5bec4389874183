// The editor's commands beyond dragging: add a box or another primitive, add a light, duplicate, delete (objects and
// lights; each one frame, undoable),
// typed transforms and lights, reset to the file, downloads, the scene list, and the camera (focus on the
// selection, frame all, back home). Each undoable change is a command (commands.js) done against
// the page's edits (scene_edits.js: structural frames wait for pending moves, then reload the
// stand-ins from the server's scene) and recorded in the undo history.
import { FrameCommand, MoveCommand } from './commands.js';
import { primitiveObject, primitiveSize } from './primitives.js';
import { addEdits, addLightEdits, duplicateObject, freshId, lightCopy, materialEdits, removeEdits, removeLightEdits,
  renameEdits, renameLightEdits, resetEdits } from './object_edits.js';
import { floorSpot, freeOffset, lightOffset } from './placement.js';
import { objectMaterialEdits } from './material_edits.js';
import { renameScene } from './scene_rename.js';
import { SceneList, download, forgetSource, rememberSource, sourceOf } from './scene_library.js';
import { sameTransform, transformOf } from './scene_transform.js';
import * as THREE from 'three';

const $ = (id) => document.getElementById(id);

export class EditorActions {
  // page: {api, state: SceneState, hub, history: UndoHistory, edits: SceneEdits, objects: SceneObjects,
  //   view: SceneView, selection() → the selected id, fail(error)}.
  constructor({ api, state, hub, history, edits, objects, view, selection, fail }) {
    Object.assign(this, { api, state, hub, history, edits, objects, view, selection, fail });
    this.sceneList = new SceneList($('scene-list'), {
      onDelete: (summary) => this.deleteScene(summary),
      onRename: (summary, name) => this.renameScene(summary, name),
      pageUrl: (id) => this.pageUrl(id),
    });
  }

  async renameScene(summary, name) {
    try {
      const answer = await renameScene(this.api, summary, name);
      if (summary.id === this.state.id) {
        this.state.name = answer.name;
        this.hub.emit('renamed', answer.name);
      }
      await this.refreshScenes();
    } catch (error) {
      this.fail(error);
    }
  }

  pageUrl(id) {
    const query = new URLSearchParams({ scene: id });
    if (this.api.token) query.set('token', this.api.token);
    return `?${query}`;
  }

  scene() {
    return this.state.json;
  }

  // Runs a structural change {redo, undo} and records it for undo.
  async change(edits, label, selectAfter, selectBefore = null) {
    try {
      await this.history.execute(new FrameCommand(edits, label, { redo: selectAfter, undo: selectBefore }), this.edits);
    } catch (error) {
      this.fail(error);
    }
  }

  addBox() {
    return this.addPrimitive('box');
  }

  // A primitive (primitives.js) a tenth of the scene's size, on the floor, in view, where no other
  // object is (placement.js), in the scene's first material: one add, selected afterwards.
  addPrimitive(kind) {
    const scene = this.scene();
    const bounds = this.objects.bounds;
    const size = Math.max(0.05, 0.1 * bounds.getSize(new THREE.Vector3()).length() / Math.sqrt(3));
    const extent = new THREE.Vector3(...primitiveSize(kind, size));
    const at = floorSpot(this.objects, this.view, extent);
    if (kind === 'plane') at[1] += size / 2; // a sheet at a box's middle height: it casts a shadow
    const material = scene.materials ? Object.keys(scene.materials)[0] : undefined;
    const object = primitiveObject(kind, freshId(scene, kind), at, size, material);
    return this.change(addEdits(object), `add ${object.id}`, object.id);
  }

  // A copy of the selected light (else the first) beside it, inside the scene's bounds, where the
  // view sees it if it can, with a fresh id: one add_light (a full rebuild on the server), selected afterwards.
  addLight() {
    const { objects } = this;
    const selected = this.selection();
    const source = (selected && selected.startsWith('light:') && objects.lightJson.get(selected.slice(6)))
      || objects.lightJson.values().next().value;
    if (!source) return null;
    const box = { min: objects.bounds.min.toArray(), max: objects.bounds.max.toArray() };
    const lights = [...objects.lightJson.values()].map((l) => l.polygon);
    const offset = lightOffset(source.polygon, box, lights, this.view.camera);
    if (!offset) {
      this.fail(new Error(`no room beside light ${source.id} for a copy inside the scene`));
      return null;
    }
    const light = lightCopy(source, freshId(this.scene(), source.id, 'lights'), offset);
    return this.change(addLightEdits(light), `add light ${light.id}`, `light:${light.id}`, selected);
  }

  // A light can go while another stays (a scene keeps at least one).
  canDeleteLight() {
    return this.objects.lightJson.size > 1;
  }

  duplicate() {
    const id = this.selection();
    if (id && id.startsWith('light:')) return this.addLight();
    const object = id && this.objects.json.get(id);
    if (!object) return null;
    const current = { ...object, transform: transformOf(this.objects.byId.get(id)) };
    // Beside the original where nothing else is (else, in a full room, a quarter of its size off).
    const box = this.objects.objectBounds(id);
    const size = box.getSize(new THREE.Vector3());
    const offset = freeOffset(this.objects, box) || [0.25 * size.x + 0.05, 0, 0.25 * size.z + 0.05];
    const copy = duplicateObject(current, freshId(this.scene(), `${id}_copy`), offset);
    return this.change(addEdits(copy), `duplicate ${id}`, copy.id, id);
  }

  deleteSelected() {
    const id = this.selection();
    if (id && id.startsWith('light:')) {
      const light = this.objects.lightJson.get(id.slice(6));
      if (!light || !this.canDeleteLight()) return null;
      return this.change(removeLightEdits(light), `delete ${id}`, null, id);
    }
    const object = id && this.objects.json.get(id);
    if (!object) return null;
    const current = { ...object, transform: transformOf(this.objects.byId.get(id)) };
    return this.change(removeEdits(current), `delete ${id}`, null, id);
  }

  // A name typed in the inspector: the object or light under a new id (one frame, one undo step).
  // A name that is not letters, digits, _ . - (at most 64) or that is taken is refused here, naming it.
  rename(id, name) {
    const isLightId = id.startsWith('light:');
    const list = isLightId ? 'lights' : 'objects';
    const old = isLightId ? id.slice(6) : id;
    const problem = !/^[A-Za-z0-9_.-]{1,64}$/.test(name) ? 'use letters, digits, _ . or - (at most 64)'
      : (this.scene()[list] || []).some((o) => o.id === name) ? `the scene has ${isLightId ? 'a light' : 'an object'} named '${name}'` : null;
    if (problem) {
      this.fail(new Error(`cannot rename '${old}' to '${name}': ${problem}`));
      this.hub.emit('selection', id); // the field shows the name it has
      return null;
    }
    if (isLightId) {
      const light = this.objects.lightJson.get(old);
      return light ? this.change(renameLightEdits(light, name), `rename ${id}`, `light:${name}`, id) : null;
    }
    const current = this.current(id);
    return current ? this.change(renameEdits(current, name), `rename ${id}`, name, id) : null;
  }

  // Another of the scene's materials chosen in the inspector: one frame, one undo step.
  setMaterial(id, material) {
    const current = this.current(id);
    if (!current || current.material === material) return null;
    return this.change(materialEdits(current, material), `material of ${id}`, id, id);
  }

  // A colour or type chosen in the inspector: one frame, one undo step (material_edits.js).
  paint(id, change) {
    const current = this.current(id);
    const edits = current && objectMaterialEdits(this.scene(), current, change);
    return edits ? this.change(edits, `material of ${id}`, id, id) : null;
  }

  // An object's JSON with the transform it has now (after drags not yet reloaded).
  current(id) {
    const object = this.objects.json.get(id);
    return object ? { ...object, transform: transformOf(this.objects.byId.get(id)) } : null;
  }

  // A transform typed in the inspector: one move, undoable.
  typedTransform(id, transform) {
    const holder = this.objects.byId.get(id);
    if (!holder) return;
    const before = transformOf(holder);
    if (sameTransform(before, transform)) return;
    const command = new MoveCommand(id, before, transform);
    command.do(this.edits);
    this.history.record(command);
  }

  // A light typed in the inspector: one set_light, undoable.
  typedLight(lightId, light) {
    const from = this.objects.lightJson.get(lightId);
    if (!from) return;
    const before = { polygon: from.polygon, radiance: from.radiance };
    const after = { polygon: light.polygon, radiance: light.radiance };
    if (sameTransform(before, after)) return;
    const command = new MoveCommand(`light:${lightId}`, before, after);
    command.do(this.edits);
    this.history.record(command);
  }

  // Back to the scene as the server first built it (kept by this browser at version 0).
  async resetToFile() {
    const { api, state } = this;
    const source = sourceOf(state.id, state.name);
    if (!source) return;
    await this.edits.coalescer.idle();
    const current = (await api.getScene(state.id)).scene;
    const edits = resetEdits(current, source);
    if (!edits.length) return;
    const undo = resetEdits(source, current);
    await this.change({ redo: edits, undo }, 'reset to file', null, this.selection());
  }

  updateReset() {
    const known = !!sourceOf(this.state.id, this.state.name);
    $('reset-scene').disabled = !known;
    $('reset-scene').title = known ? 'One frame back to the scene as the server first built it'
      : 'This browser did not see the scene at version 0, so it does not know the file';
  }

  remember(wrapped) {
    rememberSource(wrapped.id, wrapped.name, wrapped.version, wrapped.scene);
  }

  downloadJson() {
    const { api, state } = this;
    return api.getScene(state.id).then((wrapped) => {
      download(`${state.id}.v${wrapped.version}.scene.json`, new Blob([JSON.stringify(wrapped.scene, null, 1)], { type: 'application/json' }));
    }).catch(this.fail);
  }

  async downloadGlb() {
    const { api, state } = this;
    try {
      const response = await api.request('GET', `${api.scenePath(state.id)}/mesh?format=glb`);
      download(`${state.id}.v${response.headers.get('X-Penumbra-Version')}.glb`, await response.blob());
    } catch (error) {
      this.fail(error);
    }
  }

  // The server's render of the view as PNG: at the view's size in pixels, or `size` ('WxH').
  async downloadPng(size = 'view') {
    const { api, state, view } = this;
    const canvas = view.renderer.domElement;
    const [width, height] = size === 'view' ? [canvas.width, canvas.height] : size.split('x').map(Number);
    try {
      const image = await api.image(state.id, Math.min(width, 4096), Math.min(height, 4096), view.cameraQuery());
      download(`${state.id}.v${image.version}.${width}x${height}.png`, image.blob);
      return { width, height, version: image.version, bytes: image.blob.size };
    } catch (error) {
      this.fail(error);
      return null;
    }
  }

  async refreshScenes() {
    try {
      const { scenes } = await this.api.listScenes();
      this.sceneList.render(scenes, this.state.id);
      // Scenes being built: shown with their progress (the builds event stream) until they end.
      this.sceneList.followBuilds(scenes.some((s) => s.state === 'building') ? this.api.buildEventsUrl() : null,
        () => this.refreshScenes());
      return scenes.filter((s) => s.state !== 'building');
    } catch (error) {
      this.fail(error);
      return [];
    }
  }

  async deleteScene(summary) {
    const { api, state } = this;
    try {
      await api.json('DELETE', api.scenePath(summary.id));
      forgetSource(summary.id, summary.name);
      const scenes = await this.refreshScenes();
      if (summary.id === state.id) window.location.search = scenes.length ? this.pageUrl(scenes[0].id) : '';
    } catch (error) {
      this.fail(error);
    }
  }

  focus() {
    const id = this.selection();
    if (!id) return this.frameAll();
    const box = id.startsWith('light:') ? new THREE.Box3().setFromObject(this.objects.lights.getObjectByName(id))
      : this.objects.objectBounds(id);
    // From inside the room (the scene's bounds): a ceiling light is seen from below, not from above the ceiling.
    this.view.frame(box, this.objects.bounds);
  }

  frameAll() {
    this.view.frame(this.objects.bounds);
  }
}
