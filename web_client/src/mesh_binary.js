// Decodes the server's binary mesh (docs/API.md "Binary", magic PNMB, layout 1) into typed
// arrays viewing the response buffer in place. Throws an Error naming what is malformed.

const MAGIC = 'PNMB';
const LAYOUT_VERSION = 1;
const HEADER_BYTES = 40;
const RECEIVER_RECORD_BYTES = 32;
const REMOVED_RECORD_BYTES = 8;

export const CLASS_LIT = 0;
export const CLASS_PENUMBRA = 1;
export const CLASS_UMBRA = 2;

export function receiverKey(object, face) {
  return `${object}/${face}`;
}

const pad4 = (n) => (n + 3) & ~3;

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
  if (u32(4) !== LAYOUT_VERSION) throw new Error(`binary mesh: unsupported layout version ${u32(4)}`);
  const header = {
    sceneVersion: u32(8), delta: (u32(12) & 1) !== 0, since: u32(16),
    names: u32(20), receivers: u32(24), removed: u32(28), totalVertices: u32(32), totalTriangles: u32(36),
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

  need(offset, header.receivers * RECEIVER_RECORD_BYTES + header.removed * REMOVED_RECORD_BYTES, 'records');
  const receivers = [];
  for (let r = 0; r < header.receivers; ++r, offset += RECEIVER_RECORD_BYTES) {
    const object = name(u32(offset), `receiver ${r}`);
    const face = u32(offset + 4);
    receivers.push({
      object, face, key: receiverKey(object, face),
      vertexCount: u32(offset + 8), triangleCount: u32(offset + 12), sceneVersion: u32(offset + 16),
      normal: [view.getFloat32(offset + 20, true), view.getFloat32(offset + 24, true), view.getFloat32(offset + 28, true)],
    });
  }
  const removed = [];
  for (let d = 0; d < header.removed; ++d, offset += REMOVED_RECORD_BYTES) {
    const object = name(u32(offset), `removed ${d}`);
    const face = u32(offset + 4);
    removed.push({ object, face, key: receiverKey(object, face) });
  }
  for (const receiver of receivers) {
    const v = receiver.vertexCount;
    const t = receiver.triangleCount;
    need(offset, 24 * v + pad4(v) + 12 * t, `receiver ${receiver.key} arrays`);
    receiver.positions = new Float32Array(buffer, offset, 3 * v);
    offset += 12 * v;
    receiver.irradiance = new Float32Array(buffer, offset, 3 * v);
    offset += 12 * v;
    receiver.classes = new Uint8Array(buffer, offset, v);
    offset += pad4(v);
    receiver.indices = new Uint32Array(buffer, offset, 3 * t);
    offset += 12 * t;
    for (let i = 0; i < receiver.indices.length; ++i)
      if (receiver.indices[i] >= v) throw new Error(`binary mesh: receiver ${receiver.key} index ${receiver.indices[i]} ≥ ${v} vertices`);
  }
  if (offset !== buffer.byteLength) throw new Error(`binary mesh: ${buffer.byteLength - offset} bytes after the last receiver`);
  return { ...header, receivers, removedReceivers: removed, bytes: buffer.byteLength };
}
