// The loading overlay over the view: what the page is waiting for (page files, scene, mesh
// download with its bytes, drawing; an upload and the server's build when a file is loaded) and a
// progress bar when the size is known. The panel's controls stay disabled (their fieldset) until
// the scene is ready.

import { ElapsedCounter } from './elapsed_counter.js';

export class LoadingIndicator {
  // cancelButton: shown while offerCancel's work may be stopped.
  constructor(root, text, bar, controls, cancelButton) {
    Object.assign(this, { root, text, bar, controls, cancelButton });
    this.started = performance.now();
    this.fraction = null;
    this.counter = new ElapsedCounter((message) => this.show(message, this.fraction));
    cancelButton.addEventListener('click', () => {
      if (this.onCancel) this.onCancel();
    });
  }

  // fraction: 0..1, or null for an indeterminate bar. A new step ends a waiting() counter.
  step(message, fraction = null) {
    this.counter.stop();
    this.offerCancel(null);
    this.show(message, fraction);
  }

  show(message, fraction) {
    this.root.hidden = false;
    this.root.classList.remove('failed');
    this.text.textContent = message;
    if (fraction === null) this.bar.removeAttribute('value');
    else this.bar.value = Math.min(1, Math.max(0, fraction));
  }

  // Long work (the server building a scene): shows the seconds waited, counting on while
  // relabel() changes the message and the bar (the build's stage and fraction).
  waiting(message) {
    this.fraction = null;
    this.counter.start(message);
  }

  relabel(message, fraction) {
    this.fraction = fraction;
    if (this.counter.running()) this.counter.relabel(message);
    else this.show(message, fraction);
  }

  // Shows the Cancel button calling onCancel(); null hides it.
  offerCancel(onCancel) {
    this.onCancel = onCancel;
    this.cancelButton.hidden = !onCancel;
    this.cancelButton.disabled = false;
  }

  // Bytes received of a download (total 0 when the server did not say).
  bytes(message, loaded, total) {
    const mb = (n) => (n / 1048576).toFixed(n < 1048576 ? 2 : 1);
    this.step(total ? `${message}: ${mb(loaded)} of ${mb(total)} MB` : `${message}: ${mb(loaded)} MB`, total ? loaded / total : null);
  }

  done() {
    this.counter.stop();
    this.offerCancel(null);
    this.root.hidden = true;
    this.controls.disabled = false;
    this.readySeconds = (performance.now() - this.started) / 1000;
  }

  // A step given up (a refused upload): back to the loaded scene, or to why none is loaded.
  cancel() {
    if (this.readySeconds !== undefined) this.done();
    else this.failed(this.failure || 'No scene loaded: load a scene file');
  }

  failed(message) {
    this.failure = message;
    this.counter.stop();
    this.offerCancel(null);
    this.root.hidden = false;
    this.root.classList.add('failed');
    this.text.textContent = message;
    this.bar.value = 0;
  }

  visible() {
    return !this.root.hidden;
  }
}
