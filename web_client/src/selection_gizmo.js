// Click to select a movable object (a raycast against the objects' stand-ins; a press that
// moved more than a few pixels is an orbit, not a click), and drag it with TransformControls:
// W translate, E rotate, Escape deselects. Reports each gesture's start, every change and end.
import * as THREE from 'three';
import { TransformControls } from 'three/addons/controls/TransformControls.js';

const CLICK_SLOP_PX = 4;

export class SelectionGizmo {
  // callbacks: {onSelect(id|null), onDragStart(id), onChange(id), onDragEnd(id)}
  constructor(view, objects, callbacks) {
    this.view = view;
    this.objects = objects;
    this.callbacks = callbacks;
    this.selected = null;
    this.dragging = false;
    this.raycaster = new THREE.Raycaster();
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
      const typing = event.target instanceof HTMLInputElement && !['checkbox', 'button', 'file'].includes(event.target.type);
      if (typing || event.ctrlKey || event.metaKey) return;
      if (event.key === 'w' || event.key === 'W') this.setMode('translate');
      else if (event.key === 'e' || event.key === 'E') this.setMode('rotate');
      else if (event.key === 'Escape') this.select(null);
    });
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
    this.select(hits.length ? hits[0].object.userData.objectId : null);
  }

  select(id) {
    if (this.selected) {
      const old = this.objects.byId.get(this.selected);
      if (old) old.getObjectByName('outline').visible = false;
    }
    const holder = id ? this.objects.byId.get(id) : null;
    this.selected = holder ? id : null;
    if (holder) {
      holder.getObjectByName('outline').visible = true;
      this.controls.attach(holder);
    } else {
      this.controls.detach();
    }
    this.callbacks.onSelect(this.selected);
    this.view.requestRender();
  }

  holder() {
    return this.selected ? this.objects.byId.get(this.selected) : null;
  }
}
