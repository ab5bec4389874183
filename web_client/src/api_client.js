// The server's HTTP API (docs/API.md) as promises. Every non-2xx answer becomes an
// ApiError carrying the server's {code, message, path}; nothing is swallowed here.

export class ApiError extends Error {
  constructor(status, code, message, path) {
    super(`${status} ${code}: ${message}${path ? ` (at ${path})` : ''}`);
    this.status = status;
    this.code = code;
    this.path = path;
  }
}

async function failure(response) {
  let body = null;
  try {
    body = await response.json();
  } catch {
    // Not JSON (a proxy or a static 404): report the status line alone.
  }
  const error = body && body.error ? body.error : {};
  return new ApiError(response.status, error.code || 'http_error', error.message || response.statusText, error.path || '');
}

export class ApiClient {
  // token: the server's --token (the page's ?token=), sent on every request that changes something.
  constructor(base = '', token = null) {
    this.base = base;
    this.token = token;
  }

  async request(method, path, { body, signal, headers } = {}) {
    if (this.token && method !== 'GET' && method !== 'HEAD') headers = { ...headers, Authorization: `Bearer ${this.token}` };
    let response;
    try {
      response = await fetch(this.base + path, { method, body, signal, headers });
    } catch (error) {
      if (error.name === 'AbortError') throw error;
      throw new ApiError(0, 'network_error', `${method} ${path} failed: ${error.message}`, '');
    }
    if (!response.ok) throw await failure(response);
    return response;
  }

  async json(method, path, body) {
    const response = await this.request(method, path, body === undefined ? {} : {
      body: typeof body === 'string' ? body : JSON.stringify(body),
      headers: { 'Content-Type': 'application/json' },
    });
    return response.status === 204 ? null : response.json();
  }

  scenePath(id) {
    return `/api/scenes/${encodeURIComponent(id)}`;
  }

  listScenes() { return this.json('GET', '/api/scenes'); }
  getScene(id) { return this.json('GET', this.scenePath(id)); }
  stats(id) { return this.json('GET', `${this.scenePath(id)}/stats`); }
  rebuild(id) { return this.json('POST', `${this.scenePath(id)}/rebuild`, ''); }
  postEdits(id, frame) { return this.json('POST', `${this.scenePath(id)}/edits`, frame); }

  // sceneText: the file's text, sent as is so the server validates it with key paths.
  createScene(sceneText, name) {
    const query = name ? `?name=${encodeURIComponent(name)}` : '';
    return this.json('POST', `/api/scenes${query}`, sceneText);
  }

  // The binary mesh (whole, or the receivers changed after `since`) as an ArrayBuffer.
  async meshBinary(id, since) {
    const query = since === undefined || since === null ? '?format=bin' : `?since=${since}&format=bin`;
    const response = await this.request('GET', `${this.scenePath(id)}/mesh${query}`);
    return response.arrayBuffer();
  }

  // A PNG for a camera (cameraQuery: URLSearchParams entries from cameraToQuery).
  async image(id, width, height, cameraQuery, signal) {
    const params = new URLSearchParams({ width: String(width), height: String(height), ...cameraQuery });
    const response = await this.request('GET', `${this.scenePath(id)}/image?${params}`, { signal });
    return {
      blob: await response.blob(),
      version: Number(response.headers.get('X-Penumbra-Version')),
      seconds: Number(response.headers.get('X-Penumbra-Render-Seconds')),
    };
  }

  eventsUrl(id) {
    return `${this.base}${this.scenePath(id)}/events`;
  }
}
