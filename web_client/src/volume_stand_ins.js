// Stand-ins for the scene's volume objects (SCENE_FORMAT.md "Volume objects"): a holder Group per
// volume, as for polygon objects (the gizmo moves it, `move` edits place it), holding a faint box
// that clicks pick, the grid box as a distinct wireframe, and a coarse point cloud of the
// isosurface (GET .../volumes/ID/preview) that follows the isovalue. The DM mesh has no volume
// occluders: the volumes' shadows are in the server's image only (the page says so).
import * as THREE from 'three';

export const VOLUME_COLOUR = 0x36c5f0;

// The grid box's geometry in object space: the unit cube mapped by the box's three edges (`axes`).
function boxGeometry(axes) {
  const geometry = new THREE.BoxGeometry(1, 1, 1).translate(0.5, 0.5, 0.5);
  const [a, b, c] = axes.map((v) => new THREE.Vector3(...v));
  geometry.applyMatrix4(new THREE.Matrix4().makeBasis(a, b, c));
  return geometry;
}

// The holder of volume `object` (scene JSON) with `info` (GET scene's volumes[i]).
export function volumeHolder(object, info) {
  const holder = new THREE.Group();
  holder.name = object.id;
  const geometry = boxGeometry(info.axes);
  geometry.computeBoundingBox();
  const pivot = geometry.boundingBox.getCenter(new THREE.Vector3());
  holder.userData = { objectId: object.id, static: false, locked: false, volume: true, pivot, info };
  // children[0] is what picking, bounds and the selection outline use (as for polygon objects).
  const pick = new THREE.Mesh(geometry, new THREE.MeshBasicMaterial({
    color: VOLUME_COLOUR, transparent: true, opacity: 0.06, depthWrite: false, side: THREE.DoubleSide }));
  pick.userData.objectId = object.id;
  const wire = new THREE.LineSegments(new THREE.EdgesGeometry(geometry), new THREE.LineDashedMaterial({
    color: VOLUME_COLOUR, dashSize: 0.08, gapSize: 0.05 }));
  wire.computeLineDistances();
  wire.name = 'volume-box';
  const points = new THREE.Points(new THREE.BufferGeometry(), new THREE.PointsMaterial({
    size: 2.5, sizeAttenuation: false, vertexColors: true }));
  points.name = 'volume-surface';
  for (const child of [pick, wire, points]) {
    child.position.copy(pivot).negate();
    holder.add(child);
  }
  return holder;
}

// Shading of a preview point by its normal: a fixed key light from above and in front, so the
// cloud reads as a surface.
const KEY = new THREE.Vector3(0.3, 0.9, 0.4).normalize();

// Puts a preview ({points, normals}: flat object-space arrays) into a volume holder.
export function setVolumeSurface(holder, preview) {
  const points = holder.getObjectByName('volume-surface');
  if (!points) return;
  const colours = new Float32Array(preview.points.length);
  const base = new THREE.Color(VOLUME_COLOUR);
  const n = new THREE.Vector3();
  for (let i = 0; i < colours.length; i += 3) {
    n.set(preview.normals[i], preview.normals[i + 1], preview.normals[i + 2]);
    const shade = 0.35 + 0.65 * Math.abs(n.dot(KEY));
    colours[i] = base.r * shade;
    colours[i + 1] = base.g * shade;
    colours[i + 2] = base.b * shade;
  }
  points.geometry.dispose();
  points.geometry = new THREE.BufferGeometry();
  points.geometry.setAttribute('position', new THREE.Float32BufferAttribute(preview.points, 3));
  points.geometry.setAttribute('color', new THREE.Float32BufferAttribute(colours, 3));
  holder.userData.previewIsovalue = preview.isovalue;
  holder.userData.previewPoints = preview.points.length / 3;
}
