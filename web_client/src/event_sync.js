// Server-sent events (GET /events): each announced version the page does not hold is fetched
// as a mesh delta; versions made by another client also move the objects' stand-ins.

export class EventSync {
  // handlers: {onVersion(version, data), onLost()}
  constructor(url, handlers) {
    this.source = new EventSource(url);
    this.events = 0;
    this.source.addEventListener('version', (event) => {
      ++this.events;
      let data;
      try {
        data = JSON.parse(event.data);
      } catch (error) {
        handlers.onError(new Error(`event stream: bad event data: ${error.message}`));
        return;
      }
      handlers.onVersion(data.version, data);
    });
    this.source.addEventListener('error', () => {
      // EventSource retries by itself (the server sends retry: 1000); a closed stream is final.
      if (this.source.readyState === EventSource.CLOSED) handlers.onError(new Error('event stream closed by the server'));
    });
  }

  close() {
    this.source.close();
  }
}
