// The scene the page shows, as far as the page knows it: its id and name, the server's scene JSON
// last taken in, and the newest version known (the one the undo steps lead to). Taking in a new
// scene JSON (adopt) is announced as the hub's `scene`.

export class SceneState {
  constructor(hub) {
    this.hub = hub;
    this.id = null;
    this.name = null;
    this.json = null; // the scene JSON as the server last sent it
    this.version = null;
  }

  // The scene as the server sent it ({scene, volumes: the volumes' grid info, ...}).
  adopt(wrapped) {
    this.json = wrapped.scene;
    this.hub.emit('scene', wrapped);
  }
}
