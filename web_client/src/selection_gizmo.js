// Click to select a movable object or a light (a raycast against the stand-ins; a press that
// moved more than a few pixels is an orbit, not a click), and drag an object with
// TransformControls: W translate, E rotate, R scale, Escape deselects; snapping (0.1 m, 15°, 0.1)
// while Ctrl is held or the snap box is ticked. A light is selected as "light:ID" and gets the same
// gizmo on its holder (moved, turned, resized: set_light). Reports each gesture's start, every
// change and end.
import * as THREE from 'three';
import { TransformControls } from 'three/addons/controls/TransformControls.js';

const CLICK_SLOP_PX = 4;
export const SNAP = { translate: 0.1, rotateDeg: 15, scale: 0.1 };

export class SelectionGizmo {
  // callbacks: {onSelect(id|null), onDragStart(id), onChange(id), onDragEnd(id)}
  constructor(view, objects, callbacks) {
    this.view = view;
    this.objects = objects;
    this.callbacks = callbacks;
    this.selected = null;
    this.dragging = false;
    this.raycaster = new THREE.Raycaster();
    this.snapBox = false; // the panel's snap checkbox
    this.ctrlHeld = false;
    this.controls = new TransformControls(view.camera, view.renderer.domElement);
    view.scene.add(this.controls.getHelper());
    this.controls.addEventListener('change', () => view.requestMotionRender());
    this.controls.addEventListener('dragging-changed', (event) => {
      view.controls.enabled = !event.value;
      this.dragging = event.value;
      if (event.value) callbacks.onDragStart(this.selected);
      else callbacks.onDragEnd(this.selected);
    });
    this.controls.addEventListener('objectChange', () => callbacks.onChange(this.selected));

    const canvas = view.renderer.domElement;
    let down = null;
    canvas.addEventListener('pointerdown', (event) => { down = { x: event.clientX, y: event.clientY }; });
    canvas.addEventListener('pointerup', (event) => {
      if (!down || this.dragging || this.controls.axis !== null) return;
      const moved = Math.hypot(event.clientX - down.x, event.clientY - down.y);
      down = null;
      if (moved <= CLICK_SLOP_PX) this.pick(event);
    });
    window.addEventListener('keydown', (event) => {
      if (event.key === 'Control') this.setCtrl(true);
      const typing = event.target instanceof HTMLInputElement && !['checkbox', 'button', 'file'].includes(event.target.type);
      if (typing || event.ctrlKey || event.metaKey || event.altKey) return;
      if (event.key === 'w' || event.key === 'W') this.setMode('translate');
      else if (event.key === 'e' || event.key === 'E') this.setMode('rotate');
      else if (event.key === 'r' || event.key === 'R') this.setMode('scale');
      else if (event.key === 'Escape') this.select(null);
    });
    window.addEventListener('keyup', (event) => { if (event.key === 'Control') this.setCtrl(false); });
    window.addEventListener('blur', () => this.setCtrl(false));
  }

  setCtrl(held) {
    this.ctrlHeld = held;
    this.applySnap();
  }

  setSnap(on) {
    this.snapBox = on;
    this.applySnap();
  }

  snapping() {
    return this.snapBox || this.ctrlHeld;
  }

  applySnap() {
    const on = this.snapping();
    this.controls.setTranslationSnap(on ? SNAP.translate : null);
    this.controls.setRotationSnap(on ? THREE.MathUtils.degToRad(SNAP.rotateDeg) : null);
    this.controls.setScaleSnap(on ? SNAP.scale : null);
  }

  setMode(mode) {
    this.controls.setMode(mode);
    this.callbacks.onMode && this.callbacks.onMode(mode);
  }

  pick(event) {
    const rect = this.view.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2(((event.clientX - rect.left) / rect.width) * 2 - 1,
      -((event.clientY - rect.top) / rect.height) * 2 + 1);
    this.raycaster.setFromCamera(ndc, this.view.camera);
    const hits = this.raycaster.intersectObjects(this.objects.pickable(), false);
    const hit = hits.length ? hits[0].object.userData : null;
    this.select(hit ? (hit.lightId !== undefined ? `light:${hit.lightId}` : hit.objectId) : null);
  }

  select(id) {
    if (this.selected) this.objects.setOutlined(this.selected, false);
    const holder = this.objects.holderOf(id);
    this.selected = holder ? id : null;
    if (holder) {
      this.objects.setOutlined(id, true);
      this.controls.attach(holder);
    } else {
      this.controls.detach();
    }
    this.callbacks.onSelect(this.selected);
    this.view.requestRender();
  }

  // The selection's Group: an object's holder or a light's.
  holder() {
    return this.objects.holderOf(this.selected);
  }
}
