// Starts the scene's two downloads (GET /api/scenes/ID and its binary mesh) as the page opens,
// before its modules (three.js: ~1.5 MB to fetch and parse) have loaded; main.js picks them up.
// A classic script, so it runs at once: window.penumbraPrefetch = {sceneId, scene, mesh} (fetch
// promises), or {sceneId: null} when the page has no ?scene= (main.js then asks for the list).
(function prefetch() {
  const id = new URLSearchParams(window.location.search).get('scene');
  if (!id) {
    window.penumbraPrefetch = { sceneId: null };
    return;
  }
  const path = `/api/scenes/${encodeURIComponent(id)}`;
  const quiet = (promise) => { promise.catch(() => {}); return promise; }; // main.js reports failures
  window.penumbraPrefetch = { sceneId: id, scene: quiet(fetch(path)), mesh: quiet(fetch(`${path}/mesh?format=bin`)) };
}());
