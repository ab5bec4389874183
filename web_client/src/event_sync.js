// Server-sent events (GET /events): each announced version the page does not hold is fetched
// as a mesh delta; versions made by another client also move the objects' stand-ins; a render's
// progress (`event: render`) goes to the render panel. The stream
// also tells whether the server is there: a broken stream is a lost server (the browser retries
// every second, as the server's `retry: 1000` asks), a refused one (404: the scene is gone, e.g.
// a server restarted without it) is retried here every few seconds. Leaving the page closes the
// stream quietly.

const REOPEN_MS = 3000;

export class EventSync {
  // handlers: {onVersion(version, data), onRender(job), onError(error), onConnection(state)}; state:
  // 'connected', 'reconnecting' (the server is unreachable) or 'refused' (it answers, without the scene).
  constructor(url, handlers) {
    this.url = url;
    this.handlers = handlers;
    this.events = 0;
    this.state = 'connecting';
    this.leaving = false;
    this.timer = null;
    window.addEventListener('pagehide', () => this.close());
    this.open();
  }

  open() {
    this.source = new EventSource(this.url);
    this.source.addEventListener('open', () => this.setState('connected'));
    this.source.addEventListener('version', (event) => {
      const data = this.parse(event);
      if (data) this.handlers.onVersion(data.version, data);
    });
    this.source.addEventListener('render', (event) => {
      const job = this.parse(event);
      if (job && this.handlers.onRender) this.handlers.onRender(job);
    });
    this.source.addEventListener('error', () => {
      if (this.leaving) return;
      if (this.source.readyState === EventSource.CLOSED) {
        // Not retried by the browser: an HTTP error. Try again later ourselves.
        this.setState('refused');
        clearTimeout(this.timer);
        this.timer = setTimeout(() => { if (!this.leaving) this.open(); }, REOPEN_MS);
      } else {
        this.setState('reconnecting');
      }
    });
  }

  // An event's JSON data (counted), or null after reporting it unreadable.
  parse(event) {
    ++this.events;
    try {
      return JSON.parse(event.data);
    } catch (error) {
      this.handlers.onError(new Error(`event stream: bad event data: ${error.message}`));
      return null;
    }
  }

  setState(state) {
    if (state === this.state) return;
    const previous = this.state;
    this.state = state;
    this.handlers.onConnection(state, previous);
  }

  close() {
    this.leaving = true;
    clearTimeout(this.timer);
    this.source.close();
  }
}
