// While the server builds a scene this page posted (POST /api/scenes?ticket=T): the build's stage
// and fraction on the loading overlay, its seconds counting on, and a Cancel button that sends
// DELETE /api/scenes/ID (the POST then answers 409 build_cancelled). The build's progress comes
// from the server's builds event stream (GET /api/builds/events, `event: build` with our ticket);
// only while that stream is down is the scene list (GET /api/scenes, the entry with our ticket)
// polled instead.

const POLL_MS = 250;

// A ticket for one POST: the page finds its build in the scene list before it knows the id.
export function newTicket() {
  return `p${Math.random().toString(36).slice(2, 12)}${Date.now().toString(36)}`;
}

// "casting 46 %" ("import" for a stage without a count).
export function describeBuild(progress) {
  const percent = progress.fraction === null || progress.fraction === undefined ? ''
    : ` ${Math.floor(progress.fraction * 100)} %`;
  return `${progress.stage}${percent}`;
}

export class BuildProgress {
  constructor(api, loading, ticket) {
    Object.assign(this, { api, loading, ticket });
    this.id = null;
    this.running = false;
    this.timer = null; // the fallback poll's, while the stream is down
    this.source = null;
    this.cancelling = false;
    this.events = 0; // build events of ours received
    this.polls = 0;
  }

  // The upload is in: the server builds from now on.
  start() {
    if (this.running) return;
    this.running = true;
    this.loading.waiting('The server builds the discontinuity mesh…');
    this.loading.offerCancel(() => this.cancel());
    this.source = new EventSource(this.api.buildEventsUrl());
    this.source.addEventListener('open', () => this.pollWhileDown(false));
    this.source.addEventListener('error', () => this.pollWhileDown(true));
    this.source.addEventListener('build', (event) => {
      let build;
      try {
        build = JSON.parse(event.data);
      } catch {
        return; // the POST's own answer says how the build ended
      }
      if (build.ticket !== this.ticket || !this.running) return;
      ++this.events;
      if (build.state === 'building') this.show(build);
    });
  }

  // The stream is down (true) or up again (false): the scene list is polled meanwhile.
  pollWhileDown(down) {
    clearInterval(this.timer);
    this.timer = null;
    if (!down || !this.running) return;
    this.timer = setInterval(() => this.poll(), POLL_MS);
    this.poll();
  }

  async poll() {
    if (this.polling) return;
    this.polling = true;
    ++this.polls;
    try {
      const { scenes } = await this.api.listScenes();
      const build = scenes.find((s) => s.state === 'building' && s.ticket === this.ticket);
      if (build && this.running) this.show(build);
    } catch {
      // The POST's own answer says what went wrong.
    } finally {
      this.polling = false;
    }
  }

  show(build) {
    this.id = build.id;
    if (!this.cancelling) this.loading.relabel(`The server builds the discontinuity mesh: ${describeBuild(build.progress)}`, build.progress.fraction ?? null);
    else this.sendCancel();
  }

  // Cancels the build (once its id is known: the next report of it sends it).
  cancel() {
    this.cancelling = true;
    this.loading.cancelButton.disabled = true;
    this.loading.relabel('Cancelling the build…', null);
    if (this.id) this.sendCancel();
  }

  sendCancel() {
    if (this.sent) return;
    this.sent = true;
    this.api.json('DELETE', this.api.scenePath(this.id)).catch(() => {});
  }

  stop() {
    this.running = false;
    clearInterval(this.timer);
    this.timer = null;
    if (this.source) this.source.close();
    this.source = null;
  }
}
