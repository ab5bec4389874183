// The view's WebGL2 context, made by a classic script at the end of the page's body so that the
// GPU process creates it (SwiftShader: ~0.4 s) while the page's modules are still loading;
// scene_view.js takes it over (window.penumbraGL) or calls makeWebGLContext itself.
// ?antialias=on|off overrides the choice by renderer (to compare frame times).
/* exported makeWebGLContext */
const SOFTWARE_GL = /swiftshader|llvmpipe|softpipe|lavapipe|software/i;

// The WebGL renderer's name (WEBGL_debug_renderer_info) and whether it rasterises in software,
// where MSAA costs about twice the frame time (SwiftShader, 150 cubes at 1280×800: 120 ms a
// frame antialiased, 65 ms without).
function rendererOf(gl) {
  if (!gl) return { renderer: 'no WebGL', software: false, name: 'no WebGL' };
  const info = gl.getExtension('WEBGL_debug_renderer_info');
  const renderer = String(gl.getParameter(info ? info.UNMASKED_RENDERER_WEBGL : gl.RENDERER));
  const software = renderer.match(SOFTWARE_GL);
  return { renderer, software: !!software, name: software ? software[0] : renderer.slice(0, 40) };
}

// antialias: 'auto' (on unless the GL is software), 'on' or 'off'. Three.js always asks for an
// alpha channel, hence a context of our own: opaque (the background is black), not kept once
// shown (nothing reads it after the frame: timeFrames reads pixels in the drawing task,
// screenshots read the compositor), and on a software GL desynchronized (low latency): each cuts
// the compositor's work per frame (SwiftShader, 150 cubes at half resolution, frames drawn a
// second in a requestAnimationFrame loop: 18.7 before, 26.4 with all three; an empty scene
// 45 → 58). The first context is made as a software GL wants it and kept there; a GPU gets a
// second one with its own choices, which costs it nothing. The canvas is sized (the container's
// size) before its context is made: every resize, even to the same size, makes SwiftShader
// allocate a new drawing buffer (~0.2 s at 940 × 800).
function makeWebGLContext(antialias, container) {
  const width = Math.max(1, container.clientWidth);
  const height = Math.max(1, container.clientHeight);
  const attributes = { alpha: false, depth: true, stencil: false, preserveDrawingBuffer: false };
  const sizedCanvas = () => {
    const canvas = document.createElement('canvas');
    Object.assign(canvas, { width, height });
    Object.assign(canvas.style, { width: `${width}px`, height: `${height}px` });
    return canvas;
  };
  let canvas = sizedCanvas();
  let context = canvas.getContext('webgl2', { ...attributes, antialias: antialias === 'on', desynchronized: true });
  const probe = rendererOf(context);
  const wantAntialias = antialias === 'auto' ? !probe.software : antialias === 'on';
  if (context && !probe.software) {
    const lose = context.getExtension('WEBGL_lose_context');
    if (lose) lose.loseContext();
    canvas = sizedCanvas();
    context = canvas.getContext('webgl2', { ...attributes, antialias: wantAntialias, desynchronized: false });
  }
  return { canvas, context, antialias, gl: { ...probe, antialias: wantAntialias } };
}

(function early() {
  const query = new URLSearchParams(window.location.search).get('antialias');
  const antialias = ['on', 'off'].includes(query) ? query : 'auto';
  window.penumbraGL = makeWebGLContext(antialias, document.getElementById('viewport'));
}());
