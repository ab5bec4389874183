// The server's HTTP API (docs/API.md) as promises. Every non-2xx answer becomes an
// ApiError carrying the server's {code, message, path}; nothing is swallowed here.

export class ApiError extends Error {
  constructor(status, code, message, path) {
    super(`${status} ${code}: ${message}${path ? ` (at ${path})` : ''}`);
    this.reason = message; // the server's own words
    this.status = status;
    this.code = code;
    this.path = path;
  }
}

// An error answer's body text → ApiError with the server's {code, message, path}.
function errorFromText(status, statusText, text) {
  let body = null;
  try {
    body = JSON.parse(text);
  } catch {
    // Not JSON (a proxy or a static 404): report the status line alone.
  }
  const error = body && body.error ? body.error : {};
  return new ApiError(status, error.code || 'http_error', error.message || statusText, error.path || '');
}

async function failure(response) {
  let text = '';
  try {
    text = await response.text();
  } catch {
    // The body could not be read: the status line alone.
  }
  return errorFromText(response.status, response.statusText, text);
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
  // ticket: shown with the build in GET /api/scenes (build_progress.js).
  createScene(sceneText, name, onProgress, ticket) {
    const params = new URLSearchParams();
    if (name) params.set('name', name);
    if (ticket) params.set('ticket', ticket);
    const query = params.toString() ? `?${params}` : '';
    if (onProgress) return this.upload(`/api/scenes${query}`, sceneText, 'application/json', onProgress);
    return this.json('POST', `/api/scenes${query}`, sceneText);
  }

  // A POST whose upload progress is reported (fetch reports none): onProgress(sent, total,
  // false) while the body leaves, then onProgress(total, total, true) once the server has it
  // all and works on it (building a scene: seconds). Resolves with the answer's JSON.
  upload(path, body, contentType, onProgress) {
    return new Promise((resolve, reject) => {
      const xhr = new XMLHttpRequest();
      xhr.open('POST', this.base + path);
      if (contentType) xhr.setRequestHeader('Content-Type', contentType);
      if (this.token) xhr.setRequestHeader('Authorization', `Bearer ${this.token}`);
      xhr.upload.addEventListener('progress', (e) => onProgress(e.loaded, e.lengthComputable ? e.total : 0, false));
      xhr.upload.addEventListener('load', () => onProgress(1, 1, true));
      xhr.addEventListener('error', () => reject(new ApiError(0, 'network_error', `POST ${path} failed`, '')));
      xhr.addEventListener('load', () => {
        if (xhr.status < 200 || xhr.status >= 300) {
          reject(errorFromText(xhr.status, xhr.statusText, xhr.responseText));
          return;
        }
        try {
          resolve(JSON.parse(xhr.responseText));
        } catch (error) {
          reject(new ApiError(xhr.status, 'bad_answer', `POST ${path}: ${error.message}`, ''));
        }
      });
      xhr.send(body);
    });
  }

  // The binary mesh (whole, or the receivers changed after `since`) as an ArrayBuffer.
  async meshBinary(id, since) {
    const query = since === undefined || since === null ? '?format=bin' : `?since=${since}&format=bin`;
    const response = await this.request('GET', `${this.scenePath(id)}/mesh${query}`);
    return response.arrayBuffer();
  }

  // A response requested earlier (prefetch.js's), checked as request() checks its own.
  async adopt(promise, what) {
    let response;
    try {
      response = await promise;
    } catch (error) {
      throw new ApiError(0, 'network_error', `${what} failed: ${error.message}`, '');
    }
    if (!response.ok) throw await failure(response);
    return response;
  }

  // The body as an ArrayBuffer, calling onProgress(loaded, total) as it arrives (total 0 when
  // unknown: no Content-Length, or one of compressed bytes).
  static async bytesWithProgress(response, onProgress) {
    const encoded = response.headers.get('Content-Encoding');
    const total = encoded ? 0 : Number(response.headers.get('Content-Length')) || 0;
    if (!response.body) return response.arrayBuffer();
    const reader = response.body.getReader();
    const chunks = [];
    let loaded = 0;
    for (;;) {
      const { done, value } = await reader.read();
      if (done) break;
      chunks.push(value);
      loaded += value.byteLength;
      onProgress(loaded, total);
    }
    const bytes = new Uint8Array(loaded);
    let at = 0;
    for (const chunk of chunks) {
      bytes.set(chunk, at);
      at += chunk.byteLength;
    }
    return bytes.buffer;
  }

  // A PNG for a camera (cameraQuery: URLSearchParams entries from cameraToQuery); `samples`:
  // microfacet paths per pixel (null: the server's default).
  // The whole binary mesh with each vertex's baked indirect light (docs/API.md "Indirect light").
  async meshIndirect(id, signal) {
    const response = await this.request('GET', `${this.scenePath(id)}/mesh?format=bin&indirect=1`, { signal });
    return { buffer: await response.arrayBuffer(), seconds: Number(response.headers.get('X-Penumbra-Indirect-Seconds')) };
  }

  // gi: bounced light by sensors (the server's defaults) instead of the flat ambient term.
  // extra: more query keys (a render job's ticket and page, docs/API.md).
  async image(id, width, height, cameraQuery, signal, samples = null, gi = false, extra = {}) {
    const params = new URLSearchParams({ width: String(width), height: String(height), ...cameraQuery, ...extra });
    if (samples) params.set('samples', String(samples));
    if (gi) params.set('gi', 'sensors');
    const response = await this.request('GET', `${this.scenePath(id)}/image?${params}`, { signal });
    return {
      blob: await response.blob(),
      version: Number(response.headers.get('X-Penumbra-Version')),
      seconds: Number(response.headers.get('X-Penumbra-Render-Seconds')),
      samples: Number(response.headers.get('X-Penumbra-Samples')),
      giSensors: response.headers.has('X-Penumbra-Gi-Sensors') ? Number(response.headers.get('X-Penumbra-Gi-Sensors')) : null,
      giSeconds: Number(response.headers.get('X-Penumbra-Gi-Seconds')),
    };
  }

  eventsUrl(id) {
    return `${this.base}${this.scenePath(id)}/events`;
  }

  // The scenes being built, as server-sent events (`event: build`).
  buildEventsUrl() {
    return `${this.base}/api/builds/events`;
  }
}
