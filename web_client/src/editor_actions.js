// The editor's commands beyond dragging: add a box or another primitive, add a light, duplicate, delete (objects and
// lights; each one frame, undoable),
// typed transforms and lights, reset to the file, downloads, the scene list, and the camera (focus on the
// selection, frame all, back home). Structural frames wait for pending moves, then reload the
// stand-ins from the server's scene (the object list changed).
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
  constructor(app) {
    this.app = app;
    this.running = new Set(); // structural changes under way (the page is busy until they end)
    this.sceneList = new SceneList($('scene-list'), {
      onDelete: (summary) => this.deleteScene(summary),
      onRename: (summary, name) => renameScene(app, summary, name).then(() => this.refreshScenes(), app.fail),
      pageUrl: (id) => this.pageUrl(id),
    });
  }

  pageUrl(id) {
    const query = new URLSearchParams({ scene: id });
    if (this.app.api.token) query.set('token', this.app.api.token);
    return `?${query}`;
  }

  scene() {
    return this.app.sceneJson;
  }

  // One structural frame; on success the stand-ins are reloaded and `selectId` selected.
  sendStructural(edits, selectId) {
    const { app } = this;
    const task = (async () => {
      await app.coalescer.idle();
      await app.sendFrame({ edits });
      await app.reloadObjects(selectId);
    })();
    this.running.add(task);
    const forget = () => this.running.delete(task);
    task.then(forget, forget);
    return task;
  }

  // Runs a structural change {redo, undo} and records it for undo.
  async change(edits, label, selectAfter, selectBefore = null) {
    try {
      await this.sendStructural(edits.redo, selectAfter);
      this.app.history.push({ frame: edits, label, select: { redo: selectAfter, undo: selectBefore } });
      this.app.updateUndoButtons();
    } catch (error) {
      this.app.fail(error);
    }
  }

  addBox() {
    return this.addPrimitive('box');
  }

  // A primitive (primitives.js) a tenth of the scene's size, on the floor, in view, where no other
  // object is (placement.js), in the scene's first material: one add, selected afterwards.
  addPrimitive(kind) {
    const scene = this.scene();
    const bounds = this.app.objects.bounds;
    const size = Math.max(0.05, 0.1 * bounds.getSize(new THREE.Vector3()).length() / Math.sqrt(3));
    const extent = new THREE.Vector3(...primitiveSize(kind, size));
    const at = floorSpot(this.app.objects, this.app.view, extent);
    if (kind === 'plane') at[1] += size / 2; // a sheet at a box's middle height: it casts a shadow
    const material = scene.materials ? Object.keys(scene.materials)[0] : undefined;
    const object = primitiveObject(kind, freshId(scene, kind), at, size, material);
    return this.change(addEdits(object), `add ${object.id}`, object.id);
  }

  // A copy of the selected light (else the first) beside it, inside the scene's bounds, where the
  // view sees it if it can, with a fresh id: one add_light (a full rebuild on the server), selected afterwards.
  addLight() {
    const { objects } = this.app;
    const selected = this.app.gizmo.selected;
    const source = (selected && selected.startsWith('light:') && objects.lightJson.get(selected.slice(6)))
      || objects.lightJson.values().next().value;
    if (!source) return null;
    const box = { min: objects.bounds.min.toArray(), max: objects.bounds.max.toArray() };
    const lights = [...objects.lightJson.values()].map((l) => l.polygon);
    const offset = lightOffset(source.polygon, box, lights, this.app.view.camera);
    if (!offset) {
      this.app.fail(new Error(`no room beside light ${source.id} for a copy inside the scene`));
      return null;
    }
    const light = lightCopy(source, freshId(this.scene(), source.id, 'lights'), offset);
    return this.change(addLightEdits(light), `add light ${light.id}`, `light:${light.id}`, selected);
  }

  // A light can go while another stays (a scene keeps at least one).
  canDeleteLight() {
    return this.app.objects.lightJson.size > 1;
  }

  duplicate() {
    const id = this.app.gizmo.selected;
    if (id && id.startsWith('light:')) return this.addLight();
    const object = id && this.app.objects.json.get(id);
    if (!object) return null;
    const current = { ...object, transform: transformOf(this.app.objects.byId.get(id)) };
    // Beside the original where nothing else is (else, in a full room, a quarter of its size off).
    const box = this.app.objects.objectBounds(id);
    const size = box.getSize(new THREE.Vector3());
    const offset = freeOffset(this.app.objects, box) || [0.25 * size.x + 0.05, 0, 0.25 * size.z + 0.05];
    const copy = duplicateObject(current, freshId(this.scene(), `${id}_copy`), offset);
    return this.change(addEdits(copy), `duplicate ${id}`, copy.id, id);
  }

  deleteSelected() {
    const id = this.app.gizmo.selected;
    if (id && id.startsWith('light:')) {
      const light = this.app.objects.lightJson.get(id.slice(6));
      if (!light || !this.canDeleteLight()) return null;
      return this.change(removeLightEdits(light), `delete ${id}`, null, id);
    }
    const object = id && this.app.objects.json.get(id);
    if (!object) return null;
    const current = { ...object, transform: transformOf(this.app.objects.byId.get(id)) };
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
      this.app.fail(new Error(`cannot rename '${old}' to '${name}': ${problem}`));
      this.app.selected(id); // the field shows the name it has
      return null;
    }
    if (isLightId) {
      const light = this.app.objects.lightJson.get(old);
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
    const object = this.app.objects.json.get(id);
    return object ? { ...object, transform: transformOf(this.app.objects.byId.get(id)) } : null;
  }

  // A transform typed in the inspector: one move, undoable.
  typedTransform(id, transform) {
    const holder = this.app.objects.byId.get(id);
    if (!holder) return;
    const before = transformOf(holder);
    if (sameTransform(before, transform)) return;
    this.app.moveTo(id, transform);
    this.app.history.push({ id, before, after: transform });
    this.app.updateUndoButtons();
  }

  // A light typed in the inspector: one set_light, undoable.
  typedLight(lightId, light) {
    const from = this.app.objects.lightJson.get(lightId);
    if (!from) return;
    const before = { polygon: from.polygon, radiance: from.radiance };
    const after = { polygon: light.polygon, radiance: light.radiance };
    if (sameTransform(before, after)) return;
    this.app.lightTo(lightId, after);
    this.app.history.push({ id: `light:${lightId}`, before, after });
    this.app.updateUndoButtons();
  }

  // Back to the scene as the server first built it (kept by this browser at version 0).
  async resetToFile() {
    const { app } = this;
    const source = sourceOf(app.sceneId, app.sceneName);
    if (!source) return;
    await app.coalescer.idle();
    const current = (await app.api.getScene(app.sceneId)).scene;
    const edits = resetEdits(current, source);
    if (!edits.length) return;
    const undo = resetEdits(source, current);
    await this.change({ redo: edits, undo }, 'reset to file', null, app.gizmo.selected);
  }

  updateReset() {
    const { app } = this;
    const known = !!sourceOf(app.sceneId, app.sceneName);
    $('reset-scene').disabled = !known;
    $('reset-scene').title = known ? 'One frame back to the scene as the server first built it'
      : 'This browser did not see the scene at version 0, so it does not know the file';
  }

  remember(wrapped) {
    rememberSource(wrapped.id, wrapped.name, wrapped.version, wrapped.scene);
  }

  downloadJson() {
    const { app } = this;
    return app.api.getScene(app.sceneId).then((wrapped) => {
      download(`${app.sceneId}.v${wrapped.version}.scene.json`, new Blob([JSON.stringify(wrapped.scene, null, 1)], { type: 'application/json' }));
    }).catch(app.fail);
  }

  async downloadGlb() {
    const { app } = this;
    try {
      const response = await app.api.request('GET', `${app.api.scenePath(app.sceneId)}/mesh?format=glb`);
      download(`${app.sceneId}.v${response.headers.get('X-Penumbra-Version')}.glb`, await response.blob());
    } catch (error) {
      app.fail(error);
    }
  }

  // The server's render of the view as PNG: at the view's size in pixels, or `size` ('WxH').
  async downloadPng(size = 'view') {
    const { app } = this;
    const canvas = app.view.renderer.domElement;
    const [width, height] = size === 'view' ? [canvas.width, canvas.height] : size.split('x').map(Number);
    try {
      const image = await app.api.image(app.sceneId, Math.min(width, 4096), Math.min(height, 4096), app.view.cameraQuery());
      download(`${app.sceneId}.v${image.version}.${width}x${height}.png`, image.blob);
      return { width, height, version: image.version, bytes: image.blob.size };
    } catch (error) {
      app.fail(error);
      return null;
    }
  }

  async refreshScenes() {
    try {
      const { scenes } = await this.app.api.listScenes();
      this.sceneList.render(scenes, this.app.sceneId);
      // Scenes being built: shown with their progress until they are ready.
      clearTimeout(this.sceneListTimer);
      if (scenes.some((s) => s.state === 'building')) this.sceneListTimer = setTimeout(() => this.refreshScenes(), 1000);
      return scenes.filter((s) => s.state !== 'building');
    } catch (error) {
      this.app.fail(error);
      return [];
    }
  }

  async deleteScene(summary) {
    const { app } = this;
    try {
      await app.api.json('DELETE', app.api.scenePath(summary.id));
      forgetSource(summary.id, summary.name);
      const scenes = await this.refreshScenes();
      if (summary.id === app.sceneId) window.location.search = scenes.length ? this.pageUrl(scenes[0].id) : '';
    } catch (error) {
      app.fail(error);
    }
  }

  focus() {
    const id = this.app.gizmo.selected;
    if (!id) return this.frameAll();
    const box = id.startsWith('light:') ? new THREE.Box3().setFromObject(this.app.objects.lights.getObjectByName(id))
      : this.app.objects.objectBounds(id);
    // From inside the room (the scene's bounds): a ceiling light is seen from below, not from above the ceiling.
    this.app.view.frame(box, this.app.objects.bounds);
  }

  frameAll() {
    this.app.view.frame(this.app.objects.bounds);
  }
}
