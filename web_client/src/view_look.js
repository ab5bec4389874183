// The view's look in the page: the exposure (automatic, kept per scene with the user's offset in
// stops: look_setting.js), taken again when the lights' power or shape changed (not while a drag is
// on), and the panel's exposure slider, Auto button and legend.
import { LookSetting, lightsSignature } from './look_setting.js';

const $ = (id) => document.getElementById(id);

export class ViewLook {
  // page: {toneMap, receivers, glossy, objects, view}; made once the tone map exists.
  constructor({ toneMap, receivers, glossy, objects, view }, sceneId, sceneName) {
    Object.assign(this, { toneMap, receivers, glossy, objects, view });
    this.setting = new LookSetting(sceneId, sceneName);
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
    return lightsSignature([...this.objects.lightJson.values()]);
  }

  // Before a mesh's colours are made: the first whole mesh sets the automatic exposure (unless one
  // was kept for these lights).
  beforeMesh(decoded) {
    const { toneMap } = this;
    if (toneMap.calibrated) return;
    toneMap.calibrate(decoded.parts);
    this.setting.setAuto(toneMap.auto, this.signature());
    this.glossy.setExposure(toneMap.exposure);
  }

  // After a mesh was applied: lights changed since the exposure was taken → take it again from the
  // whole mesh held, with their new ambient term, and recolour.
  afterMesh() {
    const { toneMap } = this;
    const signature = this.signature();
    if (signature === this.setting.lights || this.view.interactions.has('drag')) return;
    toneMap.setLights([...this.objects.lightJson.values()]);
    toneMap.calibrate([...this.receivers.entries.values()].map((entry) => entry.part));
    this.setting.setAuto(toneMap.auto, signature);
    this.recolour();
  }

  setEv(ev) {
    this.toneMap.ev = ev;
    this.setting.setEv(ev);
    this.slider.value = String(ev);
    this.label();
    this.recolour();
  }

  recolour() {
    this.glossy.setExposure(this.toneMap.exposure);
    this.receivers.recolourAll(this.toneMap);
    this.view.requestRender();
  }

  label() {
    const { ev } = this.setting;
    $('exposure-value').textContent = ev ? `auto ${ev > 0 ? '+' : '−'}${Math.abs(ev).toFixed(2)} EV` : 'auto';
  }
}
