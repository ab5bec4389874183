// The connection bar: shown while the server is unreachable ("reconnecting") or no longer serves
// the page's scene; hidden once the event stream is back (the page then reloads the scene, which
// may have changed or, after a restart without a journal, been built afresh).

const MESSAGES = {
  reconnecting: 'Server disconnected — reconnecting…',
  refused: 'The server no longer serves this scene — retrying; load a scene file or pick another scene',
};

export class ConnectionStatus {
  constructor(root) {
    this.root = root;
    this.state = 'connecting';
    this.since = null;
    this.timer = null;
  }

  set(state) {
    this.state = state;
    clearInterval(this.timer);
    this.timer = null;
    if (!MESSAGES[state]) {
      this.root.hidden = true;
      return;
    }
    this.since = performance.now();
    const show = () => {
      this.root.textContent = `${MESSAGES[state]} (${((performance.now() - this.since) / 1000).toFixed(0)} s)`;
    };
    show();
    this.timer = setInterval(show, 1000);
    this.root.hidden = false;
  }

  visible() {
    return !this.root.hidden;
  }
}

// The bar on the page (page: {hub}): it follows the event stream's state.
export function installConnectionStatus({ hub }) {
  const status = new ConnectionStatus(document.getElementById('connection'));
  hub.on('connection', (state) => status.set(state));
  return status;
}
