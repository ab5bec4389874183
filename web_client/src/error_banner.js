// The visible error banner: every failure the page meets is shown here (and kept in `errors`
// for the test hook); it stays until dismissed, except a transient one (a refused edit), which the
// next successful edit clears. The same transient message is shown (and kept) once, not once per
// refused frame. A network failure is shown after a short hold and dropped if the page is being
// left meanwhile: leaving cuts off the requests still in flight, which is not an error to report;
// and it is taken down once the server answers again (serverBack()). The banner says each failure
// as a plain sentence with the server's code and key path on a detail line (error_text.js).

import { plainError } from './error_text.js';

const NETWORK_HOLD_MS = 300;

export class ErrorBanner {
  constructor(root, text, closeButton) {
    this.root = root;
    this.text = text;
    this.errors = [];
    this.transient = false;
    this.leaving = false;
    // Not beforeunload: a navigation it starts may still be cancelled. A page restored from the
    // back-forward cache reports again.
    window.addEventListener('pagehide', () => { this.leaving = true; });
    window.addEventListener('pageshow', () => { this.leaving = false; });
    closeButton.addEventListener('click', () => { this.root.hidden = true; });
  }

  // transient: cleared by clearTransient() (the next edit the server accepts); key: a transient
  // error with the key of the one shown is not shown again (one banner for a drag's refusals).
  show(error, options = {}) {
    if (this.leaving) return;
    if (error && error.code === 'network_error') {
      setTimeout(() => { if (!this.leaving) this.display(error, options); }, NETWORK_HOLD_MS);
      return;
    }
    this.display(error, options);
  }

  // also: a sentence to add (what the page did about it).
  display(error, { transient = false, key = null, also = '' } = {}) {
    const plain = plainError(error);
    const message = also ? `${plain.sentence} ${also}` : plain.sentence;
    if (transient && this.transient && this.visible() && (key ? this.key === key : this.message === message)) return;
    this.errors.push(plain.detail ? `${message} (${plain.detail})` : message);
    console.error('penumbra:', error);
    const detail = document.createElement('div');
    detail.className = 'error-detail';
    detail.textContent = plain.detail;
    this.text.replaceChildren(message, ...(plain.detail ? [detail] : []));
    this.message = message;
    this.code = error && error.code;
    this.transient = transient;
    this.key = key;
    this.root.hidden = false;
  }

  // The server answers again: a shown "could not be reached" is no longer true.
  serverBack() {
    if (this.code === 'network_error') this.root.hidden = true;
  }

  clearTransient() {
    if (this.transient) this.root.hidden = true;
    this.transient = false;
  }

  visible() {
    return !this.root.hidden;
  }
}
