// Editing an object's material from the inspector (its colour and type) as one frame and one undo
// step. A material only this object uses is changed in place (`set_material`: no shadow work, the
// page recolours its mesh); a shared one (or the default) is left to the other objects, and this
// object gets its own copy under a fresh name (`set_material` adding it, the object re-added in it).
// Pure functions over scene JSON v1.
import { materialEdits } from './object_edits.js';

export const MATERIAL_TYPES = ['diffuse', 'rough_diffuse', 'conductor', 'dielectric'];
const DEFAULT_BODY = { albedo: [0.8, 0.8, 0.8] };
// Keys each type takes besides albedo and type (SCENE_FORMAT.md "materials"): the others are
// dropped when the type changes, as the server refuses them.
const TYPE_KEYS = {
  diffuse: [],
  rough_diffuse: ['roughness', 'ndf', 'scattering'],
  conductor: ['roughness', 'ndf', 'scattering', 'eta', 'k'],
  dielectric: ['roughness', 'ndf', 'scattering', 'ior'],
};

// The material's body with `change` ({albedo?, type?}) applied, keeping the keys its type takes.
export function changedMaterial(body, change) {
  const type = change.type || body.type || 'diffuse';
  const out = { albedo: [...(change.albedo || body.albedo || DEFAULT_BODY.albedo)] };
  if (type !== 'diffuse') out.type = type;
  for (const key of TYPE_KEYS[type]) if (body[key] !== undefined) out[key] = body[key];
  return out;
}

function freshMaterialId(scene, base) {
  const used = new Set(Object.keys(scene.materials || {}));
  if (!used.has(base)) return base;
  for (let n = 2; ; ++n) if (!used.has(`${base}_${n}`)) return `${base}_${n}`;
}

// {redo, undo} frames giving `object` (its JSON as it stands) the material change, or null when
// nothing changes.
export function objectMaterialEdits(scene, object, change) {
  const name = object.material || '';
  const body = (name && scene.materials && scene.materials[name]) || DEFAULT_BODY;
  const next = changedMaterial(body, change);
  if (JSON.stringify(next) === JSON.stringify(changedMaterial(body, {}))) return null;
  const users = (scene.objects || []).filter((o) => (o.material || '') === name).length;
  if (name && users === 1)
    return { redo: [{ op: 'set_material', id: name, material: next }], undo: [{ op: 'set_material', id: name, material: body }] };
  const id = freshMaterialId(scene, `${object.id}_material`);
  const own = materialEdits(object, id);
  return { redo: [{ op: 'set_material', id, material: next }, ...own.redo], undo: own.undo, material: id };
}

// '#rrggbb' of a linear albedo shown as stored (no sRGB: the picker edits the numbers).
export const albedoHex = (albedo) => `#${albedo.map((x) => Math.round(255 * Math.min(Math.max(x, 0), 1)).toString(16).padStart(2, '0')).join('')}`;
export const hexAlbedo = (hex) => [1, 3, 5].map((i) => Number.parseInt(hex.slice(i, i + 2), 16) / 255);
