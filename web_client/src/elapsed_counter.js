// A message with the seconds since it started ("The server builds… 3.2 s"), redrawn every 100 ms
// until stopped or started again: long work the page cannot measure in steps still shows it moves.

const EVERY_MS = 100;

export class ElapsedCounter {
  // show(text): draws the message with its seconds.
  constructor(show) {
    this.show = show;
    this.timer = null;
  }

  start(message) {
    this.stop();
    const since = performance.now();
    const tick = () => this.show(`${message} ${((performance.now() - since) / 1000).toFixed(1)} s`);
    tick();
    this.timer = setInterval(tick, EVERY_MS);
  }

  stop() {
    clearInterval(this.timer);
    this.timer = null;
  }
}
