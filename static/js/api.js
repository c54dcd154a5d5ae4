// Talking to the server, and the few DOM helpers every part of the page uses.

export const $ = (id) => document.getElementById(id);

// The API key, when the server wants one: asked once per browser tab and kept in its session
// storage (gone when the tab closes).
const KEY = 'coverplan.apiKey';
export const hasApiKey = () => !!sessionStorage.getItem(KEY);

/** `fetch` with the tab's API key; on 401 it asks for a key and tries again. Requests refused
 * together ask once: one refused with a key that has since been replaced just tries again. */
export async function authorisedFetch(path, init = {}) {
  for (;;) {
    const key = sessionStorage.getItem(KEY);
    const headers = { ...(init.headers || {}), ...(key ? { Authorization: `Bearer ${key}` } : {}) };
    const r = await fetch(path, { ...init, headers });
    if (r.status !== 401) return r;
    if (sessionStorage.getItem(KEY) !== key) continue;
    const given = window.prompt(key ? 'That API key was refused. API key:' : 'This server needs an API key (its operator makes them with `coverplan keys create`). API key:');
    if (!given || !given.trim()) return r;
    sessionStorage.setItem(KEY, given.trim());
  }
}

/** Calls the API; a problem answer becomes an Error saying what is wrong and where. */
export async function api(method, path, body) {
  const r = await authorisedFetch(path, { method, headers: body ? { 'Content-Type': 'application/json' } : {}, body: body ? JSON.stringify(body) : undefined });
  const text = await r.text();
  const data = text ? JSON.parse(text) : null;
  if (!r.ok) {
    // the detail in words; the pointer says which input to mark, not what to read
    throw Object.assign(new Error(data && data.detail ? data.detail : `${method} ${path}: ${r.status}`), { pointer: data && data.pointer, code: data && data.code });
  }
  return data;
}

export function status(text, isError, isWarning) {
  $('status').textContent = text;
  $('status').className = isError ? 'error' : isWarning ? 'warning' : '';
}

export const escapeHtml = (s) => String(s).replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' })[c]);
