// The inspector: the selected object's transform as numbers (translate m, rotate °, scale), which
// may be typed (Enter or leaving the field applies, as one undoable edit), or the selected light's
// centre, size and radiance. Lights are shown, not edited: the server's edit frames have no light
// operation yet (docs/SCENE_FORMAT.md lists set_light / add_light / remove_light as the names
// it will take).

const ROWS = [['translate', 'move (m)'], ['rotate_deg', 'rotate (°)'], ['scale', 'scale']];
const round = (x) => String(Math.round(x * 1e4) / 1e4);

export class Inspector {
  // onTransform(id, transform): a typed transform to apply.
  constructor(root, onTransform) {
    this.root = root;
    this.onTransform = onTransform;
    this.id = null;
    this.inputs = null;
  }

  // Shows `id` (an object id, "light:ID" or null) with its data: an object's transform, or the light JSON.
  show(id, data) {
    this.id = id;
    this.root.replaceChildren();
    this.inputs = null;
    if (!id) {
      this.root.textContent = 'Nothing selected: click an object or a light.';
      return;
    }
    if (id.startsWith('light:')) return this.showLight(id.slice(6), data);
    const title = document.createElement('div');
    title.textContent = id;
    title.className = 'inspector-title';
    this.root.append(title);
    this.inputs = {};
    for (const [key, label] of ROWS) {
      const row = document.createElement('div');
      row.className = 'row inspector-row';
      const name = document.createElement('span');
      name.textContent = label;
      row.append(name);
      this.inputs[key] = [0, 1, 2].map((k) => {
        const input = document.createElement('input');
        input.type = 'text';
        input.inputMode = 'decimal';
        input.size = 6;
        input.dataset.key = `${key}.${k}`;
        input.addEventListener('change', () => this.typed());
        input.addEventListener('keydown', (event) => { if (event.key === 'Enter') input.blur(); });
        row.append(input);
        return input;
      });
      this.root.append(row);
    }
    this.update(data);
  }

  // The fields follow the object (after a drag or another client's edit) unless one is being typed in.
  update(transform) {
    if (!this.inputs || !transform) return;
    for (const [key] of ROWS) {
      const values = transform[key] || (key === 'scale' ? [1, 1, 1] : [0, 0, 0]);
      this.inputs[key].forEach((input, k) => { if (document.activeElement !== input) input.value = round(values[k]); });
    }
  }

  typed() {
    const transform = {};
    for (const [key] of ROWS) {
      const values = this.inputs[key].map((input) => Number(input.value.replace(',', '.')));
      if (values.some((v) => !Number.isFinite(v))) {
        this.inputs[key].forEach((input) => input.classList.toggle('invalid', !Number.isFinite(Number(input.value.replace(',', '.')))));
        return;
      }
      this.inputs[key].forEach((input) => input.classList.remove('invalid'));
      transform[key] = values;
    }
    this.onTransform(this.id, transform);
  }

  showLight(lightId, light) {
    const lines = [`light ${lightId}`];
    if (light) {
      const n = light.polygon.length;
      const centre = [0, 1, 2].map((k) => light.polygon.reduce((s, p) => s + p[k], 0) / n);
      const size = [0, 1, 2].map((k) => Math.max(...light.polygon.map((p) => p[k])) - Math.min(...light.polygon.map((p) => p[k])));
      lines.push(`centre ${centre.map(round).join(', ')} m`, `size ${size.map(round).join(' × ')} m (${n} corners)`,
        `radiance ${light.radiance.map(round).join(', ')}`);
    }
    lines.push('Lights cannot be edited yet: the server has no light edits (set_light).');
    for (const [i, text] of lines.entries()) {
      const line = document.createElement('div');
      line.textContent = text;
      if (i === 0) line.className = 'inspector-title';
      if (i === lines.length - 1) line.className = 'muted';
      this.root.append(line);
    }
  }
}
