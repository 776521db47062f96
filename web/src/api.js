// The studio's JSON API (docs/studio.md). Every call returns parsed JSON or
// throws an Error whose message is the server's {"error"} text and whose
// status is the HTTP status (403: refused, 412: the file changed since it
// was read). The browser sends the page's Origin with every write itself.

async function call(method, url, body, type, headers = {}) {
  const init = { method, headers: { ...headers } };
  if (body !== undefined) {
    if (type === 'text') {
      init.headers['Content-Type'] = 'text/plain; charset=utf-8';
      init.body = body;
    } else {
      init.headers['Content-Type'] = 'application/json';
      init.body = JSON.stringify(body);
    }
  }
  return answer(await fetch(url, init));
}

// raw: the body, when it was read already.
async function answer(res, raw = null) {
  let data = null;
  if (raw == null) raw = await res.text();
  try { data = raw ? JSON.parse(raw) : null; } catch { data = null; }
  if (!res.ok) {
    const msg = (data && data.error) || raw || res.statusText;
    const err = new Error(`${res.status}: ${msg}`);
    err.status = res.status;
    throw err;
  }
  return data;
}

const q = (p) => encodeURIComponent(p);

// The file list, asked for by index.html before this script loaded (the
// page's first request, beside the script's; {res, raw}), taken once.
function earlyFiles() {
  const early = globalThis.__filesAnswer;
  globalThis.__filesAnswer = null;
  return early ? early.then(({ res, raw }) => answer(res, raw)) : null;
}

export const api = {
  files: () => earlyFiles() || call('GET', '/api/files'),
  mission: (path) => call('GET', `/api/mission?path=${q(path)}`),
  check: (path, text) => call('POST', '/api/check', { path, text }),
  // etag: the version the page read (the model's etag / layout_etag), sent
  // as If-Match; null for a file that did not exist.
  saveFile: (path, text, etag) => call('PUT', `/api/file?path=${q(path)}`, text, 'text', etag ? { 'If-Match': etag } : {}),
  saveLayout: (path, layout, etag) => call('PUT', `/api/layout?path=${q(path)}`, layout, 'json', etag ? { 'If-Match': etag } : {}),
  primitives: () => call('GET', '/api/primitives'),
  verify: (path, text) => call('POST', '/api/verify', text === undefined ? { path } : { path, text }),
  run: (path, scenario, speed) => call('POST', '/api/run', { path, scenario, speed }),
  // Abort: the run's safe end (surface, then done; outcome aborted).
  abort: () => call('POST', '/api/run/abort', {}),
  // Stop: a hard stop (nothing more is sent to the vehicle; not surfaced).
  stop: () => call('POST', '/api/run/stop', {}),
  // The logs of studio runs (runs/ beside each mission), newest first; of
  // one mission when given.
  runs: (mission) => call('GET', mission ? `/api/runs?mission=${q(mission)}` : '/api/runs'),
  replay: (path) => call('GET', `/api/replay?path=${q(path)}`),
  // base: the rev of the model the page holds; the answer is then a patch
  // of it ({rev, base, patch}: patch.js) when the server still has it, else
  // the whole model.
  edit: (path, text, op, base) => call('POST', '/api/edit', base ? { path, text, op, base } : { path, text, op }),
  sonar: () => call('GET', '/api/sonar'),
};
