// The visible error banner: every failure the page meets is shown here (and kept in `errors`
// for the test hook); it stays until dismissed, except a transient one (a refused edit), which the
// next successful edit clears. The same transient message is shown (and kept) once, not once per
// refused frame.

export class ErrorBanner {
  constructor(root, text, closeButton) {
    this.root = root;
    this.text = text;
    this.errors = [];
    this.transient = false;
    closeButton.addEventListener('click', () => { this.root.hidden = true; });
  }

  // transient: cleared by clearTransient() (the next edit the server accepts); key: a transient
  // error with the key of the one shown is not shown again (one banner for a drag's refusals).
  show(error, { transient = false, key = null } = {}) {
    const message = error && error.message ? error.message : String(error);
    if (transient && this.transient && this.visible() && (key ? this.key === key : this.text.textContent === message)) return;
    this.errors.push(message);
    console.error('penumbra:', error);
    this.text.textContent = message;
    this.transient = transient;
    this.key = key;
    this.root.hidden = false;
  }

  clearTransient() {
    if (this.transient) this.root.hidden = true;
    this.transient = false;
  }

  visible() {
    return !this.root.hidden;
  }
}
