// Decodes the server's binary mesh (docs/API.md "Binary", magic PNMB, layout 4: parts, with flag 2 their indirect light, each one display
// chunk of one receiver, and in a delta value parts, a held part's new irradiance alone; a part's irradiance is r, g, b or one value per
// vertex times the part's tint) into typed arrays viewing the response buffer in place (a one-channel irradiance expanded to r, g, b).
// Throws an Error naming what is malformed.

const MAGIC = 'PNMB';
const LAYOUT_VERSION = 4;
const HEADER_BYTES = 44;
const PART_RECORD_BYTES = 56;
const VALUE_PART_RECORD_BYTES = 40;
const REMOVED_RECORD_BYTES = 16;
const FLAG_DELTA = 1;
const FLAG_INDIRECT = 2; // each part's irradiance is followed by its indirect irradiance (mesh?indirect=1)

export const CLASS_LIT = 0;
export const CLASS_PENUMBRA = 1;
export const CLASS_UMBRA = 2;

// A receiver is one face of one object; the union of its parts.
export function receiverKey(object, face) {
  return `${object}/${face}`;
}

// A part is the receiver's mesh inside one chunk (x, y) of the face's plane.
export function partKey(object, face, x, y) {
  return `${object}/${face}/${x}/${y}`;
}

const pad4 = (n) => (n + 3) & ~3;

// A record's channel count C (1 or 3) and tint (f32 r, g, b) at `offset`.
function readTint(view, offset, what) {
  const channels = view.getUint32(offset, true);
  if (channels !== 1 && channels !== 3) throw new Error(`binary mesh: ${what} has ${channels} channels (1 or 3)`);
  return { channels, tint: [view.getFloat32(offset + 4, true), view.getFloat32(offset + 8, true), view.getFloat32(offset + 12, true)] };
}

// A part's irradiance, r, g, b per vertex: the C·V floats at `offset` as they are (C = 3), or each
// value times the tint, rounded to f32 as the server's bound assumes (C = 1; exact for tint 1).
function irradianceOf(buffer, offset, { channels, tint }, v) {
  const values = new Float32Array(buffer, offset, channels * v);
  if (channels === 3) return values;
  const rgb = new Float32Array(3 * v);
  for (let i = 0; i < v; ++i) {
    rgb[3 * i] = values[i] * tint[0];
    rgb[3 * i + 1] = values[i] * tint[1];
    rgb[3 * i + 2] = values[i] * tint[2];
  }
  return rgb;
}

export function decodeMeshBinary(buffer) {
  const view = new DataView(buffer);
  const need = (offset, bytes, what) => {
    if (offset + bytes > buffer.byteLength)
      throw new Error(`binary mesh: truncated at ${what} (needs byte ${offset + bytes}, has ${buffer.byteLength})`);
  };
  need(0, HEADER_BYTES, 'header');
  const magic = String.fromCharCode(...new Uint8Array(buffer, 0, 4));
  if (magic !== MAGIC) throw new Error(`binary mesh: bad magic '${magic}'`);
  const u32 = (offset) => view.getUint32(offset, true);
  const i32 = (offset) => view.getInt32(offset, true);
  if (u32(4) !== LAYOUT_VERSION)
    throw new Error(`binary mesh: unsupported layout version ${u32(4)} (this page reads layout ${LAYOUT_VERSION})`);
  const header = {
    sceneVersion: u32(8), delta: (u32(12) & FLAG_DELTA) !== 0, indirect: (u32(12) & FLAG_INDIRECT) !== 0, since: u32(16),
    names: u32(20), partCount: u32(24), removedCount: u32(28), totalVertices: u32(32), totalTriangles: u32(36),
    valuePartCount: u32(40),
  };

  let offset = HEADER_BYTES;
  const decoder = new TextDecoder();
  const names = [];
  for (let i = 0; i < header.names; ++i) {
    need(offset, 4, `name ${i}`);
    const length = u32(offset);
    need(offset + 4, length, `name ${i}`);
    names.push(decoder.decode(new Uint8Array(buffer, offset + 4, length)));
    offset += 4 + pad4(length);
  }
  const name = (index, what) => {
    if (index >= names.length) throw new Error(`binary mesh: ${what} names object ${index} of ${names.length}`);
    return names[index];
  };

  need(offset, header.partCount * PART_RECORD_BYTES + header.valuePartCount * VALUE_PART_RECORD_BYTES +
    header.removedCount * REMOVED_RECORD_BYTES, 'records');
  const parts = [];
  for (let p = 0; p < header.partCount; ++p, offset += PART_RECORD_BYTES) {
    const object = name(u32(offset), `part ${p}`);
    const face = u32(offset + 4);
    const chunk = [i32(offset + 8), i32(offset + 12)];
    const key = partKey(object, face, ...chunk);
    parts.push({
      object, face, chunk, key, receiverKey: receiverKey(object, face),
      vertexCount: u32(offset + 16), triangleCount: u32(offset + 20), sceneVersion: u32(offset + 24),
      normal: [view.getFloat32(offset + 28, true), view.getFloat32(offset + 32, true), view.getFloat32(offset + 36, true)],
      ...readTint(view, offset + 40, `part ${key}`),
    });
  }
  // Value parts: a part the page holds whose irradiance alone changed.
  const valueParts = [];
  for (let p = 0; p < header.valuePartCount; ++p, offset += VALUE_PART_RECORD_BYTES) {
    const object = name(u32(offset), `value part ${p}`);
    const face = u32(offset + 4);
    const chunk = [i32(offset + 8), i32(offset + 12)];
    const key = partKey(object, face, ...chunk);
    valueParts.push({
      object, face, chunk, key, receiverKey: receiverKey(object, face),
      vertexCount: u32(offset + 16), sceneVersion: u32(offset + 20), ...readTint(view, offset + 24, `value part ${key}`),
    });
  }
  const removedParts = [];
  for (let d = 0; d < header.removedCount; ++d, offset += REMOVED_RECORD_BYTES) {
    const object = name(u32(offset), `removed ${d}`);
    const face = u32(offset + 4);
    const chunk = [i32(offset + 8), i32(offset + 12)];
    removedParts.push({ object, face, chunk, key: partKey(object, face, ...chunk), receiverKey: receiverKey(object, face) });
  }
  let vertices = 0, triangles = 0;
  for (const part of parts) {
    const v = part.vertexCount;
    const t = part.triangleCount;
    need(offset, (header.indirect ? 24 : 12) * v + 4 * part.channels * v + pad4(v) + 12 * t, `part ${part.key} arrays`);
    part.positions = new Float32Array(buffer, offset, 3 * v);
    offset += 12 * v;
    part.irradiance = irradianceOf(buffer, offset, part, v);
    offset += 4 * part.channels * v;
    if (header.indirect) {
      part.indirect = new Float32Array(buffer, offset, 3 * v);
      offset += 12 * v;
    }
    part.classes = new Uint8Array(buffer, offset, v);
    offset += pad4(v);
    part.indices = new Uint32Array(buffer, offset, 3 * t);
    offset += 12 * t;
    for (let i = 0; i < part.indices.length; ++i)
      if (part.indices[i] >= v) throw new Error(`binary mesh: part ${part.key} index ${part.indices[i]} ≥ ${v} vertices`);
    vertices += v;
    triangles += t;
  }
  for (const part of valueParts) {
    const v = part.vertexCount;
    need(offset, 4 * part.channels * v, `value part ${part.key} irradiance`);
    part.irradiance = irradianceOf(buffer, offset, part, v);
    offset += 4 * part.channels * v;
  }
  if (offset !== buffer.byteLength) throw new Error(`binary mesh: ${buffer.byteLength - offset} bytes after the last part`);
  if (vertices !== header.totalVertices || triangles !== header.totalTriangles)
    throw new Error(`binary mesh: header totals ${header.totalVertices} vertices, ${header.totalTriangles} triangles; parts hold ${vertices}, ${triangles}`);
  return { ...header, parts, valueParts, removedParts, bytes: buffer.byteLength };
}
