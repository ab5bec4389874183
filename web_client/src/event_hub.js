// The page's events: a module says what changed (hub.emit), the panels that care subscribe
// (hub.on) and update themselves, so the one that announces knows nothing of who listens. The
// names are fixed (EVENTS): a misspelt one throws instead of going unheard. Handlers run in the
// order they subscribed, synchronously.

// Each event with what it passes:
export const EVENTS = {
  scene: 'the server\'s scene taken in (wrapped: {id, name, version, scene, volumes})',
  renamed: 'the scene on show has a new name (the name)',
  selection: 'the selection changed (an object id, "light:ID" or null)',
  version: 'a mesh version was applied to the view (the decoded mesh)',
  standIns: 'the objects\' stand-ins were built again (the scene JSON)',
  synced: 'the stand-ins took the server\'s transforms and isovalues (the scene JSON)',
  moved: 'the page moved an object or a light (id, its transform or {polygon, radiance})',
  history: 'the undo steps changed (the UndoHistory)',
  edited: 'an edit of this page is answered and its mesh held ({result, roundTrip, bytes, phases})',
  imageStale: 'the server\'s image no longer shows the scene or the view',
  built: 'a full build\'s stats are known (the stats: GET stats at load, or a rebuild\'s answer; rebuilt: whether a rebuild)',
  render: 'a server render\'s progress or state changed (the render job, as GET renders lists it)',
  connection: 'the event stream\'s state changed (state, previous)',
};

export class EventHub {
  constructor(names = Object.keys(EVENTS)) {
    this.handlers = new Map(names.map((name) => [name, []]));
  }

  // Calls handler(...args) on each `name` from now on; returns a function that stops it.
  on(name, handler) {
    const list = this.list(name);
    list.push(handler);
    return () => {
      const at = list.indexOf(handler);
      if (at >= 0) list.splice(at, 1);
    };
  }

  emit(name, ...args) {
    for (const handler of [...this.list(name)]) handler(...args);
  }

  list(name) {
    const list = this.handlers.get(name);
    if (!list) throw new Error(`event hub: no event named '${name}' (known: ${[...this.handlers.keys()].join(', ')})`);
    return list;
  }
}
