// Frames (docs/SCENE_FORMAT.md "Edit scripts") for the page's structural edits: a box primitive,
// a duplicate, a delete, an added or deleted light, and the frame that takes a scene back to its
// source. Pure functions of scene JSON; the page sends them and keeps their inverses for undo.

// An id not used by the scene's objects (list 'objects') or lights ('lights'): base, else
// base_2, base_3, ...
export function freshId(scene, base, list = 'objects') {
  const used = new Set((scene[list] || []).map((o) => o.id));
  if (!used.has(base)) return base;
  for (let n = 2; ; ++n) if (!used.has(`${base}_${n}`)) return `${base}_${n}`;
}

// An axis-aligned box of `size` (metres) centred on its origin, placed at `at`: six quads,
// counter-clockwise seen from outside (the format's front side).
export function boxObject(id, at, size, material) {
  const [hx, hy, hz] = size.map((s) => s / 2);
  const vertices = [];
  for (const z of [-hz, hz]) for (const y of [-hy, hy]) for (const x of [-hx, hx]) vertices.push([x, y, z]);
  // vertex index = x + 2y + 4z (each 0 or 1)
  const faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 4, 6, 2], [1, 3, 7, 5], [0, 1, 5, 4], [2, 6, 7, 3]];
  const object = { id, vertices, faces, transform: { translate: [...at], rotate_deg: [0, 0, 0], scale: [1, 1, 1] } };
  if (material) object.material = material;
  return object;
}

// A copy of `object` under a new id, moved by `offset` metres.
export function duplicateObject(object, id, offset) {
  const copy = JSON.parse(JSON.stringify(object));
  copy.id = id;
  delete copy.static;
  const t = (copy.transform && copy.transform.translate) || [0, 0, 0];
  copy.transform = { ...(copy.transform || {}), translate: t.map((x, k) => x + offset[k]) };
  return copy;
}

// {redo, undo} edits of one structural change.
// A volume object ("type": "volume") is added by add_volume (its file one the server holds).
export const addOp = (object) => (object.type === 'volume' ? { op: 'add_volume', volume: object } : { op: 'add', object });
export const addEdits = (object) => ({ redo: [addOp(object)], undo: [{ op: 'remove', id: object.id }] });
export const removeEdits = (object) => ({ redo: [{ op: 'remove', id: object.id }], undo: [addOp(object)] });
// A light's: the inverse of add_light is remove_light, and remove_light's carries the whole light.
const lightOf = ({ id, polygon, radiance }) => ({ id, polygon, radiance });
export const addLightEdits = (light) => ({ redo: [{ op: 'add_light', light: lightOf(light) }], undo: [{ op: 'remove_light', id: light.id }] });
export const removeLightEdits = (light) => ({ redo: [{ op: 'remove_light', id: light.id }], undo: [{ op: 'add_light', light: lightOf(light) }] });

// A rename: the object added under its new id, then the old one removed (one frame; the engine
// has no rename, and the new id's object shadows exactly as the old one did).
export const renameEdits = (object, id) => ({
  redo: [addOp({ ...object, id }), { op: 'remove', id: object.id }],
  undo: [addOp(object), { op: 'remove', id }],
});
export const renameLightEdits = (light, id) => ({
  redo: [{ op: 'add_light', light: lightOf({ ...light, id }) }, { op: 'remove_light', id: light.id }],
  undo: [{ op: 'add_light', light: lightOf(light) }, { op: 'remove_light', id }],
});
// Another of the scene's materials for an object: it is replaced (removed and added) in one frame.
export const materialEdits = (object, material) => ({
  redo: [{ op: 'remove', id: object.id }, addOp({ ...object, material })],
  undo: [{ op: 'remove', id: object.id }, addOp(object)],
});

// A copy of `light` under a new id, its polygon moved by `offset` metres.
export function lightCopy(light, id, offset) {
  return { id, polygon: light.polygon.map((p) => p.map((x, k) => x + offset[k])), radiance: [...light.radiance] };
}

const lightsById = (scene) => new Map((scene.lights || []).map((l) => [l.id, l]));

// One frame taking `current` back to `source`: objects added since are removed, removed ones
// added back, moved ones moved back (by transform; an object whose geometry changed is replaced),
// edited lights set back (set_light), lights added since removed and removed ones added back
// (additions first: the frame never leaves the scene without a light).
export function resetEdits(current, source) {
  const now = new Map(current.objects.map((o) => [o.id, o]));
  const then = new Map(source.objects.map((o) => [o.id, o]));
  const edits = [];
  const same = (a, b) => JSON.stringify(a) === JSON.stringify(b);
  for (const [id, object] of now) {
    const original = then.get(id);
    const volume = object.type === 'volume' && original && original.type === 'volume';
    if (!original) edits.push({ op: 'remove', id });
    else if (!same({ ...object, transform: null, isovalue: null }, { ...original, transform: null, isovalue: null })
      || (!volume && object.isovalue !== original.isovalue)) edits.push({ op: 'remove', id }, addOp(original));
    else {
      if (!same(object.transform || {}, original.transform || {})) edits.push({ op: 'move', id, transform: original.transform || {} });
      if (volume && object.isovalue !== original.isovalue) edits.push({ op: 'set_volume', id, isovalue: original.isovalue });
    }
  }
  for (const [id, object] of then) if (!now.has(id)) edits.push(addOp(object));
  const lightsNow = lightsById(current), lightsThen = lightsById(source);
  for (const [id, light] of lightsThen) if (!lightsNow.has(id)) edits.push({ op: 'add_light', light: lightOf(light) });
  for (const id of lightsNow.keys()) if (!lightsThen.has(id)) edits.push({ op: 'remove_light', id });
  for (const light of source.lights || []) {
    const lit = lightsNow.get(light.id);
    if (!lit) continue;
    const edit = { op: 'set_light', id: light.id };
    if (!same(lit.polygon, light.polygon)) edit.polygon = light.polygon;
    if (!same(lit.radiance, light.radiance)) edit.radiance = light.radiance;
    if (edit.polygon || edit.radiance) edits.push(edit);
  }
  return edits;
}
