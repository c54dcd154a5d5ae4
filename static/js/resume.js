// Resume: a click on the plan's path, or the flight's log (chosen or dropped on the map), says
// where the flight stopped; the server plans what is left (POST /api/v1/plans/{id}/resume),
// shown over the original, which stays faded beside it (with the track the log flew).

import { $, api, authorisedFetch, escapeHtml, status } from './api.js';
import { map, state } from './map.js';
import { keepForComparison, showPlan } from './result.js';

/** The share of the polyline `coords` ([lon, lat]) up to its point nearest `latlng`. */
export function fractionAlong(coords, latlng) {
  const k = Math.cos((latlng.lat * Math.PI) / 180);
  const xy = (c) => [c[0] * k, c[1]];
  const p = [latlng.lng * k, latlng.lat];
  let total = 0;
  let best = { d: Infinity, at: 0 };
  for (let i = 1; i < coords.length; i++) {
    const a = xy(coords[i - 1]), b = xy(coords[i]);
    const dx = b[0] - a[0], dy = b[1] - a[1], len = Math.hypot(dx, dy);
    const t = len > 0 ? Math.max(0, Math.min(1, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (len * len))) : 0;
    const d = Math.hypot(a[0] + t * dx - p[0], a[1] + t * dy - p[1]);
    if (d < best.d) best = { d, at: total + t * len };
    total += len;
  }
  return total > 0 ? best.at / total : 1;
}

const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

/** Sends a flight log as the body; the answer as `api` gives it. */
async function postLog(file) {
  const r = await authorisedFetch(`/api/v1/plans/${state.result.planId}/resume`, { method: 'POST', headers: { 'Content-Type': 'application/octet-stream' }, body: await file.arrayBuffer() });
  const data = await r.json().catch(() => null);
  if (!r.ok) throw new Error(data && data.detail ? `the log: ${data.detail}` : `the log: ${r.status}`);
  return data;
}

async function resume(request) {
  try {
    const queued = await request();
    $('progress').hidden = false;
    let plan = queued;
    while (['queued', 'running'].includes(plan.status)) {
      $('progress').value = plan.progress || 0;
      status(`resuming: ${plan.status}…`);
      await sleep(300);
      plan = await api('GET', `/api/v1/plans/${queued.id}`);
    }
    if (plan.status !== 'succeeded') return status(plan.status === 'failed' ? `resuming failed: ${plan.error}` : plan.status, true);
    // the original stays on the map, faded: what was flown and what is left side by side
    keepForComparison();
    await showPlan(plan);
    const r = plan.stats.resume;
    const redone = r.redone_m ? `, ${Math.round(r.redone_m)} m the log shows not imaged flown again` : '';
    status(`resumed: ${(plan.stats.sweep_length_m / 1000).toFixed(2)} km of lines left (the original had ${(r.original_sweep_left_m / 1000).toFixed(2)} km after the stop, ${Math.round(r.overlap_m)} m flown again${redone})`);
    $('result-heading').focus();
  } catch (e) {
    status(e.message, true);
  } finally {
    $('progress').hidden = true;
  }
}

// a piece of the shown plan clicked: offer to plan the rest from there
document.addEventListener('coverplan:piece-click', (e) => {
  const { feature, latlng } = e.detail;
  const p = feature.properties;
  if (!state.result || !state.result.planId || state.result.stats.inspection || p.seq === undefined) return;
  // a click while drawing is the drawing's
  if (map.pm && (map.pm.globalDrawModeEnabled() || map.pm.globalEditModeEnabled())) return;
  const fraction = fractionAlong(feature.geometry.coordinates, latlng);
  const box = document.createElement('div');
  box.className = 'resume-box';
  const whose = p.vehicle === undefined ? 'the' : `drone ${p.vehicle + 1}'s`;
  box.innerHTML = `<p>Did ${whose} flight stop here (${escapeHtml(p.kind)}, ${Math.round(100 * fraction)} % along)?</p>`
    + '<label>photos flown again <input class="photos-back" type="number" min="0" max="20" value="2"></label> '
    + '<button class="resume-here" type="button">Plan the rest</button>';
  const popup = L.popup().setLatLng(latlng).setContent(box).openOn(map);
  box.querySelector('.resume-here').onclick = () => {
    map.closePopup(popup);
    const photosBack = Number(box.querySelector('.photos-back').value);
    // a fleet's pieces are numbered drone by drone: the drone is named
    resume(() => api('POST', `/api/v1/plans/${state.result.planId}/resume`, { at: { seq: p.seq, fraction, vehicle: p.vehicle }, photos_back: photosBack }));
  };
});

// a flight log: chosen, or dropped on the map while a plan is shown
const resumable = () => state.result && state.result.planId && !state.result.stats.inspection;
$('resume-log').addEventListener('change', (e) => {
  const file = e.target.files[0];
  e.target.value = '';
  if (file && resumable()) resume(() => postLog(file));
});
// a dropped field file is the import's (mission.js); a log is told by its name
const isLog = (file) => /\.(tlog|ulg|bin)$/i.test(file.name);
map.getContainer().addEventListener('drop', (e) => {
  const file = e.dataTransfer.files[0];
  if (!file || !isLog(file) || !resumable()) return;
  e.preventDefault();
  e.stopImmediatePropagation();
  resume(() => postLog(file));
}, true);
document.addEventListener('coverplan:plan-shown', () => {
  $('resume-log-box').hidden = !resumable();
});
