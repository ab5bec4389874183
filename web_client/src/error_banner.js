// The visible error banner: every failure the page meets is shown here (and kept in `errors`
// for the test hook); it stays until dismissed.

export class ErrorBanner {
  constructor(root, text, closeButton) {
    this.root = root;
    this.text = text;
    this.errors = [];
    closeButton.addEventListener('click', () => { this.root.hidden = true; });
  }

  show(error) {
    const message = error && error.message ? error.message : String(error);
    this.errors.push(message);
    console.error('penumbra:', error);
    this.text.textContent = message;
    this.root.hidden = false;
  }

  visible() {
    return !this.root.hidden;
  }
}
