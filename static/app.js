// coverplan's map page: draw a mission, plan it, look at the result. Plain script, no build step.
'use strict';

const $ = (id) => document.getElementById(id);
const api = async (method, path, body) => {
  const r = await fetch(path, { method, headers: body ? { 'Content-Type': 'application/json' } : {}, body: body ? JSON.stringify(body) : undefined });
  const text = await r.text();
  const data = text ? JSON.parse(text) : null;
  if (!r.ok) {
    const where = data && data.pointer ? ` (at ${data.pointer})` : '';
    throw new Error(data && data.detail ? data.detail + where : `${method} ${path}: ${r.status}`);
  }
  return data;
};

const state = {
  missionId: null,
  fields: L.featureGroup(), // polygons with holes
  zones: L.featureGroup(),
  obstacles: L.featureGroup(),
  poses: { home: null, start: null, end: null },
  result: null, // { layer, photos, stats, features }
  compared: null,
  planId: null,
};

const map = L.map('map', { zoomControl: true }).setView([51.5, 6.06], 15);
L.control.scale({ imperial: false }).addTo(map);
state.fields.addTo(map);
state.zones.addTo(map);
state.obstacles.addTo(map);
window.coverplan = { map, state }; // for the browser test and the curious

const styles = {
  field: { color: '#2e7d32', weight: 2, fillOpacity: 0.1 },
  nfz: { color: '#c62828', weight: 2, fillOpacity: 0.25, dashArray: '4 3' },
  obstacle: { color: '#6d4c41', weight: 2, fillOpacity: 0.3 },
};

function status(text, isError) {
  $('status').textContent = text;
  $('status').className = isError ? 'error' : '';
}

// ---- map tiles: only when the server is configured with a tile URL (works offline without) ----
api('GET', '/api/v1/ui-config').then((c) => {
  if (c && c.tile_url) L.tileLayer(c.tile_url, { maxZoom: 20, attribution: c.tile_attribution || '' }).addTo(map);
}).catch(() => {});

// ---- drawing ----
map.pm.setGlobalOptions({ allowSelfIntersection: false, snappable: true });

function addPolygon(kind, latlngs, height) {
  const layer = L.polygon(latlngs, styles[kind]);
  layer.cpKind = kind;
  if (kind === 'obstacle') {
    layer.cpHeight = height;
    layer.bindTooltip(`${height} m`);
  }
  (kind === 'field' ? state.fields : kind === 'nfz' ? state.zones : state.obstacles).addLayer(layer);
  return layer;
}

/** Adds `ring` as a hole of the field that contains it. */
function cutHole(ring) {
  const inside = state.fields.getLayers().find((f) => ring.every((p) => f.getBounds().contains(p)));
  if (!inside) return status('a hole must be drawn inside a field', true);
  const rings = inside.getLatLngs();
  inside.setLatLngs([...rings, ring]);
}

function poseIcon(kind, heading) {
  const glyph = kind === 'home' ? '⌂' : heading == null ? (kind === 'start' ? 'S' : 'E') : '➤';
  const rotate = kind !== 'home' && heading != null ? `transform: rotate(${heading - 90}deg);` : '';
  return L.divIcon({ className: 'pose', html: `<div title="${kind}" style="${rotate}">${glyph}</div>`, iconSize: [18, 18] });
}

function setPose(kind, latlng, heading) {
  if (state.poses[kind]) map.removeLayer(state.poses[kind]);
  const m = L.marker(latlng, { icon: poseIcon(kind, heading), draggable: true, title: kind });
  m.cpHeading = heading;
  state.poses[kind] = m.addTo(map);
}

$('draw').onclick = () => {
  const kind = $('draw-kind').value;
  if (['home', 'start', 'end'].includes(kind)) {
    map.pm.enableDraw('Marker', { markerStyle: { icon: poseIcon(kind, null) } });
  } else {
    map.pm.enableDraw('Polygon', { pathOptions: styles[kind === 'hole' ? 'field' : kind] });
  }
};

map.on('pm:create', (e) => {
  const kind = $('draw-kind').value;
  map.removeLayer(e.layer);
  if (e.shape === 'Marker') {
    const h = $('pose-heading').value;
    setPose(kind, e.layer.getLatLng(), kind === 'home' || h === '' ? null : Number(h));
  } else if (kind === 'hole') {
    cutHole(e.layer.getLatLngs()[0]);
  } else {
    addPolygon(kind, e.layer.getLatLngs(), Number($('obstacle-height').value));
  }
});

function syncDrawInputs() {
  const kind = $('draw-kind').value;
  $('height-box').hidden = kind !== 'obstacle';
  $('heading-box').hidden = !['start', 'end'].includes(kind);
}
$('draw-kind').onchange = syncDrawInputs;
syncDrawInputs();

function clearMission() {
  state.fields.clearLayers();
  state.zones.clearLayers();
  state.obstacles.clearLayers();
  for (const k of Object.keys(state.poses)) {
    if (state.poses[k]) map.removeLayer(state.poses[k]);
    state.poses[k] = null;
  }
  state.missionId = null;
}
$('clear').onclick = () => { clearMission(); clearResult(); history.replaceState(null, '', '/'); };

// ---- mission ⇄ GeoJSON ----
const ringOf = (latlngs) => {
  const r = latlngs.map((p) => [p.lng, p.lat]);
  r.push(r[0]);
  return r;
};
const polygonOf = (layer) => {
  const rings = layer.getLatLngs();
  const list = Array.isArray(rings[0]) ? rings : [rings];
  return list.map(ringOf);
};
const multi = (group) => {
  const polys = group.getLayers().map(polygonOf);
  return polys.length ? { type: 'MultiPolygon', coordinates: polys } : null;
};

function missionBody() {
  const area = multi(state.fields);
  if (!area) throw new Error('draw at least one field first');
  const obstacles = state.obstacles.getLayers().map((l) => ({
    type: 'Feature', properties: { height_m: l.cpHeight }, geometry: { type: 'Polygon', coordinates: polygonOf(l) },
  }));
  const home = state.poses.home && state.poses.home.getLatLng();
  return {
    name: $('mission-name').value || 'Unnamed field',
    area,
    no_fly_zones: multi(state.zones),
    obstacles: obstacles.length ? { type: 'FeatureCollection', features: obstacles } : null,
    home: home ? [home.lng, home.lat] : null,
  };
}

/** Polygons (with holes) of any GeoJSON geometry, Feature or FeatureCollection, as Leaflet rings. */
function polygonsOf(g) {
  if (!g) return [];
  const toLatLngs = (poly) => poly.map((ring) => ring.slice(0, -1).map(([lng, lat]) => L.latLng(lat, lng)));
  switch (g.type) {
    case 'FeatureCollection': return g.features.flatMap((f) => polygonsOf(f));
    case 'Feature': return polygonsOf(g.geometry).map((p) => Object.assign(p, { properties: g.properties || {} }));
    case 'Polygon': return [toLatLngs(g.coordinates)];
    case 'MultiPolygon': return g.coordinates.map(toLatLngs);
    default: return [];
  }
}

function drawMission(m) {
  clearMission();
  state.missionId = m.id || null;
  $('mission-name').value = m.name || 'New field';
  polygonsOf(m.area).forEach((p) => addPolygon('field', p));
  polygonsOf(m.no_fly_zones).forEach((p) => addPolygon('nfz', p));
  polygonsOf(m.obstacles).forEach((p) => addPolygon('obstacle', p, (p.properties && p.properties.height_m) || 20));
  if (m.home) setPose('home', L.latLng(m.home[1], m.home[0]), null);
  if (state.fields.getLayers().length) map.fitBounds(state.fields.getBounds(), { padding: [20, 20] });
}

async function saveMission() {
  const body = missionBody();
  const m = state.missionId ? await api('PUT', `/api/v1/missions/${state.missionId}`, body) : await api('POST', '/api/v1/missions', body);
  state.missionId = m.id;
  history.replaceState(null, '', `/?mission=${m.id}`);
  await listMissions();
  return m;
}
$('save').onclick = () => saveMission().then((m) => status(`saved as ${m.id}`)).catch((e) => status(e.message, true));

async function listMissions() {
  const page = await api('GET', '/api/v1/missions?limit=100');
  const sel = $('missions');
  sel.innerHTML = '<option value="">—</option>' + page.items.map((m) => `<option value="${m.id}">${escapeHtml(m.name)}</option>`).join('');
  if (state.missionId) sel.value = state.missionId;
}
const escapeHtml = (s) => String(s).replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' })[c]);

async function openMission(id) {
  const m = await api('GET', `/api/v1/missions/${id}`);
  drawMission(m);
  history.replaceState(null, '', `/?mission=${id}`);
  clearResult();
  const plans = await api('GET', `/api/v1/missions/${id}/plans`);
  const latest = plans.find((p) => p.status === 'succeeded');
  if (latest) {
    restoreParams(latest.params);
    await showPlan(latest);
  }
  $('missions').value = id;
}
$('missions').onchange = (e) => e.target.value && openMission(e.target.value).catch((err) => status(err.message, true));

// ---- files dropped on the map ----
function kmlToGeoJson(text) {
  const doc = new DOMParser().parseFromString(text, 'application/xml');
  const ring = (el) => el.textContent.trim().split(/\s+/).map((t) => t.split(',').slice(0, 2).map(Number));
  const polys = [...doc.getElementsByTagName('Polygon')].map((p) => {
    const outer = p.getElementsByTagName('outerBoundaryIs')[0];
    const inner = [...p.getElementsByTagName('innerBoundaryIs')];
    return [outer, ...inner].map((b) => ring(b.getElementsByTagName('coordinates')[0]));
  });
  return { type: 'MultiPolygon', coordinates: polys };
}

const mapEl = $('map');
mapEl.addEventListener('dragover', (e) => e.preventDefault());
mapEl.addEventListener('drop', async (e) => {
  e.preventDefault();
  const file = e.dataTransfer.files[0];
  if (!file) return;
  try {
    const text = await file.text();
    const data = /\.kml$/i.test(file.name) || text.trimStart().startsWith('<') ? kmlToGeoJson(text) : JSON.parse(text);
    if (data.area) {
      drawMission({ ...data, id: null });
    } else {
      const polys = polygonsOf(data);
      if (!polys.length) throw new Error('no polygon in this file');
      polys.forEach((p) => addPolygon('field', p));
      map.fitBounds(state.fields.getBounds(), { padding: [20, 20] });
    }
    status(`loaded ${file.name}`);
  } catch (err) {
    status(`${file.name}: ${err.message}`, true);
  }
});

// ---- the parameter form, from the API's lists ----
async function fillForm() {
  const [planners, vehicles, cameras] = await Promise.all([api('GET', '/api/v1/planners'), api('GET', '/api/v1/vehicles'), api('GET', '/api/v1/cameras')]);
  $('planner').innerHTML = planners.map((p) => `<option value="${p.id}" title="${escapeHtml(p.description)}">${p.id}</option>`).join('');
  $('vehicle').innerHTML = vehicles.map((v) => `<option value="${v.profile}" title="${escapeHtml(v.description)}">${v.profile} (${v.kind.replace('_', ' ')})</option>`).join('');
  $('vehicle').value = 'generic_multirotor';
  $('camera').innerHTML += cameras.map((c) => `<option value="${c.id}">${escapeHtml(c.name || c.id)}</option>`).join('');
  syncForm();
}

function syncForm() {
  const camera = $('camera').value !== '';
  $('spacing-box').hidden = camera;
  $('fixed-heading-box').hidden = $('direction').value !== 'fixed';
  $('objective-box').hidden = $('planner').value !== 'auto';
}
['camera', 'direction', 'planner'].forEach((id) => $(id).addEventListener('change', syncForm));

const num = (id) => ($(id).value === '' ? undefined : Number($(id).value));

function planParams() {
  const p = { planner: $('planner').value, vehicle: { profile: $('vehicle').value } };
  if ($('camera').value) {
    p.camera = { preset: $('camera').value };
    p.side_overlap = num('side-overlap');
    p.front_overlap = num('front-overlap');
    if (num('gsd') !== undefined) p.gsd_cm = num('gsd');
  } else {
    p.line_spacing_m = num('spacing');
  }
  if (num('altitude') !== undefined && p.gsd_cm === undefined) p.altitude_m = num('altitude');
  if ($('direction').value === 'fixed') p.heading_deg = num('fixed-heading');
  if ($('direction').value === 'optimal') p.sweep_direction = 'optimal';
  if (p.planner === 'auto') p.objective = $('objective').value;
  for (const kind of ['start', 'end']) {
    const m = state.poses[kind];
    if (m) {
      const at = m.getLatLng();
      p[kind] = { position: [at.lng, at.lat] };
      if (m.cpHeading != null) p[kind].heading_deg = m.cpHeading;
    }
  }
  return p;
}

function restoreParams(p) {
  if (!p) return;
  const set = (id, v) => { if (v !== undefined && v !== null) $(id).value = v; };
  set('planner', p.planner);
  set('vehicle', p.vehicle && p.vehicle.profile);
  $('camera').value = (p.camera && p.camera.preset) || '';
  set('spacing', p.line_spacing_m);
  set('altitude', p.altitude_m);
  set('gsd', p.gsd_cm);
  $('direction').value = p.heading_deg !== undefined ? 'fixed' : p.sweep_direction === 'optimal' ? 'optimal' : 'planner';
  set('fixed-heading', p.heading_deg);
  set('objective', p.objective);
  syncForm();
}

// ---- planning ----
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

$('plan').onclick = async () => {
  try {
    $('plan').disabled = true;
    await saveMission();
    const queued = await api('POST', `/api/v1/missions/${state.missionId}/plans`, planParams());
    state.planId = queued.id;
    $('cancel').disabled = false;
    $('progress').hidden = false;
    let plan = queued;
    while (['queued', 'running'].includes(plan.status)) {
      $('progress').value = plan.progress || 0;
      status(`${plan.status}…`);
      await sleep(300);
      plan = await api('GET', `/api/v1/plans/${queued.id}`);
    }
    if (plan.status === 'succeeded') {
      if ($('compare').checked && state.result) keepForComparison();
      await showPlan(plan);
      status(`planned in ${Math.round(plan.stats.planning_time_ms)} ms`);
    } else {
      status(plan.status === 'failed' ? `failed: ${plan.error}` : plan.status, plan.status === 'failed');
    }
  } catch (e) {
    status(e.message, true);
  } finally {
    $('plan').disabled = false;
    $('cancel').disabled = true;
    $('progress').hidden = true;
    state.planId = null;
  }
};

$('cancel').onclick = () => state.planId && api('DELETE', `/api/v1/plans/${state.planId}`).catch((e) => status(e.message, true));

// ---- the result ----
const kindStyle = {
  sweep: { color: '#1565c0', weight: 3 },
  turn: { color: '#ef6c00', weight: 2 },
  transit: { color: '#6a1b9a', weight: 2, dashArray: '6 4' },
};

function bearing(a, b) {
  const rad = Math.PI / 180;
  const y = Math.sin((b[0] - a[0]) * rad) * Math.cos(b[1] * rad);
  const x = Math.cos(a[1] * rad) * Math.sin(b[1] * rad) - Math.sin(a[1] * rad) * Math.cos(b[1] * rad) * Math.cos((b[0] - a[0]) * rad);
  return (Math.atan2(y, x) / rad + 360) % 360;
}

function drawTrajectory(fc, faded) {
  const group = L.featureGroup();
  const lines = fc.features.filter((f) => f.geometry.type === 'LineString');
  L.geoJSON({ type: 'FeatureCollection', features: lines }, {
    style: (f) => ({ ...kindStyle[f.properties.kind], opacity: faded ? 0.35 : 0.9 }),
    onEachFeature: (f, layer) => layer.bindTooltip(`${f.properties.kind} ${f.properties.length_m} m, ${f.properties.speed_mps} m/s, sortie ${f.properties.sortie}`),
  }).addTo(group);
  if (!faded) {
    // flight direction on every sweep
    for (const f of lines.filter((f) => f.properties.kind === 'sweep')) {
      const c = f.geometry.coordinates;
      const a = c[0], b = c[c.length - 1];
      const mid = [(a[0] + b[0]) / 2, (a[1] + b[1]) / 2];
      const icon = L.divIcon({ className: 'arrow', html: `<div style="transform: rotate(${bearing(a, b) - 90}deg)">➤</div>`, iconSize: [14, 14] });
      L.marker([mid[1], mid[0]], { icon, interactive: false }).addTo(group);
    }
    if (lines.length) {
      const first = lines[0].geometry.coordinates[0];
      const lastLine = lines[lines.length - 1].geometry.coordinates;
      const last = lastLine[lastLine.length - 1];
      L.circleMarker([first[1], first[0]], { radius: 7, color: '#1b5e20', fillOpacity: 1 }).bindTooltip('start').addTo(group);
      L.circleMarker([last[1], last[0]], { radius: 7, color: '#b71c1c', fillOpacity: 1 }).bindTooltip('end').addTo(group);
    }
  }
  const photos = L.featureGroup();
  for (const f of fc.features.filter((f) => f.properties.kind === 'photos')) {
    f.geometry.coordinates.forEach((c) => L.circleMarker([c[1], c[0]], { radius: 2, color: '#37474f' }).addTo(photos));
  }
  return { layer: group.addTo(map), photos };
}

function clearResult() {
  for (const r of [state.result, state.compared]) {
    if (r) { map.removeLayer(r.layer); map.removeLayer(r.photos); }
  }
  state.result = null;
  state.compared = null;
  $('download').hidden = true;
  renderFigures();
  drawChart();
}

function keepForComparison() {
  if (state.compared) { map.removeLayer(state.compared.layer); map.removeLayer(state.compared.photos); }
  map.removeLayer(state.result.layer);
  map.removeLayer(state.result.photos);
  state.compared = { ...state.result, ...drawTrajectory(state.result.fc, true) };
  state.result = null;
}

async function showPlan(plan) {
  const fc = await api('GET', `/api/v1/plans/${plan.id}/trajectory`);
  if (state.result) { map.removeLayer(state.result.layer); map.removeLayer(state.result.photos); }
  state.result = { ...drawTrajectory(fc, false), fc, stats: plan.stats, params: plan.params };
  $('download').href = `/api/v1/plans/${plan.id}/trajectory`;
  $('download').download = `plan-${plan.id}.geojson`;
  $('download').hidden = false;
  togglePhotos();
  renderFigures();
  drawChart();
}

function togglePhotos() {
  const r = state.result;
  if (!r) return;
  if ($('show-photos').checked) r.photos.addTo(map); else map.removeLayer(r.photos);
}
$('show-photos').onchange = togglePhotos;

const figureRows = [
  ['planner', (s, p) => s.planner || (p && p.planner)],
  ['length', (s) => `${(s.length_m / 1000).toFixed(2)} km`],
  ['flight time', (s) => `${(s.duration_s / 60).toFixed(1)} min`],
  ['energy', (s) => `${s.energy_wh.toFixed(1)} Wh`],
  ['coverage', (s) => `${(100 * s.coverage_ratio).toFixed(1)} %`],
  ['efficiency', (s) => `${(100 * s.efficiency).toFixed(1)} %`],
  ['turns', (s) => s.turns],
  ['sorties', (s) => s.sorties],
  ['photos', (s) => s.photos],
];

function renderFigures() {
  const a = state.result, b = state.compared;
  $('col-b').hidden = !b;
  $('figures').tBodies[0].innerHTML = a
    ? figureRows.map(([name, f]) => `<tr><td>${name}</td><td data-figure="${name}">${f(a.stats, a.params)}</td>${b ? `<td>${f(b.stats, b.params)}</td>` : ''}</tr>`).join('')
    : '';
}

/** Speed and energy used against the distance flown. */
function drawChart() {
  const canvas = $('chart');
  const ctx = canvas.getContext('2d');
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  if (!state.result) return;
  const lines = state.result.fc.features.filter((f) => f.geometry.type === 'LineString');
  const points = [];
  let d = 0;
  for (const f of lines) {
    points.push({ d, v: f.properties.speed_mps, e: f.properties.cumulative_energy_j - f.properties.energy_j });
    d += f.properties.length_m;
    points.push({ d, v: f.properties.speed_mps, e: f.properties.cumulative_energy_j });
  }
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

// ---- start ----
(async () => {
  try {
    await fillForm();
    await listMissions();
    const id = new URLSearchParams(location.search).get('mission');
    if (id) await openMission(id);
    document.body.dataset.ready = 'true';
  } catch (e) {
    status(e.message, true);
    document.body.dataset.ready = 'true';
  }
})();
