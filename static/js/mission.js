// The mission: drawing fields, holes, zones, obstacles, structures and poses; GeoJSON in and out;
// saving, listing and dropped files.

import { $, api, authorisedFetch, escapeHtml, status } from './api.js';
import { map, state } from './map.js';
import { isTerrainFile, loadTerrain, uploadTerrain } from './terrain.js';

const styles = {
  field: { color: '#2e7d32', weight: 2, fillOpacity: 0.1 },
  nfz: { color: '#c62828', weight: 2, fillOpacity: 0.25, dashArray: '4 3' },
  obstacle: { color: '#6d4c41', weight: 2, fillOpacity: 0.3 },
  structure: { color: '#455a64', weight: 2, fillOpacity: 0.45 },
};

// ---- drawing ----
map.pm.setGlobalOptions({ allowSelfIntersection: false, snappable: true });

const groupOf = (kind) => ({ field: state.fields, nfz: state.zones, obstacle: state.obstacles, structure: state.structures })[kind];

function addPolygon(kind, latlngs, height) {
  const layer = L.polygon(latlngs, styles[kind]);
  layer.cpKind = kind;
  if (kind === 'obstacle') {
    layer.cpHeight = height;
    layer.bindTooltip(`${height} m`);
  }
  groupOf(kind).addLayer(layer);
  return layer;
}

/** A structure to inspect: a footprint (or a circle, for a silo) with its height, base and name. */
function addStructure(shape, { height, base = 0, name }) {
  const layer = shape.radius ? L.circle(shape.centre, { radius: shape.radius, ...styles.structure }) : L.polygon(shape, styles.structure);
  Object.assign(layer, { cpKind: 'structure', cpHeight: height, cpBase: base, cpName: name || `structure-${state.structures.getLayers().length + 1}` });
  layer.bindTooltip(`${layer.cpName}: ${height} m`);
  state.structures.addLayer(layer);
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

export function setPose(kind, latlng, heading) {
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

// Escape ends whatever is being drawn
document.addEventListener('keydown', (e) => {
  if (e.key === 'Escape' && map.pm.globalDrawModeEnabled()) map.pm.disableDraw();
});

map.on('pm:create', (e) => {
  const kind = $('draw-kind').value;
  map.removeLayer(e.layer);
  if (e.shape === 'Marker') {
    // one click places the point; the mode ends there
    map.pm.disableDraw();
    const h = $('pose-heading').value;
    setPose(kind, e.layer.getLatLng(), kind === 'home' || h === '' ? null : Number(h));
  } else if (kind === 'hole') {
    cutHole(e.layer.getLatLngs()[0]);
  } else if (kind === 'structure') {
    addStructure(e.layer.getLatLngs(), { height: Number($('obstacle-height').value), name: $('structure-name').value.trim() || undefined });
  } else {
    addPolygon(kind, e.layer.getLatLngs(), Number($('obstacle-height').value));
  }
});

function syncDrawInputs() {
  const kind = $('draw-kind').value;
  $('height-box').hidden = !['obstacle', 'structure'].includes(kind);
  $('structure-name-box').hidden = kind !== 'structure';
  $('heading-box').hidden = !['start', 'end'].includes(kind);
}
$('draw-kind').onchange = syncDrawInputs;
syncDrawInputs();

export function clearMission() {
  state.fields.clearLayers();
  state.zones.clearLayers();
  state.obstacles.clearLayers();
  state.structures.clearLayers();
  for (const k of Object.keys(state.poses)) {
    if (state.poses[k]) map.removeLayer(state.poses[k]);
    state.poses[k] = null;
  }
  state.missionId = null;
  loadTerrain().catch(() => {});
}

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
  const structures = state.structures.getLayers().map((l) => {
    if (l.cpFeature) return l.cpFeature; // a model, kept as it came
    const properties = { name: l.cpName, height_m: l.cpHeight, base_m: l.cpBase };
    if (l instanceof L.Circle) {
      const c = l.getLatLng();
      return { type: 'Feature', properties: { ...properties, radius_m: l.getRadius() }, geometry: { type: 'Point', coordinates: [c.lng, c.lat] } };
    }
    return { type: 'Feature', properties, geometry: { type: 'Polygon', coordinates: polygonOf(l) } };
  });
  const home = state.poses.home && state.poses.home.getLatLng();
  return {
    name: $('mission-name').value || 'Unnamed field',
    area,
    no_fly_zones: multi(state.zones),
    obstacles: obstacles.length ? { type: 'FeatureCollection', features: obstacles } : null,
    structures: structures.length ? { type: 'FeatureCollection', features: structures } : null,
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

export function drawMission(m) {
  clearMission();
  state.missionId = m.id || null;
  $('mission-name').value = m.name || 'New field';
  polygonsOf(m.area).forEach((p) => addPolygon('field', p));
  polygonsOf(m.no_fly_zones).forEach((p) => addPolygon('nfz', p));
  polygonsOf(m.obstacles).forEach((p) => addPolygon('obstacle', p, (p.properties && p.properties.height_m) || 20));
  for (const f of (m.structures && m.structures.features) || []) {
    const p = f.properties || {};
    const solid = { height: p.height_m, base: p.base_m || 0, name: p.name };
    if (p.obj) {
      // a 3D model (Wavefront OBJ) anchored at its point: shown as a marker, saved unchanged
      const [lng, lat] = f.geometry.coordinates;
      const icon = L.divIcon({ className: 'pose', html: '<div title="model">▣</div>', iconSize: [18, 18] });
      const marker = L.marker(L.latLng(lat, lng), { icon, title: p.name || 'model' }).bindTooltip(`${p.name || 'model'} (3D model)`);
      marker.cpFeature = f;
      state.structures.addLayer(marker);
    } else if (f.geometry.type === 'Point') addStructure({ centre: L.latLng(f.geometry.coordinates[1], f.geometry.coordinates[0]), radius: p.radius_m }, solid);
    else polygonsOf(f.geometry).forEach((rings) => addStructure(rings, solid));
  }
  if (m.home) setPose('home', L.latLng(m.home[1], m.home[0]), null);
  if (state.fields.getLayers().length) map.fitBounds(state.fields.getBounds(), { padding: [20, 20] });
  loadTerrain().catch((e) => status(e.message, true));
}

export async function saveMission() {
  const body = missionBody();
  const m = state.missionId ? await api('PUT', `/api/v1/missions/${state.missionId}`, body) : await api('POST', '/api/v1/missions', body);
  state.missionId = m.id;
  history.replaceState(null, '', `/?mission=${m.id}`);
  await listMissions();
  return m;
}
$('save').onclick = () => saveMission().then((m) => status(`saved as ${m.id}`)).catch((e) => status(e.message, true));

export async function listMissions() {
  const page = await api('GET', '/api/v1/missions?limit=100&fields=summary');
  const sel = $('missions');
  sel.innerHTML = '<option value="">—</option>' + page.items.map((m) => `<option value="${m.id}">${escapeHtml(m.name)}</option>`).join('');
  if (state.missionId) sel.value = state.missionId;
}

/** Stores the mission (the model belongs to it) and `file` as its elevation model. */
async function terrainOf(file) {
  try {
    const m = await saveMission();
    await uploadTerrain(file, m.id);
  } catch (err) {
    status(`${file.name}: ${err.message}`, true);
  }
}
$('terrain-file').onchange = (e) => {
  const file = e.target.files[0];
  e.target.value = '';
  if (file) terrainOf(file);
};

// ---- files dropped on the map: the server reads them (GeoJSON, KML, KMZ, shapefile zip,
// ISOXML TaskData, QGroundControl .plan) and stores the mission ----
const mapEl = $('map');
mapEl.addEventListener('dragover', (e) => e.preventDefault());
mapEl.addEventListener('drop', async (e) => {
  e.preventDefault();
  const file = e.dataTransfer.files[0];
  if (!file) return;
  if (isTerrainFile(file.name)) return terrainOf(file);
  try {
    const r = await authorisedFetch('/api/v1/missions/import', { method: 'POST', body: file });
    const m = await r.json();
    if (!r.ok) throw new Error(m.detail + (m.pointer ? ` (at ${m.pointer})` : ''));
    drawMission(m);
    history.replaceState(null, '', `/?mission=${m.id}`);
    await listMissions();
    status(`imported ${file.name}` + (m.warnings.length ? `; ${m.warnings.join('; ')}` : ''));
  } catch (err) {
    status(`${file.name}: ${err.message}`, true);
  }
});
