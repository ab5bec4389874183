// While the server builds a scene this page posted (POST /api/scenes?ticket=T): the build's stage
// and fraction from GET /api/scenes (the entry with our ticket) on the loading overlay, its
// seconds counting on, and a Cancel button that sends DELETE /api/scenes/ID (the POST then
// answers 409 build_cancelled).

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
    this.timer = null;
    this.cancelling = false;
  }

  // The upload is in: the server builds from now on.
  start() {
    if (this.timer !== null) return;
    this.loading.waiting('The server builds the discontinuity mesh…');
    this.loading.offerCancel(() => this.cancel());
    this.timer = setInterval(() => this.poll(), POLL_MS);
    this.poll();
  }

  async poll() {
    if (this.polling) return;
    this.polling = true;
    try {
      const { scenes } = await this.api.listScenes();
      const build = scenes.find((s) => s.state === 'building' && s.ticket === this.ticket);
      if (build && this.timer !== null) {
        this.id = build.id;
        if (!this.cancelling) this.loading.relabel(`The server builds the discontinuity mesh: ${describeBuild(build.progress)}`, build.progress.fraction ?? null);
        else this.sendCancel();
      }
    } catch {
      // The POST's own answer says what went wrong.
    } finally {
      this.polling = false;
    }
  }

  // Cancels the build (once its id is known: the next poll sends it).
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
    clearInterval(this.timer);
    this.timer = null;
  }
}
