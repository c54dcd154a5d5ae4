// The result: the trajectory on the map, the figures table and the speed and energy chart.

import { $, api, authorisedFetch, escapeHtml, hasApiKey, status } from './api.js';
import { map, notForDrawing, state } from './map.js';
import { hide3d, show3d } from './view3d.js';
import { drawProfile } from './terrain.js';

// ---- the result ----
const kindStyle = {
  sweep: { color: '#1565c0', weight: 3 },
  headland: { color: '#00897b', weight: 3, dashArray: '10 3' },
  turn: { color: '#ef6c00', weight: 2 },
  transit: { color: '#6a1b9a', weight: 2, dashArray: '6 4' },
};
const tramlineStyle = { color: '#2e7d32', weight: 5 };

/** Compass bearing from `a` to `b` ([lon, lat]), degrees from north. */
export function bearing(a, b) {
  const rad = Math.PI / 180;
  const y = Math.sin((b[0] - a[0]) * rad) * Math.cos(b[1] * rad);
  const x = Math.cos(a[1] * rad) * Math.sin(b[1] * rad) - Math.sin(a[1] * rad) * Math.cos(b[1] * rad) * Math.cos((b[0] - a[0]) * rad);
  return (Math.atan2(y, x) / rad + 360) % 360;
}

// a fleet's drones, each in its own colour (the kind still shows in weight and dashes)
const droneColours = ['#1565c0', '#2e7d32', '#c2185b', '#ef6c00', '#6a1b9a', '#00838f', '#5d4037', '#9e9d24'];
export const droneColour = (k) => droneColours[k % droneColours.length];

function drawTrajectory(fc, faded) {
  const group = L.featureGroup();
  const lines = fc.features.filter((f) => f.geometry.type === 'LineString');
  // a tramline swath is drawn wider, in its own colour
  const own = (p) => (p.tramline ? { ...kindStyle[p.kind], ...tramlineStyle } : kindStyle[p.kind]);
  const style = (p) => (p.vehicle === undefined ? own(p) : { ...own(p), color: droneColour(p.vehicle) });
  const drone = (p) => (p.vehicle === undefined ? '' : `drone ${p.vehicle + 1}, `);
  L.geoJSON({ type: 'FeatureCollection', features: lines }, {
    pane: 'result',
    style: (f) => ({ ...style(f.properties), opacity: faded ? 0.35 : 0.9, className: `kind-${f.properties.kind}${f.properties.tramline ? ' tramline' : ''}` }),
    onEachFeature: (f, layer) => {
      const p = f.properties;
      const shape = p.turn_type ? ` (${p.turn_type === 'u' ? 'U' : p.turn_type})` : '';
      const sortie = p.sortie === undefined ? '' : `, sortie ${p.sortie}`;
      // in wind: over the ground and through the air, and the nose's angle to the track
      const air = p.ground_speed_mps === undefined ? `${p.speed_mps} m/s` : `${p.ground_speed_mps} m/s over the ground, ${p.airspeed_mps} m/s airspeed, crab ${p.crab_deg}°`;
      layer.bindTooltip(`${drone(p)}${p.kind}${p.tramline ? ' (tramline)' : ''}${shape} ${p.length_m} m, ${air}${sortie}`);
      // a click says where a flight stopped (resume.js offers to plan the rest)
      if (!faded) layer.on('click', (e) => document.dispatchEvent(new CustomEvent('coverplan:piece-click', { detail: { feature: f, latlng: e.latlng } })));
    },
  }).addTo(group);
  if (!faded) {
    // flight direction on every sweep
    for (const f of lines.filter((f) => f.properties.kind === 'sweep')) {
      const c = f.geometry.coordinates;
      const a = c[0], b = c[c.length - 1];
      const mid = [(a[0] + b[0]) / 2, (a[1] + b[1]) / 2];
      const icon = L.divIcon({ className: 'arrow', html: `<div style="transform: rotate(${bearing(a, b) - 90}deg)">➤</div>`, iconSize: [14, 14] });
      L.marker([mid[1], mid[0]], { icon, interactive: false, keyboard: false }).addTo(group);
    }
    if (lines.length) {
      const first = lines[0].geometry.coordinates[0];
      const lastLine = lines[lines.length - 1].geometry.coordinates;
      const last = lastLine[lastLine.length - 1];
      L.circleMarker([first[1], first[0]], { radius: 7, color: '#1b5e20', fillOpacity: 1 }).bindTooltip('start').addTo(group);
      L.circleMarker([last[1], last[0]], { radius: 7, color: '#b71c1c', fillOpacity: 1 }).bindTooltip('end').addTo(group);
    }
  }
  // what a flight log shows flown, beside what is left (a resumed plan's)
  for (const f of fc.features.filter((f) => f.properties.kind === 'flown')) {
    L.geoJSON(f, { pane: 'result', interactive: false, style: { color: '#616161', weight: 2, dashArray: '2 5', opacity: faded ? 0.35 : 0.8, className: 'kind-flown' } }).addTo(group);
  }
  // ground no sweep covers: mostly the clearance kept around no-fly zones
  for (const f of fc.features.filter((f) => f.properties.kind === 'uncovered')) {
    // amber, unlike the no-fly zones' red
    L.geoJSON(f, { style: { color: '#ff8f00', weight: 0, fillColor: '#ffb300', fillOpacity: faded ? 0.15 : 0.45, className: 'uncovered' }, interactive: !faded })
      .bindTooltip(`not covered: ${Math.round(f.properties.area_m2)} m² (the clearance around no-fly zones, nfz_margin_m, and corners the lines do not reach)`)
      .addTo(group);
  }
  // without a home: where each battery runs out
  for (const f of fc.features.filter((f) => f.properties.kind === 'battery_swap')) {
    const [lng, lat] = f.geometry.coordinates;
    L.circleMarker([lat, lng], { radius: 6, color: '#f9a825', fillOpacity: 1, className: 'battery-swap' })
      .bindTooltip(`battery ${f.properties.battery} runs out here: change it`).addTo(group);
  }
  // an inspection's viewpoints, in flight order
  for (const f of fc.features.filter((f) => f.properties.kind === 'viewpoint')) {
    const [lng, lat, z] = f.geometry.coordinates;
    const p = f.properties;
    L.circleMarker([lat, lng], { radius: 4, color: '#ef6c00', fillOpacity: faded ? 0.3 : 0.9, className: 'viewpoint' })
      .bindTooltip(`viewpoint ${p.order}: ${z} m up, facing ${Math.round(p.yaw_deg)}°, gimbal ${Math.round(p.gimbal_pitch_deg)}°, ${p.new_pois_seen} new points`)
      .addTo(group);
  }
  const photos = L.featureGroup();
  for (const f of fc.features.filter((f) => f.properties.kind === 'photos')) {
    f.geometry.coordinates.forEach((c) => L.circleMarker([c[1], c[0]], { radius: 2, color: '#37474f', interactive: false }).addTo(photos));
  }
  return { layer: notForDrawing(group).addTo(map), photos: notForDrawing(photos) };
}

export function clearResult() {
  for (const r of [state.result, state.compared]) {
    if (r) { map.removeLayer(r.layer); map.removeLayer(r.photos); }
  }
  state.result = null;
  state.compared = null;
  hide3d();
  $('download-box').hidden = true;
  renderFigures();
  drawChart();
  drawProfile();
}

/** Forgets the plan kept for comparison. */
export function dropComparison() {
  if (!state.compared) return;
  map.removeLayer(state.compared.layer);
  map.removeLayer(state.compared.photos);
  state.compared = null;
  renderFigures();
}
$('compare').onchange = () => { if (!$('compare').checked) dropComparison(); };

export function keepForComparison() {
  if (state.compared) { map.removeLayer(state.compared.layer); map.removeLayer(state.compared.photos); }
  map.removeLayer(state.result.layer);
  map.removeLayer(state.result.photos);
  state.compared = { ...state.result, ...drawTrajectory(state.result.fc, true) };
  state.result = null;
}

export async function showPlan(plan) {
  const fc = await api('GET', `/api/v1/plans/${plan.id}/trajectory`);
  if (state.result) { map.removeLayer(state.result.layer); map.removeLayer(state.result.photos); }
  state.result = { ...drawTrajectory(fc, false), fc, stats: plan.stats, params: plan.params };
  state.result.planId = plan.id;
  updateDownload();
  $('download-box').hidden = false;
  togglePhotos();
  renderFigures();
  drawChart();
  drawProfile();
  if (plan.stats.inspection) show3d(fc);
  else hide3d();
  document.dispatchEvent(new CustomEvent('coverplan:plan-shown'));
}

function togglePhotos() {
  const r = state.result;
  if (!r) return;
  if ($('show-photos').checked) r.photos.addTo(map); else map.removeLayer(r.photos);
}
$('show-photos').onchange = togglePhotos;

// diesel's energy per litre (lower heating value, about 36 MJ): a ground vehicle's energy is fuel
export const DIESEL_J_PER_L = 36e6;
const onGround = (s) => Boolean(s.ground);
const hours = (seconds) => (seconds >= 5400 ? `${Math.floor(seconds / 3600)} h ${Math.round((seconds % 3600) / 60)} min` : `${(seconds / 60).toFixed(1)} min`);

// each row: its label (by the plan's kind) and its value; a row no shown plan has is left out
const figureRows = [
  ['planner', (s, p) => s.planner || (p && p.planner)],
  ['vehicle', (s, p) => p && p.vehicle && (p.vehicles > 1 ? `${p.vehicles} × ${p.vehicle.profile}` : p.vehicle.profile)],
  ['length', (s) => `${(s.length_m / 1000).toFixed(2)} km`],
  [(s) => (onGround(s) ? 'working time' : 'flight time'), (s) => hours(s.duration_s)],
  [(s) => (onGround(s) ? 'fuel' : 'energy'), (s) => (onGround(s) ? `${(s.energy_j / DIESEL_J_PER_L).toFixed(1)} l of diesel` : `${s.energy_wh.toFixed(1)} Wh`)],
  ['altitude', (s, p, fc) => (onGround(s) || s.inspection ? '' : altitudeFlown(s, p, fc))],
  ['line spacing', (s) => (s.inspection ? '' : `${s.line_spacing_m.toFixed(1)} m`)],
  ['coverage', (s) => (s.inspection ? '' : `${(100 * s.coverage_ratio).toFixed(1)} %`)],
  // the covered area over the spacing, per metre flown: the API's efficiency counts the whole
  // area, which a plan that leaves some unflown can seem to beat (over 100 %)
  ['efficiency', (s) => (s.inspection ? '' : `${(100 * s.efficiency * Math.min(1, s.coverage_ratio)).toFixed(1)} %`)],
  ['points seen', (s) => (s.inspection ? `${(100 * s.inspection_coverage).toFixed(1)} % (${s.inspection.pois_seen} of ${s.inspection.pois})` : '')],
  ['viewpoints', (s) => (s.inspection ? `${s.inspection.viewpoints} of ${s.inspection.viewpoints_sampled} sampled` : '')],
  ['targets', (s) => (s.inspection ? s.inspection.targets.map((t) => `${t.name} ${t.face} ${(100 * t.coverage).toFixed(0)} %`).join(', ') : '')],
  ['turns', (s) => s.turns],
  ['sorties', (s) => (onGround(s) ? '' : s.sorties)],
  ['last landing', (s) => (s.makespan_s == null ? '' : `${(s.makespan_s / 60).toFixed(1)} min`)],
  ['conflicts', (s) => (s.conflicts == null ? '' : s.conflicts.length)],
  ['photos', (s) => (s.photos ? s.photos : '')],
  // an oblique plan's passes: the camera's pitch and heading, photos and length of each
  ['passes', (s) => (s.passes ? s.passes.map((p) => `${p.camera_heading_deg == null ? 'nadir' : `${Math.round(p.camera_heading_deg)}° at ${p.gimbal_pitch_deg}°`}: ${p.photos} photos, ${(p.length_m / 1000).toFixed(2)} km`).join('; ') : '')],
  ['wind', (s) => (s.wind ? windFigure(s) : '')],
  ['resumed at', (s) => (s.resume ? `piece ${s.resume.seq}, ${Math.round(100 * s.resume.fraction)} % along (${(s.resume.original_left_m / 1000).toFixed(2)} km were left)` : '')],
  ['mainland worked', (s) => (s.ground ? `${(100 * s.ground.mainland_coverage).toFixed(1)} %` : '')],
  ['headland worked', (s) => (s.ground ? `${(100 * s.ground.headland_coverage).toFixed(1)} % (${s.ground.headland_passes} passes, ${s.ground.headland_width_m.toFixed(1)} m)` : '')],
  ['tramlines', (s) => (s.ground && s.ground.tramlines ? s.ground.tramlines : '')],
  ['turn shapes', (s) => (s.ground ? `${s.ground.u_turns} U, ${s.ground.omega_turns} Ω, ${s.ground.fishtail_turns} fishtail, ${s.ground.headland_drives} along a pass${s.ground.corner_manoeuvres ? `, ${s.ground.corner_manoeuvres} corners worked` : ''}` : '')],
  ['turns leaving the field', (s) => (s.ground ? s.ground.turns_leaving_field + s.ground.turns_crossing_holes : '')],
];

/** The wind a plan was made for (an arrow pointing downwind), and what planning for it saved
 * against the plan made as in still air, flown in the same wind. */
function windFigure(s) {
  const w = s.wind;
  const arrow = `<span class="wind-arrow" style="transform: rotate(${w.from_deg + 90}deg)">➤</span>`;
  const less = (mine, theirs, what) => (theirs > 0 ? `${(100 * (1 - mine / theirs)).toFixed(1)} % ${what}` : '');
  const saved = [less(s.energy_j, w.still_air_plan_energy_j, 'energy'), less(s.duration_s, w.still_air_plan_duration_s, 'time')].filter(Boolean);
  const against = saved.length ? ` · saves ${saved.join(', ')} against the still-air plan in this wind` : '';
  return `${arrow} ${w.speed_mps.toFixed(1)} m/s from ${Math.round(w.from_deg)}°${against}`;
}

/** A fleet's drones, one row each, in their colours. */
function renderFleet(stats) {
  const drones = (stats && stats.vehicles) || [];
  $('fleet-figures').hidden = !drones.length;
  const min = (s) => `${(s / 60).toFixed(1)} min`;
  $('fleet-figures').tBodies[0].innerHTML = drones
    .map((v) => `<tr data-drone="${v.vehicle}"><td><span class="sw" style="background:${droneColour(v.vehicle)}"></span>${v.vehicle + 1} ${v.profile}</td>`
      + `<td>${(v.area_m2 / 1e4).toFixed(2)}</td><td>${v.sweep_lines}</td><td>${v.sorties}</td><td>${min(v.departure_s)}</td><td>${min(v.landing_s)}</td>`
      + `<td>${(v.energy_j / 3600).toFixed(1)}</td></tr>`)
    .join('');
}

/** The altitude the sweeps are flown at (the trajectory's own heights: a GSD sets it), and the
 * GSD that gives with the plan's camera. */
function altitudeFlown(s, p, fc) {
  if (s.terrain) return `${s.terrain.sweep_height_above_ground_m.map((h) => h.toFixed(1)).join(' to ')} m above the ground on sweeps`;
  const sweep = fc && fc.features.find((f) => f.properties.kind === 'sweep');
  const z = sweep && sweep.geometry.coordinates[0][2];
  if (z == null) return '';
  const cam = p && p.camera && (state.cameras || []).find((c) => c.id === p.camera.preset);
  const gsd = cam ? ` · GSD ${((cam.sensor_width_mm * z * 100) / (cam.focal_length_mm * cam.image_width_px)).toFixed(2)} cm/px` : '';
  return `${z.toFixed(1)} m above home${gsd}`;
}

/** What tells two plans apart, for their columns' heads: the planner, the vehicle, or else the
 * parameters that differ. */
export function columnLabels(a, b) {
  if (!b) return ['this plan', ''];
  if (a.stats.resume) return ['what is left', 'the original (kept)'];
  const planner = (r) => r.stats.planner || r.params.planner;
  const vehicle = (r) => (r.params.vehicles > 1 ? `${r.params.vehicles} × ` : '') + ((r.params.vehicle && r.params.vehicle.profile) || 'default');
  const parts = [[planner(a), planner(b)], [vehicle(a), vehicle(b)]].filter(([x, y]) => x !== y);
  if (!parts.length) {
    const keys = [...new Set([...Object.keys(a.params), ...Object.keys(b.params)])].filter((k) => JSON.stringify(a.params[k]) !== JSON.stringify(b.params[k]));
    parts.push(...keys.map((k) => [`${k} ${JSON.stringify(a.params[k] ?? '—')}`, `${k} ${JSON.stringify(b.params[k] ?? '—')}`]));
  }
  if (!parts.length) return ['this plan', 'the same, kept'];
  return [parts.map((p) => p[0]).join(', '), `${parts.map((p) => p[1]).join(', ')} (kept)`];
}

function renderFigures() {
  const a = state.result, b = state.compared;
  renderFleet(a && a.stats);
  $('col-b').hidden = !b;
  const [headA, headB] = a ? columnLabels(a, b) : ['this plan', ''];
  $('col-a').textContent = headA;
  $('col-b').textContent = headB;
  const shown = [a, b].filter(Boolean);
  $('figures').tBodies[0].innerHTML = shown.length && a
    ? figureRows
      .map(([label, f]) => [typeof label === 'function' ? label(a.stats) : label, shown.map((r) => f(r.stats, r.params, r.fc))])
      .filter(([, values]) => values.some((v) => v !== '' && v !== undefined && v !== null))
      .map(([name, [va, vb]]) => `<tr><td>${name}</td><td data-figure="${name}">${va ?? ''}</td>${b ? `<td>${vb ?? ''}</td>` : ''}</tr>`)
      .join('')
    : '';
}

/** Speed and energy used against the distance flown. */
export function drawChart() {
  const canvas = $('chart');
  const ctx = canvas.getContext('2d');
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  if (!state.result) return;
  const lines = state.result.fc.features.filter((f) => f.geometry.type === 'LineString');
  // energy as a running total over the whole plan: each sortie's own count restarts at zero
  // each sortie's climb to altitude and descent from it (stats.takeoff_landing_energy_j) is shared
  // out at its start and end, so that the chart ends at the table's energy
  const points = [];
  const s = state.result.stats;
  const flightOf = (f) => `${f.properties.vehicle ?? 0}/${f.properties.sortie ?? 1}`;
  const flights = lines.filter((f, i) => i === 0 || flightOf(f) !== flightOf(lines[i - 1])).length;
  const perEnd = (s.takeoff_landing_energy_j || 0) / Math.max(1, flights) / 2;
  let d = 0;
  let e = 0;
  for (const [i, f] of lines.entries()) {
    // a landing and a take-off between flights, a take-off before the first
    if (i === 0 || flightOf(f) !== flightOf(lines[i - 1])) e += i === 0 ? perEnd : 2 * perEnd;
    points.push({ d, v: f.properties.speed_mps, e });
    d += f.properties.length_m;
    e += f.properties.energy_j;
    points.push({ d, v: f.properties.speed_mps, e });
  }
  if (points.length) points.push({ d, v: 0, e: e + perEnd });
  state.chart = points; // read by the browser test
  if (!points.length || d === 0) return;
  const w = canvas.width, h = canvas.height, pad = 18;
  const vmax = Math.max(...points.map((p) => p.v), 1);
  const emax = Math.max(...points.map((p) => p.e), 1);
  const x = (p) => pad + (p.d / d) * (w - 2 * pad);
  const plot = (key, max, color) => {
    ctx.strokeStyle = color;
    ctx.beginPath();
    points.forEach((p, i) => { const y = h - pad - (p[key] / max) * (h - 2 * pad); i ? ctx.lineTo(x(p), y) : ctx.moveTo(x(p), y); });
    ctx.stroke();
  };
  ctx.strokeStyle = '#9aa59d';
  ctx.strokeRect(pad, pad, w - 2 * pad, h - 2 * pad);
  plot('v', vmax, '#1565c0');
  plot('e', emax, '#c62828');
  ctx.fillStyle = '#333';
  ctx.font = '10px system-ui';
  ctx.fillText(`${vmax.toFixed(1)} m/s`, pad + 2, pad - 4);
  ctx.fillText(`${(emax / 3600).toFixed(1)} Wh`, w - pad - 50, pad - 4);
  ctx.fillText(`${(d / 1000).toFixed(2)} km`, w - pad - 40, h - 4);
}

/** The download menu, from the server's formats (`GET /api/v1/formats`), in its order. */
export async function fillFormats() {
  const formats = await api('GET', '/api/v1/formats');
  $('download-format').innerHTML = formats
    .map(
      (f) =>
        `<option value="${f.id}" data-firmware="${f.firmware_commands}" data-limit="${f.waypoint_limit}" data-default-limit="${f.default_max_waypoints ?? ''}" title="${escapeHtml(f.media_type)}">${escapeHtml(f.label)}</option>`,
    )
    .join('');
  updateDownload();
}

/** The download link for the chosen format; the server names the file after the mission. */
function updateDownload() {
  const format = $('download-format').value;
  const chosen = $('download-format').selectedOptions[0]?.dataset ?? {};
  $('firmware-box').hidden = chosen.firmware !== 'true';
  // a controller's waypoint limit: the formats it loads, with the format's own default shown
  $('max-waypoints-box').hidden = chosen.limit !== 'true';
  $('download-max-waypoints').placeholder = chosen.defaultLimit ? `default ${chosen.defaultLimit}` : 'no limit';
  if (!state.result) return;
  const firmware = $('firmware-box').hidden ? '' : `&firmware=${$('download-firmware').value}`;
  const limit = $('max-waypoints-box').hidden || !$('download-max-waypoints').value ? '' : `&max_waypoints=${$('download-max-waypoints').value}`;
  $('download').href = `/api/v1/plans/${state.result.planId}/trajectory?format=${format}${firmware}${limit}`;
}
// a link cannot send the API key: with one, the file is fetched and saved from memory
$('download').onclick = async (e) => {
  if (!hasApiKey()) return;
  e.preventDefault();
  const r = await authorisedFetch($('download').getAttribute('href'));
  if (!r.ok) return status(`download: ${r.status}`, true);
  const name = /filename="([^"]+)"/.exec(r.headers.get('content-disposition') || '');
  const save = document.createElement('a');
  save.href = URL.createObjectURL(await r.blob());
  save.download = name ? name[1] : 'trajectory';
  save.click();
  setTimeout(() => URL.revokeObjectURL(save.href), 10000);
};
$('download-format').onchange = updateDownload;
$('download-firmware').onchange = updateDownload;
$('download-max-waypoints').oninput = updateDownload;
