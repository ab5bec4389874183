// Frames of a drag from a cached picture of what did not change. While an object is dragged the
// camera stands still and most of the scene stays as it was (150 cubes: over a whole drag of one
// cube, 10 of 715 mesh parts, 6 000 of 75 000 triangles, ever change), yet a frame draws it all
// again. A FrameCache keeps the unchanged opaque objects drawn once in a render target (colour and
// depth) and draws each frame as that picture (its depth restored) plus the objects that changed
// since the drag began. Owned by the SceneView; used between begin() and end() only, and only on a
// canvas without antialiasing: a picture of resolved pixels cannot stand in for the samples of
// an antialiased one (where a changed and an unchanged object share a pixel, 2% of the pixels of
// a 15-cube drag came out up to 104 of 255 off).
import * as THREE from 'three';

// Above this share of the triangles changed, the cache saves too little to be worth its upkeep
// (a frame from the cache costs the changed objects plus one textured rectangle; the picture is
// drawn again only when an object in it changes, at most once per object in a drag). 15 cubes:
// 59% of the triangles change in a drag of one cube (the floor's few chunks); 150 cubes: 8%.
const HOT_SHARE_LIMIT = 0.75;

const COMPOSITE_VERTEX = `
varying vec2 vUv;
void main() {
  vUv = uv;
  gl_Position = vec4(position.xy, 0.0, 1.0);
}`;

// The cached colour (the target is sRGB: the sample is linear, encoded for the screen as any
// material's output) and its depth, written as this pixel's depth so later objects are hidden
// behind the cached ones exactly as in a whole frame.
const COMPOSITE_FRAGMENT = `
uniform sampler2D colourMap;
uniform sampler2D depthMap;
varying vec2 vUv;
void main() {
  gl_FragColor = texture2D(colourMap, vUv);
  gl_FragDepth = texture2D(depthMap, vUv).x;
  #include <colorspace_fragment>
}`;

const drawable = (o) => o.isMesh || o.isLine || o.isPoints || o.isSprite;

function versionsOf(geometry) {
  let versions = geometry.index ? geometry.index.version : 0;
  for (const name in geometry.attributes) versions += geometry.attributes[name].version;
  return versions;
}

// What an object's pixels depend on besides the camera: geometry (and its buffers' versions),
// material (and its version), where it is.
function stateOf(object) {
  const { geometry, material } = object;
  return { geometry, versions: versionsOf(geometry), material, materialVersion: material.version, matrix: object.matrixWorld.elements.slice() };
}

// Whether `object` is as `state` recorded it (allocates nothing: it runs for every object each frame).
function unchanged(state, object) {
  const { geometry, material } = object;
  if (state.geometry !== geometry || state.material !== material || state.materialVersion !== material.version
    || state.versions !== versionsOf(geometry)) return false;
  const m = object.matrixWorld.elements;
  for (let i = 0; i < 16; ++i) if (state.matrix[i] !== m[i]) return false;
  return true;
}

const trianglesOf = (object) => {
  const g = object.geometry;
  return (g.index ? g.index.count : g.attributes.position ? g.attributes.position.count : 0) / 3;
};

// Drawn through the cache: none transparent (blended over what is behind it, drawn after the
// opaque objects anyway) or refracting (three.js's transmission pass must see the opaque ones).
const cacheable = (object) => {
  const m = object.material;
  return !Array.isArray(m) && !m.transparent && !(m.transmission > 0);
};

// Leaves `objects` out of the frames drawn until the returned function is called. By their layers,
// not `visible`, which some objects set again as they are drawn (TransformControls' handles, in
// its updateMatrixWorld: hidden that way, the drag's axis line was drawn twice).
function hide(objects) {
  const masks = [];
  for (const o of objects) {
    masks.push(o.layers.mask);
    o.layers.mask = 0;
  }
  return () => {
    let i = 0;
    for (const o of objects) o.layers.mask = masks[i++];
  };
}

export class FrameCache {
  constructor(renderer) {
    this.renderer = renderer;
    this.target = null; // WebGLRenderTarget with a DepthTexture, at the drawing buffer's size
    this.composite = new THREE.Mesh(new THREE.PlaneGeometry(2, 2), new THREE.ShaderMaterial({
      vertexShader: COMPOSITE_VERTEX, fragmentShader: COMPOSITE_FRAGMENT,
      uniforms: { colourMap: { value: null }, depthMap: { value: null } },
      depthTest: true, depthFunc: THREE.AlwaysDepth, depthWrite: true, toneMapped: false,
    }));
    this.composite.frustumCulled = false;
    this.compositeScene = new THREE.Scene();
    this.compositeScene.add(this.composite);
    this.compositeCamera = new THREE.OrthographicCamera(-1, 1, 1, -1, 0, 1);
    this.active = false;
    this.stats = { cached: 0, rebuilt: 0, direct: 0 }; // frames drawn each way during drags, since the page loaded
    this.end();
  }

  // A drag starts: from its second frame on, what changes is drawn over the cached rest.
  begin() {
    this.end();
    this.active = true;
  }

  // The drag ended: frames are drawn whole again (the cache's target is kept for the next drag).
  end() {
    this.active = false;
    this.seen = new Map(); // object → its state when first drawn in this drag
    this.hot = new Set(); // objects changed (or new) since the drag's first frame
    this.members = null; // Set of the objects in the cached picture, or null
    this.view = null; // the camera and size the picture was drawn for
    this.frame = 0;
    this.hotShare = 0; // the share of the last frame's triangles drawn over the picture
  }

  // Draws `scene` as seen by `camera` (the renderer's own render when not active, or when the
  // cache would not pay). Returns how: 'direct', 'rebuilt' (the picture drawn again) or 'cached'.
  render(scene, camera) {
    if (!this.active) return this.direct(scene, camera);
    const how = this.draw(scene, camera);
    ++this.stats[how];
    return how;
  }

  direct(scene, camera) {
    this.renderer.render(scene, camera);
    return 'direct';
  }

  draw(scene, camera) {
    scene.updateMatrixWorld();
    if (camera.parent === null) camera.updateMatrixWorld();
    const size = this.renderer.getDrawingBufferSize(new THREE.Vector2());
    const view = [...camera.matrixWorld.elements, ...camera.projectionMatrix.elements, size.x, size.y];
    if (this.view && view.some((x, i) => x !== this.view[i])) this.begin(); // moved or resized: start again
    this.view = view;
    const objects = [];
    let refracting = false;
    scene.traverseVisible((o) => {
      if (!drawable(o)) return;
      objects.push(o);
      if (o.material && o.material.transmission > 0) refracting = true;
    });
    const first = this.frame++ === 0;
    let total = 0, hotTriangles = 0;
    const cold = new Set();
    for (const o of objects) {
      const before = this.seen.get(o);
      if (!before) {
        this.seen.set(o, stateOf(o));
        if (!first) this.hot.add(o);
      } else if (!this.hot.has(o) && !unchanged(before, o)) {
        this.hot.add(o);
      }
      const n = trianglesOf(o);
      total += n;
      if (this.hot.has(o) || !cacheable(o)) hotTriangles += n;
      else cold.add(o);
    }
    this.forgetGone(objects);
    this.hotShare = total ? hotTriangles / total : 0;
    // The drag's first frame only records what is there: the cache starts from what then stays.
    if (first || refracting || hotTriangles > HOT_SHARE_LIMIT * total) return this.direct(scene, camera);
    let how = 'cached';
    if (!this.members || this.members.size !== cold.size || [...cold].some((o) => !this.members.has(o))) {
      this.drawPicture(scene, camera, objects, cold, size);
      how = 'rebuilt';
    }
    this.drawOver(scene, camera, cold);
    return how;
  }

  // Drops what the drag saw of objects no longer drawn (each delta replaces a few batches: kept, a
  // long drag would hold on to every geometry it replaced). One that comes back counts as new.
  forgetGone(objects) {
    if (this.seen.size <= objects.length + 64) return;
    const present = new Set(objects);
    for (const o of this.seen.keys()) {
      if (present.has(o)) continue;
      this.seen.delete(o);
      this.hot.delete(o);
    }
  }

  // The cold objects alone into the target.
  drawPicture(scene, camera, objects, cold, size) {
    if (!this.target || this.target.width !== size.x || this.target.height !== size.y) {
      if (this.target) this.target.dispose();
      this.target = new THREE.WebGLRenderTarget(size.x, size.y, {
        minFilter: THREE.NearestFilter, magFilter: THREE.NearestFilter, generateMipmaps: false,
        colorSpace: THREE.SRGBColorSpace, depthTexture: new THREE.DepthTexture(size.x, size.y),
      });
      this.composite.material.uniforms.colourMap.value = this.target.texture;
      this.composite.material.uniforms.depthMap.value = this.target.depthTexture;
    }
    const restore = hide(objects.filter((o) => !cold.has(o)));
    const previous = this.renderer.getRenderTarget();
    this.renderer.setRenderTarget(this.target);
    this.renderer.render(scene, camera);
    this.renderer.setRenderTarget(previous);
    restore();
    this.members = cold;
  }

  // The picture with its depth, then the other objects over it, as the scene draws them.
  drawOver(scene, camera, cold) {
    const { renderer } = this;
    renderer.render(this.compositeScene, this.compositeCamera);
    const restore = hide(cold);
    const { background } = scene;
    const autoClear = renderer.autoClear;
    scene.background = null; // a colour background would clear the picture
    renderer.autoClear = false;
    renderer.render(scene, camera);
    renderer.autoClear = autoClear;
    scene.background = background;
    restore();
  }
}
