// Talking to the server, and the few DOM helpers every part of the page uses.

export const $ = (id) => document.getElementById(id);

/** Calls the API; a problem answer becomes an Error saying what is wrong and where. */
export async function api(method, path, body) {
  const r = await fetch(path, { method, headers: body ? { 'Content-Type': 'application/json' } : {}, body: body ? JSON.stringify(body) : undefined });
  const text = await r.text();
  const data = text ? JSON.parse(text) : null;
  if (!r.ok) {
    const where = data && data.pointer ? ` (at ${data.pointer})` : '';
    throw new Error(data && data.detail ? data.detail + where : `${method} ${path}: ${r.status}`);
  }
  return data;
}

export function status(text, isError) {
  $('status').textContent = text;
  $('status').className = isError ? 'error' : '';
}

export const escapeHtml = (s) => String(s).replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' })[c]);
