// A message with the seconds since it started ("The server builds… 3.2 s"), redrawn every 100 ms
// until stopped or started again: long work the page cannot measure in steps still shows it moves.

const EVERY_MS = 100;

export class ElapsedCounter {
  // show(text): draws the message with its seconds.
  constructor(show) {
    this.show = show;
    this.timer = null;
  }

  // fromSeconds: what the work had taken already when it was reported (a server's build).
  start(message, fromSeconds = 0) {
    this.stop();
    this.message = message;
    const since = performance.now() - 1000 * fromSeconds;
    this.tick = () => this.show(`${this.message} ${((performance.now() - since) / 1000).toFixed(1)} s`);
    this.tick();
    this.timer = setInterval(this.tick, EVERY_MS);
  }

  // A new message while the seconds keep counting from start().
  relabel(message) {
    this.message = message;
    if (this.timer !== null) this.tick();
  }

  running() {
    return this.timer !== null;
  }

  stop() {
    clearInterval(this.timer);
    this.timer = null;
  }
}
