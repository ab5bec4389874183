// The inspector: the selected object's transform as numbers (translate m, rotate °, scale), or the
// selected light's centre, size, radiance and intensity; either may be typed (Enter or leaving the
// field applies, as one undoable edit: a move, or a set_light). Each field is an ExactField: a
// value not typed goes back exactly as the page holds it, never as the rounded text shown.

import { ExactField } from './exact_field.js';
import { MATERIAL_TYPES, albedoHex, hexAlbedo } from './material_edits.js';
import { centroid, intensityOf, movedTo, quadAxes, resized, resizedQuad, sizeOf, withIntensity } from './light_shape.js';

const ROWS = [['translate', 'move (m)'], ['rotate_deg', 'rotate (°)'], ['scale', 'scale']];

// Each field's tooltip: what it is, per component (Enter or leaving the field applies it).
const XYZ = ['x', 'y', 'z'];
const RGB = ['red', 'green', 'blue'];
const TIPS = {
  translate: (k) => `Position along ${XYZ[k]} in metres (y is up): where the object's pivot, its centre, stands`,
  rotate_deg: (k) => `Turn about the ${XYZ[k]} axis in degrees (Euler angles, three.js 'XYZ' order)`,
  scale: (k) => `Size factor along the object's own ${XYZ[k]} axis (1: as in the file)`,
  centre: (k) => `The light's centre along ${XYZ[k]} in metres (y is up)`,
  quad: (k) => `The light's ${k ? 'depth (along its last edge)' : 'width (along its first edge)'} in metres: a bigger light gives softer shadows`,
  size: () => 'The light\'s size in metres (twice its farthest corner\'s distance from its centre): a bigger light gives softer shadows',
  radiance: (k) => `Emitted radiance, ${RGB[k]} channel (W/(m² sr)): its colour and brightness`,
  intensity: () => 'The radiance\'s largest channel: typing it scales all three, keeping the colour',
};

export class Inspector {
  // onTransform(id, transform): a typed transform to apply; onLight(lightId, {polygon, radiance}):
  // a typed light.
  // more: {onRename(id, newName), onMaterial(id, material), materials() → [[name, JSON]], materialOf(id),
  // onPaint(id, {albedo?, type?}), paintable(id): a polygon object (a volume is not painted here)}.
  constructor(root, onTransform, onLight, more = {}) {
    this.root = root;
    this.onTransform = onTransform;
    this.onLight = onLight;
    this.more = more;
    this.id = null;
    this.inputs = null;
  }

  // Shows `id` (an object id, "light:ID" or null) with its data: an object's transform, or the light JSON.
  show(id, data) {
    this.id = id;
    this.root.replaceChildren();
    this.inputs = null;
    this.light = null;
    if (!id) {
      this.root.textContent = 'Nothing selected: click an object or a light.';
      return;
    }
    if (id.startsWith('light:')) return this.showLight(id.slice(6), data);
    this.nameRow(id, id);
    this.inputs = {};
    for (const [key, label] of ROWS) this.inputs[key] = this.row(key, label, 3, () => this.typed());
    if (this.more.materials && this.more.materials().length) this.materialRow(id);
    if (this.more.onPaint && this.more.paintable(id)) this.paintRow(id);
    this.update(data);
  }

  // The selection's name (its id): typed and entered, a rename (one undo step).
  nameRow(id, name) {
    const row = document.createElement('div');
    row.className = 'row inspector-row inspector-title';
    const label = document.createElement('span');
    label.textContent = id.startsWith('light:') ? 'light' : 'name';
    const input = document.createElement('input');
    Object.assign(input, { type: 'text', value: name, size: 16 });
    input.dataset.key = 'name';
    input.title = 'The name (id) in the scene: type a new one (letters, digits, _ . -) and press Enter to rename it (one undo step)';
    label.title = input.title;
    input.addEventListener('change', () => {
      const next = input.value.trim();
      if (next && next !== name && this.more.onRename) this.more.onRename(id, next);
      else input.value = name;
    });
    row.append(label, input);
    this.root.append(row);
  }

  // The object's material, one of the scene's (its type and colour in the list): a choice
  // replaces the object in that material (one undo step).
  materialRow(id) {
    const row = document.createElement('div');
    row.className = 'row inspector-row';
    const label = document.createElement('span');
    label.textContent = 'material';
    const select = document.createElement('select');
    select.dataset.key = 'material';
    select.title = 'The object\'s material, one of the scene\'s (type and colour): a choice is one edit, one undo step';
    label.title = select.title;
    const current = this.more.materialOf(id);
    for (const [name, material] of this.more.materials()) {
      const option = document.createElement('option');
      const rgb = (material.albedo || [0.8, 0.8, 0.8]).map((x) => Math.round(255 * Math.min(Math.max(x, 0), 1)));
      option.value = name;
      option.textContent = `${name} (${material.type || 'diffuse'})`;
      option.style.background = `rgb(${rgb.join(',')})`;
      option.style.color = rgb[0] * 0.3 + rgb[1] * 0.6 + rgb[2] * 0.1 > 128 ? '#000' : '#fff';
      select.append(option);
    }
    select.value = current || '';
    select.addEventListener('change', () => this.more.onMaterial(id, select.value));
    row.append(label, select);
    this.root.append(row);
  }

  // The object's colour (albedo) and material type: a change is one edit and one undo step, to its
  // material when only it uses that one, else to a copy of its own (material_edits.js).
  paintRow(id) {
    const row = document.createElement('div');
    row.className = 'row inspector-row';
    const label = document.createElement('span');
    label.textContent = 'colour, type';
    const name = this.more.materialOf(id);
    const body = (name && new Map(this.more.materials()).get(name)) || { albedo: [0.8, 0.8, 0.8] };
    const colour = document.createElement('input');
    Object.assign(colour, { type: 'color', value: albedoHex(body.albedo || [0.8, 0.8, 0.8]) });
    colour.dataset.key = 'albedo';
    colour.title = 'The material\'s colour (albedo, the share of light it reflects per channel): one edit, one undo step. '
      + 'A material other objects share is left to them: this object gets its own copy';
    const type = document.createElement('select');
    type.dataset.key = 'type';
    type.title = 'The material\'s type: diffuse (matte), rough diffuse, conductor (metal) or dielectric (glass); '
      + 'the server render and the view\'s glossy layer follow. One edit, one undo step';
    for (const t of MATERIAL_TYPES) type.append(new Option(t.replace('_', ' '), t));
    type.value = body.type || 'diffuse';
    label.title = colour.title;
    colour.addEventListener('change', () => this.more.onPaint(id, { albedo: hexAlbedo(colour.value) }));
    type.addEventListener('change', () => this.more.onPaint(id, { type: type.value }));
    row.append(label, colour, type);
    this.root.append(row);
  }

  // The fields follow the object (after a drag or another client's edit) unless one is being typed
  // in; for a selected light, `transform` is the light's JSON.
  update(transform) {
    if (!this.inputs || !transform) return;
    if (this.light) return this.updateLight(transform);
    for (const [key] of ROWS) {
      const values = transform[key] || (key === 'scale' ? [1, 1, 1] : [0, 0, 0]);
      this.inputs[key].forEach((field, k) => field.set(values[k]));
    }
  }

  // The fields as a transform: the typed value, and every other exactly as held.
  typed() {
    let bad = false;
    for (const fields of Object.values(this.inputs))
      for (const field of fields) {
        const invalid = !Number.isFinite(field.read());
        field.input.classList.toggle('invalid', invalid);
        bad ||= invalid;
      }
    if (bad) return;
    const transform = {};
    for (const [key] of ROWS) transform[key] = this.inputs[key].map((field) => field.read());
    this.onTransform(this.id, transform);
  }

  // A light's rows: centre (m), size (a parallelogram's width × depth along its edges, else the
  // size of any polygon: scaled about its centre), radiance and intensity (its largest channel:
  // typing it scales the radiance). A change becomes one set_light (onLight(id, {polygon, radiance})).
  showLight(lightId, light) {
    this.nameRow(`light:${lightId}`, lightId);
    this.light = light;
    const quad = light && quadAxes(light.polygon);
    const rows = [['centre', 'centre (m)', 3], quad ? ['quad', 'width × depth (m)', 2] : ['size', 'size (m)', 1],
      ['radiance', 'radiance', 3], ['intensity', 'intensity', 1]];
    this.inputs = {};
    for (const [key, label, count] of rows) this.inputs[key] = this.row(key, label, count, () => this.typedLight(lightId));
    const note = document.createElement('div');
    note.className = 'muted';
    note.textContent = 'Drag the light with the gizmo: W move, E turn, R resize. Each change relights the scene. '
      + 'Duplicate adds a copy beside it, Delete removes it (not the last light).';
    this.root.append(note);
    this.update(light);
  }

  row(key, label, count, onChange) {
    const row = document.createElement('div');
    row.className = 'row inspector-row';
    const name = document.createElement('span');
    name.textContent = label;
    row.append(name);
    const fields = Array.from({ length: count }, (_, k) => new ExactField(`${key}.${k}`, onChange));
    for (const [k, field] of fields.entries()) field.input.title = TIPS[key] ? TIPS[key](k) : label;
    name.title = fields[0].input.title;
    row.append(...fields.map((field) => field.input));
    this.root.append(row);
    return fields;
  }

  // The light's fields from its JSON (unless one is being typed in).
  updateLight(light) {
    this.light = light;
    const quad = quadAxes(light.polygon);
    const values = { centre: centroid(light.polygon), radiance: light.radiance, intensity: [intensityOf(light.radiance)],
      quad: quad ? [quad.width, quad.depth] : null, size: [sizeOf(light.polygon)] };
    for (const [key, fields] of Object.entries(this.inputs))
      if (values[key]) fields.forEach((field, k) => field.set(values[key][k]));
  }

  // The typed fields as a light: the fields that differ from the light's own are applied in order
  // (centre, size, radiance, intensity); a field not typed reads back exactly the light's value, so
  // it changes nothing. Invalid numbers are marked and nothing is sent.
  typedLight(lightId) {
    const read = (key) => this.inputs[key] && this.inputs[key].map((field) => field.read());
    const positive = (key) => key.startsWith('quad') || key.startsWith('size');
    const nonNegative = (key) => key.startsWith('radiance') || key.startsWith('intensity');
    let bad = false;
    for (const fields of Object.values(this.inputs))
      for (const field of fields) {
        const v = field.read();
        const { key } = field.input.dataset;
        const invalid = !Number.isFinite(v) || (positive(key) && v <= 0) || (nonNegative(key) && v < 0);
        field.input.classList.toggle('invalid', invalid);
        bad ||= invalid;
      }
    if (bad || !this.light) return;
    const same = (a, b) => a.every((x, k) => x === b[k]);
    let { polygon, radiance } = this.light;
    const centre = read('centre');
    if (!same(centre, centroid(polygon))) polygon = movedTo(polygon, centre);
    const quad = read('quad'), size = read('size');
    const axes = quadAxes(polygon);
    if (quad && axes && !same(quad, [axes.width, axes.depth])) polygon = resizedQuad(polygon, quad[0], quad[1]);
    if (size && !same(size, [sizeOf(polygon)])) polygon = resized(polygon, size[0]);
    const typedRadiance = read('radiance');
    if (!same(typedRadiance, radiance)) radiance = typedRadiance;
    const intensity = read('intensity')[0];
    if (intensity !== intensityOf(this.light.radiance)) radiance = withIntensity(radiance, intensity);
    this.onLight(lightId, { polygon, radiance });
  }
}
