// The running server render's progress beside the panel's counter: the server's stage and
// fraction, as text and a bar, and a Cancel button that stops it (DELETE of the ticket, and the
// request aborted). The progress comes from the scene's event stream (`event: render`, handed to
// report()); only while that stream is down is it polled by the render's ticket (in GET
// /api/scenes/{id}/renders). Elements are made here, after the counter's element.

const POLL_MS = 250;
const STAGES = { tracing: 'tracing', sensors: 'GI sensors', shading: 'shading', encoding: 'encoding', queued: 'queued' };

export class RenderProgress {
  // after: the element to follow (the counter); onCancel(): stops the refinement.
  constructor(api, sceneId, after, onCancel) {
    Object.assign(this, { api, sceneId, onCancel });
    this.text = document.createElement('span');
    this.text.id = 'render-fraction';
    this.text.className = 'muted';
    this.bar = document.createElement('progress');
    this.bar.id = 'render-bar';
    this.bar.max = 1;
    this.bar.hidden = true;
    this.button = document.createElement('button');
    this.button.id = 'render-cancel';
    this.button.type = 'button';
    this.button.textContent = 'Cancel';
    this.button.title = 'Stop this server render (DELETE of its ticket)';
    this.button.hidden = true;
    this.button.addEventListener('click', () => this.cancel());
    after.after(this.text, ' ', this.bar, ' ', this.button);
    this.ticket = null;
    this.timer = null;
    this.streaming = false; // whether the scene's event stream is connected
    this.last = null; // the last progress the server sent ({stage, fraction, elapsed_seconds, …})
    this.polls = 0;
  }

  // A pass with this ticket is on its way.
  follow(ticket) {
    this.stop();
    this.ticket = ticket;
    this.button.hidden = false;
    this.pollWhileDown();
  }

  // The scene's event stream connected (true) or lost (false).
  setStreaming(on) {
    this.streaming = on;
    this.pollWhileDown();
  }

  pollWhileDown() {
    clearInterval(this.timer);
    this.timer = null;
    const { ticket } = this;
    if (!this.streaming && ticket) this.timer = setInterval(() => this.poll(ticket), POLL_MS);
  }

  // A render job as the server describes it (an `event: render`, or an entry of the list).
  report(job) {
    if (!this.ticket || job.ticket !== this.ticket || job.state !== 'running') return;
    this.last = job.progress;
    const { stage, fraction } = job.progress;
    const name = STAGES[stage] ?? stage;
    this.text.textContent = fraction === null ? name : `${name} ${Math.floor(fraction * 100)}%`;
    this.bar.hidden = fraction === null;
    if (fraction !== null) this.bar.value = fraction;
  }

  async poll(ticket) {
    try {
      // The scene's list, not the ticket's own route: before the request reaches the server the
      // ticket is unknown there, and a 404 would be logged as a failed load.
      ++this.polls;
      const { renders } = await this.api.json('GET', `${this.api.scenePath(this.sceneId)}/renders`);
      const job = renders.find((r) => r.ticket === ticket);
      if (ticket === this.ticket && job) this.report(job);
    } catch {
      // The server unreachable for a moment: the next poll or the image says.
    }
  }

  async cancel() {
    const ticket = this.ticket;
    this.onCancel();
    this.stop();
    this.text.textContent = 'cancelled';
    if (!ticket) return;
    try {
      await this.api.request('DELETE', `${this.api.scenePath(this.sceneId)}/renders/${ticket}`);
    } catch {
      // Already ended (404): aborting the request stopped it.
    }
  }

  stop() {
    clearInterval(this.timer);
    this.timer = null;
    this.ticket = null;
    this.text.textContent = '';
    this.bar.hidden = true;
    this.button.hidden = true;
  }
}
