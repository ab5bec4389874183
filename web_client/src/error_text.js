// What the error banner says of a failure: one plain sentence for a person (what went wrong, in
// the server's words where it gave any), and a detail line with what a developer needs (HTTP
// status, the server's error code, the key path). ApiErrors (api_client.js) carry all three.

const LEADS = {
  network_error: 'The server could not be reached',
  malformed_json: 'The server could not read the request',
  bad_parameter: 'The server refused a request parameter',
  invalid_utf8: 'A name or text is not valid UTF-8',
  unauthorized: 'This page has no permission to change the scene (open it with the server\'s token)',
  not_found: 'The server does not have this',
  payload_too_large: 'The file is larger than the server accepts',
  bad_request: 'The server could not read the upload',
  invalid_scene: 'The server refused the scene',
  invalid_frame: 'The server refused the edit',
  invalid_name: 'The server refused the name',
  scene_stalled: 'The scene is read-only on the server',
  too_many_scenes: 'The server holds as many scenes as it may: delete one first',
  too_many_streams: 'The server has too many pages open',
  busy: 'The server is busy: try again',
  journal_failed: 'The server could not save the change, so it did not make it',
  frame_not_applied: 'The server could not apply the edit; the scene is as it was',
  resource_limit: 'The scene would grow past the server\'s limits',
  out_of_memory: 'The server ran out of memory; nothing was changed',
  internal_error: 'The server met a bug',
};

const sentence = (text) => {
  const trimmed = String(text).trim();
  if (!trimmed) return '';
  const capital = trimmed[0].toUpperCase() + trimmed.slice(1);
  return /[.!?]$/.test(capital) ? capital : `${capital}.`;
};

// {sentence, detail}: detail is '' for a failure of the page itself (no server code).
export function plainError(error) {
  if (!error || !error.code || error.status === undefined) return { sentence: sentence(error && error.message ? error.message : String(error)), detail: '' };
  const lead = LEADS[error.code] || `The request failed (${error.status || 'no answer'})`;
  const why = error.code === 'network_error' ? '' : error.reason;
  const detail = [error.status ? `${error.status} ${error.code}` : error.code, error.path ? `at ${error.path}` : '',
    error.code === 'network_error' ? error.reason : ''].filter(Boolean).join(' ');
  return { sentence: sentence(why ? `${lead}: ${why}` : lead), detail };
}
