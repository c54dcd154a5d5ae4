// The mission's elevation model: uploaded from a file, drawn as shaded relief with its extent,
// and the height profile of a plan flown over it (ground, planned altitude, tolerance band).

import { $, api, authorisedFetch, escapeHtml, status } from './api.js';
import { map, state } from './map.js';

let relief = null;
let extent = null;

/** Files read as elevation models rather than as missions. */
export const isTerrainFile = (name) => /\.(tif|tiff|hgt)$/i.test(name) || /\.hgt\.zip$/i.test(name);

function clearTerrain() {
  for (const layer of [relief, extent]) if (layer) map.removeLayer(layer);
  relief = extent = null;
  state.terrain = null;
  $('terrain-info').textContent = 'none';
  $('terrain-remove').hidden = true;
  const ground = $('altitude-reference').querySelector('option[value=terrain]');
  ground.disabled = true;
  if ($('altitude-reference').value === 'terrain') $('altitude-reference').value = 'home';
  $('altitude-reference').dispatchEvent(new Event('change'));
}

/** Light from the north-west, 45° up, on a grid of heights: grey levels, clear where there is no data. */
function shade(grid) {
  const { columns: w, rows: h, heights, bounds } = grid;
  const lat = (bounds[1] + bounds[3]) / 2;
  const dx = ((bounds[2] - bounds[0]) * 111320 * Math.cos((lat * Math.PI) / 180)) / (w - 1);
  const dy = ((bounds[3] - bounds[1]) * 110574) / (h - 1);
  const canvas = document.createElement('canvas');
  canvas.width = w;
  canvas.height = h;
  const ctx = canvas.getContext('2d');
  const image = ctx.createImageData(w, h);
  const at = (c, r) => heights[Math.min(h - 1, Math.max(0, r)) * w + Math.min(w - 1, Math.max(0, c))];
  const light = [-0.5, 0.5, Math.SQRT1_2];
  for (let r = 0; r < h; r++) {
    for (let c = 0; c < w; c++) {
      const here = at(c, r);
      const i = 4 * (r * w + c);
      if (here == null) continue;
      const east = ((at(c + 1, r) ?? here) - (at(c - 1, r) ?? here)) / (2 * dx);
      const north = ((at(c, r - 1) ?? here) - (at(c, r + 1) ?? here)) / (2 * dy);
      const norm = Math.hypot(east, north, 1);
      const lit = Math.max(0, (-east * light[0] - north * light[1] + light[2]) / norm);
      const grey = Math.round(40 + 215 * lit);
      image.data.set([grey, grey, grey, 150], i);
    }
  }
  ctx.putImageData(image, 0, 0);
  return canvas.toDataURL();
}

/** Shows the current mission's model, if it has one. */
export async function loadTerrain() {
  clearTerrain();
  if (!state.missionId) return;
  const r = await authorisedFetch(`/api/v1/missions/${state.missionId}/terrain`);
  if (r.status === 404) return;
  if (!r.ok) return status(`terrain: ${r.status}`, true);
  const t = await r.json();
  const grid = await api('GET', `/api/v1/missions/${state.missionId}/terrain/grid?size=256`);
  const [w, s, e, n] = grid.bounds;
  const bounds = [[s, w], [n, e]];
  relief = L.imageOverlay(shade(grid), bounds, { interactive: false, alt: 'shaded relief of the elevation model' }).addTo(map);
  relief.bringToBack();
  extent = L.rectangle(bounds, { color: '#795548', weight: 1, fill: false, dashArray: '3 4', interactive: false }).addTo(map);
  state.terrain = t;
  const cell = Math.round(Math.min(...t.cell_size_m));
  $('terrain-info').textContent = `${t.file_name}: ${t.crs}, ${cell} m cells, ${Math.round(t.min_m)}–${Math.round(t.max_m)} m`;
  $('terrain-remove').hidden = false;
  const ground = $('altitude-reference').querySelector('option[value=terrain]');
  ground.disabled = false;
}

/** Uploads `file` as the elevation model of the saved mission `missionId`. */
export async function uploadTerrain(file, missionId) {
  const type = /\.zip$/i.test(file.name) ? 'application/zip' : /\.hgt$/i.test(file.name) ? 'application/octet-stream' : 'image/tiff';
  const r = await authorisedFetch(`/api/v1/missions/${missionId}/terrain?name=${encodeURIComponent(file.name)}`, { method: 'PUT', headers: { 'content-type': type }, body: file });
  const body = await r.json();
  if (!r.ok) throw new Error(body.detail);
  await loadTerrain();
  // a model was given to be flown over
  $('altitude-reference').value = 'terrain';
  $('altitude-reference').dispatchEvent(new Event('change'));
  status(`elevation model ${escapeHtml(file.name)} stored: plans fly at their altitude above its ground`);
}

$('terrain-remove').onclick = async () => {
  if (!state.missionId) return;
  await api('DELETE', `/api/v1/missions/${state.missionId}/terrain`).catch((e) => status(e.message, true));
  await loadTerrain();
};

/** Metres between two [lon, lat] points (a plane at their latitude: pieces are short). */
const metres = (a, b) => Math.hypot((b[0] - a[0]) * 111320 * Math.cos((a[1] * Math.PI) / 180), (b[1] - a[1]) * 110574);

/** Ground, planned altitude and the tolerance band against the distance flown. */
export function drawProfile() {
  const canvas = $('profile');
  const ctx = canvas.getContext('2d');
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  const pieces = state.result ? state.result.fc.features.filter((f) => f.geometry.type === 'LineString' && f.properties.ground_m) : [];
  canvas.hidden = $('profile-legend').hidden = !pieces.length;
  state.profile = [];
  if (!pieces.length) return;
  const tolerance = (state.result.params && state.result.params.terrain_tolerance_m) || 5;
  let d = 0;
  for (const f of pieces) {
    const coords = f.geometry.coordinates;
    coords.forEach((p, i) => {
      if (i) d += metres(coords[i - 1], p);
      state.profile.push({ d, ground: f.properties.ground_m[i], z: p[2], height: f.properties.altitude_m, sweep: f.properties.kind === 'sweep' });
    });
  }
  const w = canvas.width, h = canvas.height, pad = 18;
  const lo = Math.min(...state.profile.map((p) => p.ground));
  const hi = Math.max(...state.profile.map((p) => Math.max(p.z, p.ground + p.height + tolerance)));
  const x = (p) => pad + (p.d / Math.max(d, 1)) * (w - 2 * pad);
  const y = (z) => h - pad - ((z - lo) / Math.max(hi - lo, 1)) * (h - 2 * pad);
  const line = (value, colour, dash = []) => {
    ctx.strokeStyle = colour;
    ctx.setLineDash(dash);
    ctx.beginPath();
    state.profile.forEach((p, i) => (i ? ctx.lineTo(x(p), y(value(p))) : ctx.moveTo(x(p), y(value(p)))));
    ctx.stroke();
    ctx.setLineDash([]);
  };
  // the ground, filled
  ctx.fillStyle = '#d7ccc8';
  ctx.beginPath();
  ctx.moveTo(x(state.profile[0]), h - pad);
  state.profile.forEach((p) => ctx.lineTo(x(p), y(p.ground)));
  ctx.lineTo(x(state.profile[state.profile.length - 1]), h - pad);
  ctx.fill();
  line((p) => p.ground + p.height - tolerance, '#7cb342', [3, 3]);
  line((p) => p.ground + p.height + tolerance, '#7cb342', [3, 3]);
  line((p) => p.z, '#1565c0');
  ctx.strokeStyle = '#9aa59d';
  ctx.strokeRect(pad, pad, w - 2 * pad, h - 2 * pad);
  ctx.fillStyle = '#333';
  ctx.font = '10px system-ui';
  ctx.fillText(`${Math.round(hi)} m`, pad + 2, pad - 4);
  ctx.fillText(`${Math.round(lo)} m`, pad + 2, h - 4);
  ctx.fillText(`${(d / 1000).toFixed(2)} km`, w - pad - 40, h - 4);
}
