// The view's look in the page: the exposure (automatic, kept per scene with the user's offset in
// stops: look_setting.js), taken again when the lights' power or shape changed (not while a drag is
// on), and the panel's exposure slider, Auto button and legend.
import { LookSetting, lightsSignature } from './look_setting.js';

const $ = (id) => document.getElementById(id);

export class ViewLook {
  // app: the page (toneMap, receivers, glossy, objects, view); called once the tone map exists.
  constructor(app, sceneId, sceneName) {
    this.app = app;
    this.setting = new LookSetting(sceneId, sceneName);
    const { toneMap } = app;
    toneMap.ev = this.setting.ev;
    const kept = this.setting.autoFor(this.signature());
    if (kept) Object.assign(toneMap, { auto: kept, calibrated: true });
    this.slider = $('exposure');
    this.slider.value = String(this.setting.ev);
    this.slider.addEventListener('input', () => this.setEv(Number(this.slider.value)));
    $('exposure-auto').addEventListener('click', () => this.setEv(0));
    this.label();
  }

  signature() {
    return lightsSignature([...this.app.objects.lightJson.values()]);
  }

  // Before a mesh's colours are made: the first whole mesh sets the automatic exposure (unless one
  // was kept for these lights).
  beforeMesh(decoded) {
    const { toneMap } = this.app;
    if (toneMap.calibrated) return;
    toneMap.calibrate(decoded.parts);
    this.setting.setAuto(toneMap.auto, this.signature());
    this.app.glossy.setExposure(toneMap.exposure);
  }

  // After a mesh was applied: lights changed since the exposure was taken → take it again from the
  // whole mesh held, with their new ambient term, and recolour.
  afterMesh() {
    const { app } = this;
    const signature = this.signature();
    if (signature === this.setting.lights || app.view.interactions.has('drag')) return;
    app.toneMap.setLights([...app.objects.lightJson.values()]);
    app.toneMap.calibrate([...app.receivers.entries.values()].map((entry) => entry.part));
    this.setting.setAuto(app.toneMap.auto, signature);
    this.recolour();
  }

  setEv(ev) {
    this.app.toneMap.ev = ev;
    this.setting.setEv(ev);
    this.slider.value = String(ev);
    this.label();
    this.recolour();
  }

  recolour() {
    const { app } = this;
    app.glossy.setExposure(app.toneMap.exposure);
    app.receivers.recolourAll(app.toneMap);
    app.view.requestRender();
  }

  label() {
    const { ev } = this.setting;
    $('exposure-value').textContent = ev ? `auto ${ev > 0 ? '+' : '−'}${Math.abs(ev).toFixed(2)} EV` : 'auto';
  }
}
