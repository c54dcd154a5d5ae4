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
  corridor: { color: '#1565c0', weight: 4, opacity: 0.8, dashArray: '10 5' },
};

// ---- drawing ----
map.pm.setGlobalOptions({ allowSelfIntersection: false, snappable: true });

const groupOf = (kind) => ({ field: state.fields, nfz: state.zones, obstacle: state.obstacles, structure: state.structures })[kind];

function addPolygon(kind, latlngs, height) {
  const layer = L.polygon(latlngs, styles[kind]);
  layer.cpKind = kind;
  layer.on('pm:edit', changed);
  if (kind === 'obstacle') {
    layer.cpHeight = height;
    layer.bindTooltip(`${height} m`);
  }
  groupOf(kind).addLayer(layer);
  return layer;
}

/** A corridor: its centre line (latlngs) and its whole width in metres. */
function addCorridor(latlngs, width) {
  const layer = L.polyline(latlngs, styles.corridor);
  Object.assign(layer, { cpKind: 'centre-line', cpWidth: width });
  layer.on('pm:edit', changed);
  layer.bindTooltip(`corridor ${width} m wide`);
  state.corridors.addLayer(layer);
  return layer;
}

/** A structure to inspect: a footprint (or a circle, for a silo) with its height, base and name. */
function addStructure(shape, { height, base = 0, name }) {
  const layer = shape.radius ? L.circle(shape.centre, { radius: shape.radius, ...styles.structure }) : L.polygon(shape, styles.structure);
  Object.assign(layer, { cpKind: 'structure', cpHeight: height, cpBase: base, cpName: name || `structure-${state.structures.getLayers().length + 1}` });
  layer.on('pm:edit', changed);
  layer.bindTooltip(`${layer.cpName}: ${height} m`);
  state.structures.addLayer(layer);
  return layer;
}

/** Whether `p` lies inside `ring` (latlngs, not closed): the even-odd rule. */
function insideRing(p, ring) {
  let inside = false;
  for (let i = 0, j = ring.length - 1; i < ring.length; j = i++) {
    const [a, b] = [ring[i], ring[j]];
    if ((a.lat > p.lat) !== (b.lat > p.lat) && p.lng < ((b.lng - a.lng) * (p.lat - a.lat)) / (b.lat - a.lat) + a.lng) inside = !inside;
  }
  return inside;
}

/** Whether segments ab and cd cross. */
function crosses(a, b, c, d) {
  const side = (p, q, r) => Math.sign((q.lng - p.lng) * (r.lat - p.lat) - (q.lat - p.lat) * (r.lng - p.lng));
  return side(a, b, c) * side(a, b, d) < 0 && side(c, d, a) * side(c, d, b) < 0;
}

const edges = (ring) => ring.map((p, i) => [p, ring[(i + 1) % ring.length]]);

/** Whether `ring` lies inside `outer`: every corner inside, no edge crossing it (a notch). */
function ringWithin(ring, outer) {
  return ring.every((p) => insideRing(p, outer)) && !edges(ring).some(([a, b]) => edges(outer).some(([c, d]) => crosses(a, b, c, d)));
}

/** Whether two rings overlap: an edge crosses, or one holds a corner of the other. */
const ringsOverlap = (r, s) => insideRing(r[0], s) || insideRing(s[0], r) || edges(r).some(([a, b]) => edges(s).some(([c, d]) => crosses(a, b, c, d)));

/** Adds `ring` as a hole of the field it lies in; says why not when it lies in none. */
function cutHole(ring) {
  const field = state.fields.getLayers().find((f) => ringWithin(ring, f.getLatLngs()[0]));
  if (!field) return drawingError('A hole must lie inside a field: this one reaches outside every field. Draw it again, inside the field.');
  const [outer, ...holes] = field.getLatLngs();
  if (holes.some((h) => ringsOverlap(ring, h))) return drawingError('This hole overlaps another hole of the field: draw it apart, or edit the other one.');
  field.setLatLngs([outer, ...holes, ring]);
  changed();
}

/** A drawing refused: said beside the drawing tools, where the user is looking. */
function drawingError(text) {
  $('draw-error').textContent = text;
  $('draw-error').hidden = false;
}

function poseIcon(kind, heading) {
  const glyph = kind === 'home' ? '⌂' : kind === 'landing-site' ? 'L' : heading == null ? (kind === 'start' ? 'S' : 'E') : '➤';
  const rotate = kind !== 'home' && heading != null ? `transform: rotate(${heading - 90}deg);` : '';
  return L.divIcon({ className: 'pose', html: `<div title="${kind}" style="${rotate}">${glyph}</div>`, iconSize: [18, 18] });
}

export function setPose(kind, latlng, heading) {
  if (state.poses[kind]) map.removeLayer(state.poses[kind]);
  // markers stay out of the tab order: the form is what the keyboard walks through
  const m = L.marker(latlng, { icon: poseIcon(kind, heading), draggable: true, title: kind, keyboard: false });
  m.cpHeading = heading;
  m.on('dragend', changed);
  state.poses[kind] = m.addTo(map);
}

/** A landing site: another place than home where sorties may land and take off again. */
export function addLandingSite(latlng) {
  const m = L.marker(latlng, { icon: poseIcon('landing-site', null), draggable: true, title: 'landing site', keyboard: false });
  m.on('dragend', changed);
  state.landingSites.addLayer(m);
}

/** Places the point of `kind` at `latlng`: a landing site is added to the others, a pose moved. */
function placePoint(kind, latlng, heading) {
  if (kind === 'landing-site') addLandingSite(latlng);
  else setPose(kind, latlng, heading);
}

const isPoint = (kind) => ['home', 'start', 'end', 'landing-site'].includes(kind);

/** Ends every drawing, editing and removing mode. */
export function endModes() {
  if (map.pm.globalDrawModeEnabled()) map.pm.disableDraw();
  if (map.pm.globalEditModeEnabled()) map.pm.disableGlobalEditMode();
  if (map.pm.globalRemovalModeEnabled()) map.pm.disableGlobalRemovalMode();
  syncModeButtons();
}

function syncModeButtons() {
  $('edit').setAttribute('aria-pressed', String(map.pm.globalEditModeEnabled()));
  $('remove').setAttribute('aria-pressed', String(map.pm.globalRemovalModeEnabled()));
  $('draw-help').textContent = map.pm.globalEditModeEnabled()
    ? 'Drag a corner to move it, drag a midpoint to add one, right-click (or long-press) a corner to delete it. Escape ends editing.'
    : map.pm.globalRemovalModeEnabled() ? 'Click a shape to delete it. Escape ends deleting.' : '';
}

/** "lat, lon" (or "lat lon") as a LatLng; `null` when it is not one. */
export function parseLatLng(text) {
  const m = /^\s*(-?\d+(?:\.\d+)?)\s*[,; ]\s*(-?\d+(?:\.\d+)?)\s*$/.exec(text);
  if (!m) return null;
  const [lat, lng] = [Number(m[1]), Number(m[2])];
  return Math.abs(lat) <= 90 && Math.abs(lng) <= 180 ? L.latLng(lat, lng) : null;
}

function poseHeading(kind) {
  const h = $('pose-heading').value;
  return kind === 'home' || h === '' ? null : Number(h);
}

$('draw').onclick = () => {
  endModes();
  $('draw-error').hidden = true;
  const kind = $('draw-kind').value;
  if (isPoint(kind)) {
    // typed coordinates place the point at once; without them, the next click does
    const typed = $('point-at').value.trim();
    if (typed) {
      const at = parseLatLng(typed);
      if (!at) return drawingError('Type the point as "latitude, longitude", for example 51.985, 5.664.');
      placePoint(kind, at, poseHeading(kind));
      map.panTo(at);
      $('point-at').value = '';
      return changed();
    }
    map.pm.enableDraw('Marker', { markerStyle: { icon: poseIcon(kind, null) } });
  } else if ($('point-at').value.trim()) {
    const corners = $('point-at').value.split(/[;\n]/).map((c) => c.trim()).filter(Boolean).map(parseLatLng);
    const least = kind === 'centre-line' ? 2 : 3;
    if (corners.length < least || corners.some((c) => !c)) return drawingError(`Type at least ${least === 2 ? 'two points' : 'three corners'} as "latitude, longitude", separated by semicolons.`);
    addShape(kind, corners);
    $('point-at').value = '';
    map.fitBounds(L.latLngBounds(corners), { padding: [20, 20], maxZoom: 17 });
  } else if (kind === 'centre-line') {
    map.pm.enableDraw('Line', { pathOptions: styles.corridor });
  } else {
    map.pm.enableDraw('Polygon', { pathOptions: styles[kind === 'hole' ? 'field' : kind] });
  }
};

/** Adds a drawn or typed outline as the kind chosen. */
function addShape(kind, ring) {
  if (kind === 'hole') return cutHole(ring);
  if (kind === 'centre-line') {
    const width = Number($('corridor-width').value);
    if (!(width > 0 && width <= 2000)) return drawingError('Give the corridor a width of 1 to 2 000 m.');
    addCorridor(ring, width);
    return changed();
  }
  if (kind === 'structure') addStructure(ring, { height: Number($('obstacle-height').value), name: $('structure-name').value.trim() || undefined });
  else addPolygon(kind, ring, Number($('obstacle-height').value));
  changed();
}

$('edit').onclick = () => {
  const on = !map.pm.globalEditModeEnabled();
  endModes();
  if (on) map.pm.enableGlobalEditMode({ allowSelfIntersection: false });
  syncModeButtons();
};
$('remove').onclick = () => {
  const on = !map.pm.globalRemovalModeEnabled();
  endModes();
  if (on) map.pm.enableGlobalRemovalMode();
  syncModeButtons();
};

map.on('pm:remove', (e) => {
  for (const group of [state.fields, state.corridors, state.zones, state.obstacles, state.structures, state.landingSites]) group.removeLayer(e.layer);
  for (const k of Object.keys(state.poses)) if (state.poses[k] === e.layer) state.poses[k] = null;
  changed();
});

// Escape ends whatever is being drawn, edited or deleted; Ctrl+Z and Ctrl+Y undo and redo
document.addEventListener('keydown', (e) => {
  if (e.key === 'Escape') endModes();
  const typing = ['INPUT', 'SELECT', 'TEXTAREA'].includes(document.activeElement?.tagName);
  if (!(e.ctrlKey || e.metaKey) || typing) return;
  if (e.key === 'z' && !e.shiftKey) { e.preventDefault(); undo(); }
  if (e.key === 'y' || (e.key === 'Z' && e.shiftKey)) { e.preventDefault(); redo(); }
});

// a corner that would make the outline cross itself is not added: say so while drawing (the
// event comes as the line to the pointer turns red)
map.on('pm:intersect', () => drawingError('An outline may not cross itself: a corner there is not added. Click elsewhere, or press Escape to start again.'));

map.on('pm:create', (e) => {
  const kind = $('draw-kind').value;
  map.removeLayer(e.layer);
  if (e.shape === 'Marker') {
    // one click places the point; the mode ends there
    map.pm.disableDraw();
    placePoint(kind, e.layer.getLatLng(), poseHeading(kind));
    changed();
  } else if (e.shape === 'Line') {
    addShape(kind, e.layer.getLatLngs());
  } else {
    addShape(kind, e.layer.getLatLngs()[0]);
  }
});

function syncDrawInputs() {
  const kind = $('draw-kind').value;
  $('height-box').hidden = !['obstacle', 'structure'].includes(kind);
  $('corridor-width-box').hidden = kind !== 'centre-line';
  $('structure-name-box').hidden = kind !== 'structure';
  $('heading-box').hidden = !['start', 'end'].includes(kind);
  // typed coordinates draw without a mouse: a point, or a shape's corners
  $('point-label').textContent = isPoint(kind) ? 'at' : 'corners';
  $('point-at').placeholder = isPoint(kind) ? 'lat, lon (or click the map)' : 'lat, lon; lat, lon; … (or click the map)';
  $('draw').textContent = isPoint(kind) ? 'Place' : 'Draw';
}
$('draw-kind').onchange = syncDrawInputs;
syncDrawInputs();

/** Removes every shape and point from the map (the mission's id stays). */
function clearShapes() {
  endModes();
  state.fields.clearLayers();
  state.corridors.clearLayers();
  state.zones.clearLayers();
  state.obstacles.clearLayers();
  state.structures.clearLayers();
  state.landingSites.clearLayers();
  for (const k of Object.keys(state.poses)) {
    if (state.poses[k]) map.removeLayer(state.poses[k]);
    state.poses[k] = null;
  }
}

export function clearMission() {
  clearShapes();
  state.missionId = null;
  $('mission-name').value = 'New field';
  $('draw-error').hidden = true;
  resetHistory();
  announceChange();
  loadTerrain().catch(() => {});
}

// ---- what changed: undo and redo, the area, stale results ----
// each change keeps the mission as it was (its GeoJSON with the start and end poses): undo and
// redo put one back
const edits = { past: [], future: [], now: null };
const snapshot = () => JSON.stringify({ ...geometryOf(), start: poseOf('start'), end: poseOf('end'), landing_sites: landingSites() });
const poseOf = (kind) => {
  const m = state.poses[kind];
  return m ? { at: [m.getLatLng().lng, m.getLatLng().lat], heading: m.cpHeading ?? null } : null;
};

/** The landing sites as the API takes them: `[[lon, lat], …]`. */
export const landingSites = () => state.landingSites.getLayers().map((m) => [m.getLatLng().lng, m.getLatLng().lat]);

function resetHistory() {
  edits.past = [];
  edits.future = [];
  edits.now = snapshot();
  syncHistoryButtons();
}

function syncHistoryButtons() {
  $('undo').disabled = !edits.past.length;
  $('redo').disabled = !edits.future.length;
}

/** Called after every change a user makes to the mission. */
function changed() {
  const now = snapshot();
  if (now === edits.now) return;
  edits.past.push(edits.now);
  if (edits.past.length > 100) edits.past.shift();
  edits.future = [];
  edits.now = now;
  syncHistoryButtons();
  announceChange();
}

function restore(text) {
  const m = JSON.parse(text);
  clearShapes();
  drawShapes(m);
  for (const kind of ['start', 'end']) if (m[kind]) setPose(kind, L.latLng(m[kind].at[1], m[kind].at[0]), m[kind].heading);
  for (const [lng, lat] of m.landing_sites || []) addLandingSite(L.latLng(lat, lng));
  edits.now = text;
  syncHistoryButtons();
  announceChange();
}

export function undo() {
  if (!edits.past.length) return;
  edits.future.push(edits.now);
  restore(edits.past.pop());
}

export function redo() {
  if (!edits.future.length) return;
  edits.past.push(edits.now);
  restore(edits.future.pop());
}
$('undo').onclick = undo;
$('redo').onclick = redo;

/** Square metres of a ring of latlngs, on a plane tangent at its middle (fields are small). */
function ringArea(ring) {
  const R = 6371008.8, rad = Math.PI / 180;
  const lat0 = ring.reduce((s, p) => s + p.lat, 0) / ring.length;
  const k = Math.cos(lat0 * rad);
  let twice = 0;
  for (let i = 0, j = ring.length - 1; i < ring.length; j = i++) twice += (ring[j].lng * k * rad * R) * (ring[i].lat * rad * R) - (ring[i].lng * k * rad * R) * (ring[j].lat * rad * R);
  return Math.abs(twice) / 2;
}

/** The fields' area less their holes, in hectares. */
export function fieldHectares() {
  return state.fields.getLayers().reduce((sum, f) => {
    const [outer, ...holes] = f.getLatLngs();
    return sum + ringArea(outer) - holes.reduce((h, r) => h + ringArea(r), 0);
  }, 0) / 1e4;
}

/** The mission changed: its area and the first-step prompt follow; the results of the mission
 * as it was are stale (app.js clears them). */
function announceChange() {
  const n = state.fields.getLayers().length;
  const corridors = state.corridors.getLayers();
  // a corridor's length along its centre line (metres on the map's sphere)
  const km = corridors.reduce((sum, l) => sum + l.getLatLngs().reduce((d, p, i, all) => d + (i ? map.distance(all[i - 1], p) : 0), 0), 0) / 1000;
  const parts = [n ? `${n} field${n > 1 ? 's' : ''} · ${fieldHectares().toFixed(2)} ha` : '', corridors.length ? `${corridors.length} corridor${corridors.length > 1 ? 's' : ''} · ${km.toFixed(2)} km` : ''];
  $('mission-area').textContent = parts.filter(Boolean).join(' · ') || 'no field yet';
  $('first-step').hidden = n + corridors.length > 0;
  document.dispatchEvent(new CustomEvent('mission-changed'));
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

/** The mission's shapes and home as the API takes them (the area may be missing). */
function geometryOf() {
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
  // corridors are LineString features of the area with their width, beside the fields
  const corridors = state.corridors.getLayers().map((l) => ({
    type: 'Feature', properties: { width_m: l.cpWidth }, geometry: { type: 'LineString', coordinates: l.getLatLngs().map((p) => [p.lng, p.lat]) },
  }));
  const fields = multi(state.fields);
  const area = corridors.length ? { type: 'FeatureCollection', features: [...(fields ? [{ type: 'Feature', properties: {}, geometry: fields }] : []), ...corridors] } : fields;
  return {
    area,
    no_fly_zones: multi(state.zones),
    obstacles: obstacles.length ? { type: 'FeatureCollection', features: obstacles } : null,
    structures: structures.length ? { type: 'FeatureCollection', features: structures } : null,
    home: home ? [home.lng, home.lat] : null,
  };
}

function missionBody() {
  const body = { name: $('mission-name').value || 'Unnamed field', ...geometryOf() };
  if (!body.area) throw new Error('draw at least one field first');
  return body;
}

/** Polygons (with holes) of any GeoJSON geometry, Feature or FeatureCollection, as Leaflet rings. */
export function polygonsOf(g) {
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

/** Draws a mission's shapes and home (GeoJSON, as the API gives them). */
function drawShapes(m) {
  polygonsOf(m.area).forEach((p) => addPolygon('field', p));
  for (const f of (m.area && m.area.features) || (m.area && m.area.type === 'Feature' ? [m.area] : [])) {
    if (f.geometry && f.geometry.type === 'LineString' && f.properties && f.properties.width_m) {
      addCorridor(f.geometry.coordinates.map(([lng, lat]) => L.latLng(lat, lng)), f.properties.width_m);
    }
  }
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
}

/** Shows a mission (opened, imported): its shapes, name and model; undo starts from it. */
export function drawMission(m) {
  clearShapes();
  state.missionId = m.id || null;
  $('mission-name').value = m.name || 'New field';
  $('draw-error').hidden = true;
  drawShapes(m);
  const drawn = L.featureGroup([...state.fields.getLayers(), ...state.corridors.getLayers()]);
  if (drawn.getLayers().length) map.fitBounds(drawn.getBounds(), { padding: [20, 20] });
  resetHistory();
  announceChange();
  loadTerrain().catch((e) => status(e.message, true));
}

export async function saveMission() {
  const body = missionBody();
  const m = state.missionId ? await api('PUT', `/api/v1/missions/${state.missionId}`, body) : await api('POST', '/api/v1/missions', body);
  state.missionId = m.id;
  window.history.replaceState(null, '', `/?mission=${m.id}`);
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

// ---- files opened or dropped on the map: the server reads them (GeoJSON, KML, KMZ, shapefile
// zip, ISOXML TaskData, QGroundControl .plan) and stores the mission ----
/** A message about a file without the server's pointer into it (`/doc.kml/…`). */
const plainly = (text) => String(text).replace(/^\/\S*: /, '');

async function importFile(file) {
  if (isTerrainFile(file.name)) return terrainOf(file);
  try {
    const r = await authorisedFetch('/api/v1/missions/import', { method: 'POST', body: file });
    const m = await r.json();
    if (!r.ok) throw new Error(m.detail);
    drawMission(m);
    // the file's guidance lines are offered to a ground vehicle's plan
    document.dispatchEvent(new CustomEvent('guidance-lines', { detail: m.guidance || [] }));
    window.history.replaceState(null, '', `/?mission=${m.id}`);
    await listMissions();
    status(`imported ${file.name}` + (m.warnings.length ? `; ${m.warnings.map(plainly).join('; ')}` : ''));
  } catch (err) {
    status(`${file.name}: ${plainly(err.message)}`, true);
  }
}
const mapEl = $('map');
mapEl.addEventListener('dragover', (e) => e.preventDefault());
mapEl.addEventListener('drop', (e) => {
  e.preventDefault();
  const file = e.dataTransfer.files[0];
  if (file) importFile(file);
});
$('import-file').onchange = (e) => {
  const file = e.target.files[0];
  e.target.value = '';
  if (file) importFile(file);
};

// ---- going to a place typed as "lat, lon" ----
$('goto').onsubmit = (e) => {
  e.preventDefault();
  const at = parseLatLng($('goto-at').value);
  $('goto-at').setAttribute('aria-invalid', String(!at));
  if (!at) return status('Type a place as "latitude, longitude", for example 51.985, 5.664.', true);
  map.setView(at, Math.max(map.getZoom(), 16));
};

resetHistory();
announceChange();
