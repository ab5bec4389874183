// The view's exposure, kept per scene in this browser (localStorage), so a reload shows the same
// look: the automatic exposure (ToneMap.calibrate, from the lit mesh) with the lights it was taken
// under, and the user's offset in stops (EV) on top of it. A change of the lights' power or shape
// calls for a new automatic exposure (a bigger light would blow the floor to white); moving objects
// does not (colours hold still while you drag).

const keyOf = (id, name) => `penumbra.look.${id}.${name}`;

// The lights as a text that changes when their power or shape does.
export const lightsSignature = (lights) => JSON.stringify([...lights].sort((a, b) => (a.id < b.id ? -1 : 1))
  .map((l) => [l.id, l.polygon, l.radiance]));

export class LookSetting {
  constructor(sceneId, sceneName) {
    this.key = keyOf(sceneId, sceneName);
    let kept = null;
    try {
      kept = JSON.parse(localStorage.getItem(this.key) || 'null');
    } catch {
      // Unreadable or no storage: automatic, no offset.
    }
    this.auto = kept && Number.isFinite(kept.auto) && kept.auto > 0 ? kept.auto : null;
    this.lights = kept ? kept.lights : null;
    this.ev = kept && Number.isFinite(kept.ev) ? kept.ev : 0;
  }

  // The kept automatic exposure if it was taken under these lights, else null (calibrate anew).
  autoFor(signature) {
    return this.auto !== null && this.lights === signature ? this.auto : null;
  }

  setAuto(auto, signature) {
    Object.assign(this, { auto, lights: signature });
    this.save();
  }

  setEv(ev) {
    this.ev = ev;
    this.save();
  }

  save() {
    try {
      localStorage.setItem(this.key, JSON.stringify({ auto: this.auto, lights: this.lights, ev: this.ev }));
    } catch {
      // Storage full or disabled: the look lasts until the page is left.
    }
  }
}
