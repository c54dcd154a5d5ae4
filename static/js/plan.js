// The parameters form (from the API's lists), the request it makes, and the planning loop.

import { $, api, escapeHtml, status } from './api.js';
import { state } from './map.js';
import { addLandingSite, fieldHectares, landingSites, saveMission, setPose } from './mission.js';
import { DIESEL_J_PER_L, bearing, fillFormats, keepForComparison, showPlan } from './result.js';

// ---- the parameter form, from the API's lists ----
const kindNames = { multirotor: 'Multirotor drones', fixed_wing: 'Fixed-wing aircraft', ground: 'Ground vehicles' };
/** A vehicle as a person names it: its description up to the first detail, then its id. */
const vehicleName = (v) => `${(v.description || v.profile).split(/[:;(,]/)[0].trim()} (${v.profile})`;
let vehicleList = [];
let cameraList = [];

export async function fillForm() {
  const [planners, vehicles, cameras] = await Promise.all([api('GET', '/api/v1/planners'), api('GET', '/api/v1/vehicles'), api('GET', '/api/v1/cameras'), fillFormats()]);
  catalogue = new Map(planners.map((p) => [p.id, p]));
  vehicleList = vehicles;
  cameraList = cameras;
  state.cameras = cameras;
  // a patrol has its own form (the Patrol button)
  $('planner').innerHTML = planners.filter((p) => p.method !== 'patrol').map((p) => `<option value="${p.id}" title="${escapeHtml(p.description)}">${escapeHtml(p.name)}</option>`).join('');
  $('vehicle').innerHTML = Object.entries(kindNames)
    .map(([kind, label]) => `<optgroup label="${label}">${vehicles.filter((v) => v.kind === kind).map((v) => `<option value="${v.profile}" data-kind="${v.kind}" title="${escapeHtml(v.description)}">${escapeHtml(vehicleName(v))}</option>`).join('')}</optgroup>`)
    .join('');
  $('vehicle').value = 'generic_multirotor';
  $('camera').innerHTML += cameras.map((c) => `<option value="${c.id}">${escapeHtml(c.name || c.id)}</option>`).join('');
  syncForm();
}

/** Marks the planner recommended for the chosen vehicle (the one it defaults to). */
function markRecommended() {
  const kind = vehicleKind();
  for (const o of $('planner').options) {
    const p = catalogue.get(o.value);
    o.textContent = p.name + (p.default_for.includes(kind) ? ' (recommended)' : '');
  }
}

/** The planners as `GET /api/v1/planners` describes them, by id. */
let catalogue = new Map();
const chosenPlanner = () => catalogue.get($('planner').value);
/** Whether the chosen planner reads request member `name`. */
const reads = (name) => Boolean(chosenPlanner()?.parameters.some((q) => q.name === name));
const vehicleKind = () => $('vehicle').selectedOptions[0]?.dataset.kind;

/** True when the chosen vehicle works the ground: it gets its implement's fields and a ground
 * planner instead of a camera, a line spacing and drones. */
const groundVehicle = () => vehicleKind() === 'ground';
const fixedWing = () => vehicleKind() === 'fixed_wing';

/** An inspection flies to viewpoints around the mission's structures: no lines, no sweep
 * direction, no fleet. */
const inspecting = () => chosenPlanner()?.method === 'inspection';

/** Keeps the chosen planner one that plans the chosen vehicle: the vehicle's default otherwise. */
function fitPlannerToVehicle() {
  const kind = vehicleKind();
  if (!kind || chosenPlanner()?.vehicle_kinds.includes(kind)) return;
  const fallback = [...catalogue.values()].find((p) => p.default_for.includes(kind));
  if (fallback) $('planner').value = fallback.id;
}

function syncForm() {
  fitPlannerToVehicle();
  markRecommended();
  const ground = groundVehicle();
  const inspection = !ground && inspecting();
  $('ground-box').hidden = !ground;
  $('inspection-box').hidden = !inspection;
  // a tractor has no altitude, camera, image overlaps or drones: its implement sets the swaths
  for (const id of ['camera-box', 'layers-box', 'gsd-box', 'overlap-box', 'altitude-box']) $(id).hidden = ground;
  // an inspection always has a camera: leaving it unset means the planner's default preset
  $('camera').options[0].textContent = inspection ? 'default: DJI Mavic 3 Enterprise (wide)' : 'none: give the line spacing';
  $('drones').closest('.row').hidden = ground || inspection;
  for (const id of ['altitude-box', 'direction-box']) $(id).hidden = ground ? id === 'altitude-box' : inspection;
  const camera = !ground && $('camera').value !== '';
  $('overlap-box').hidden = ground || inspection || !camera;
  $('gsd-box').hidden = ground || !camera;
  $('direction-label').textContent = ground ? 'Swath direction' : 'Sweep heading';
  $('spacing-box').hidden = camera || ground || inspection;
  $('line-ends-box').hidden = !aircraftLineEnds();
  $('guidance-typed').hidden = !ground || $('guidance').value !== 'typed';
  // a guidance line sets a tractor's swath direction
  $('direction-box').hidden = inspection || (ground && $('guidance').value !== '');
  $('fixed-heading-box').hidden = $('direction-box').hidden || $('direction').value !== 'fixed';
  $('objective-box').hidden = !reads('objective');
  $('layers-box').hidden = ground || inspection || !(num('drones') > 1);
  // how flights end: an aircraft's; the approach heading and the lead-in are a fixed wing's
  $('ends-box').hidden = ground || inspection;
  $('lead-in-box').hidden = !fixedWing();
  $('landing-heading-box').hidden = !fixedWing() || $('landing').value !== 'auto';
  $('reference-box').hidden = ground || inspection;
  // wind changes an aircraft's coverage flight, not a tractor's work or an inspection
  $('wind-box').hidden = ground || inspection;
  showWindArrow();
  $('tolerance-box').hidden = $('altitude-reference').value !== 'terrain';
  // further passes: an aircraft's, alone; obliques need a camera on a multirotor
  $('pattern-box').hidden = ground || inspection || num('drones') > 1;
  $('oblique-pitch-box').hidden = $('pattern-box').hidden || $('pattern').value !== 'oblique';
  preview();
}
['camera', 'direction', 'planner', 'drones', 'vehicle', 'altitude-reference', 'landing', 'guidance', 'pattern'].forEach((id) => $(id).addEventListener('change', syncForm));

/** The form's arrow points where the wind blows (downwind), grey in a calm. */
function showWindArrow() {
  const arrow = $('wind-arrow');
  const from = num('wind-from') ?? 0;
  // ➤ points east (90°): turn it to the downwind bearing
  arrow.style.transform = `rotate(${from + 180 - 90}deg)`;
  arrow.classList.toggle('calm', !(num('wind-speed') > 0));
}
for (const id of ['wind-speed', 'wind-from']) $(id).addEventListener('input', showWindArrow);
// a click round the arrow points it there: the wind blows that way, so it comes from the opposite
$('wind-dial').addEventListener('click', (e) => {
  const box = $('wind-dial').getBoundingClientRect();
  const towards = (Math.atan2(e.clientX - (box.left + box.width / 2), (box.top + box.height / 2) - e.clientY) * 180) / Math.PI;
  // to 10°, as weather reports give it
  $('wind-from').value = (Math.round((towards + 180 + 360) / 10) * 10) % 360;
  showWindArrow();
});

// GSD and altitude say the same thing with a camera: typing one empties the other
$('altitude').addEventListener('input', () => { if ($('altitude').value !== '') $('gsd').value = ''; });
$('gsd').addEventListener('input', () => { if ($('gsd').value !== '') $('altitude').value = ''; });
for (const id of ['altitude', 'gsd', 'side-overlap', 'front-overlap', 'spacing', 'working-width', 'drones']) $(id).addEventListener('input', () => preview());
document.addEventListener('mission-changed', () => preview());

// ---- figures before planning ----
const chosenCamera = () => cameraList.find((c) => c.id === $('camera').value);
const chosenVehicle = () => vehicleList.find((v) => v.profile === $('vehicle').value);

/** The camera's footprint figures at `altitude` (m): GSD (cm/px), across and along (m). A
 * landscape image's width lies across the lines, as the planner lays them. */
function footprint(cam, altitude) {
  const across = (cam.sensor_width_mm * altitude) / cam.focal_length_mm;
  const along = (cam.sensor_height_mm * altitude) / cam.focal_length_mm;
  return { gsd: (100 * across) / cam.image_width_px, across, along };
}

/** The altitude, spacing and photo interval the form asks for, as far as it says them. */
function layout() {
  if (groundVehicle()) return { spacing: valid('working-width') };
  const cam = chosenCamera();
  if (!cam) return { spacing: valid('spacing'), altitude: valid('altitude') };
  let altitude = valid('altitude');
  if (altitude === undefined && valid('gsd') !== undefined) altitude = (num('gsd') * cam.focal_length_mm * cam.image_width_px) / (100 * cam.sensor_width_mm);
  if (altitude === undefined) return {};
  const f = footprint(cam, altitude);
  return { altitude, gsd: f.gsd, spacing: f.across * (1 - (num('side-overlap') ?? 70) / 100), interval: f.along * (1 - (num('front-overlap') ?? 80) / 100) };
}

let previewAsked = 0;
/** The figures the form gives before planning: altitude ⇄ GSD, spacing, photo interval, and a
 * quick estimate of the sweeps' time and batteries from the vehicle's own energy model. */
async function preview() {
  const out = $('preview');
  if (inspecting() && !groundVehicle()) return (out.textContent = '');
  const l = layout();
  const parts = [];
  if (l.gsd !== undefined) {
    parts.push(num('altitude') === undefined ? `altitude ${l.altitude.toFixed(1)} m` : `GSD ${l.gsd.toFixed(2)} cm/px`);
    $(num('altitude') === undefined ? 'altitude' : 'gsd').placeholder = num('altitude') === undefined ? l.altitude.toFixed(1) : l.gsd.toFixed(2);
  }
  if (l.spacing) parts.push(`${groundVehicle() ? 'swaths' : 'lines'} ${l.spacing.toFixed(1)} m apart`);
  if (l.interval) parts.push(`a photo every ${l.interval.toFixed(1)} m`);
  const ha = fieldHectares();
  const ask = ++previewAsked;
  out.textContent = parts.join(' · ');
  const vehicle = chosenVehicle();
  if (!(ha > 0 && l.spacing > 0 && vehicle) || groundVehicle()) return;
  // the sweeps alone are the area over the spacing: flown as one straight line, priced by the
  // server's model of this vehicle (turns and transits come on top)
  const sweeps = (ha * 1e4) / l.spacing / Math.max(1, num('drones') || 1);
  try {
    const c = state.fields.getBounds().getCenter();
    const east = 1000 / (111320 * Math.cos((c.lat * Math.PI) / 180));
    const alt = l.altitude ?? 50;
    const e = await api('POST', '/api/v1/estimates', { vehicle: { profile: vehicle.profile }, waypoints: [[c.lng, c.lat, alt], [c.lng + east, c.lat, alt]] });
    if (ask !== previewAsked) return;
    const leg = e.legs[0];
    const fixedS = e.totals.duration_s - leg.duration_s;
    const fixedJ = e.totals.energy_j - leg.energy_j;
    const seconds = fixedS + (leg.duration_s * sweeps) / leg.length_m;
    const joules = fixedJ + (leg.energy_j * sweeps) / leg.length_m;
    const usable = e.totals.energy_j / e.totals.battery_used;
    parts.push(`sweeps ${(sweeps / 1000).toFixed(1)} km${num('drones') > 1 ? ' each' : ''}: at least ${(seconds / 60).toFixed(0)} min, ${Math.ceil(joules / usable)} batter${Math.ceil(joules / usable) > 1 ? 'ies' : 'y'}`);
    out.textContent = parts.join(' · ');
  } catch {
    // the estimate is a help: the plan itself says what is wrong
  }
}

/** An aircraft's plan by a planner that lays parallel lines: the line-end rule applies. */
const aircraftLineEnds = () => !groundVehicle() && !inspecting() && reads('swath_ends');

const num = (id) => ($(id).value === '' ? undefined : Number($(id).value));
/** Watt-hours in a litre of diesel. */
const WH_PER_LITRE = DIESEL_J_PER_L / 3600;
/** A value for the figures before planning: none while the input is out of its bounds. */
const valid = (id) => ($(id).checkValidity() ? num(id) : undefined);

/** An inspection's request: the budget, the faces, the camera's reach and the search. */
function inspectionParams(p) {
  p.budget = { [$('budget-kind').value]: num('budget') };
  const faces = [['walls', 'target-walls'], ['roof', 'target-roof']].filter(([, id]) => $(id).checked).map(([face]) => face);
  const names = $('target-names').value.split(',').map((n) => n.trim()).filter(Boolean);
  const both = faces.length === 2;
  p.targets = names.length ? names.map((name) => (both ? name : { name, faces })) : both ? [] : faces;
  p.inspection = { range_m: [num('range-min'), num('range-max')], safety_margin_m: num('safety-margin'), extension: $('extension').value, show_unseen: true };
  p.seed = num('inspection-seed');
  if ($('camera').value) p.camera = { preset: $('camera').value };
  if (num('gsd') !== undefined) p.gsd_cm = num('gsd');
  for (const kind of ['start', 'end']) {
    const m = state.poses[kind];
    if (m) p[kind] = { position: [m.getLatLng().lng, m.getLatLng().lat] };
  }
  return p;
}

export function planParams() {
  const p = { planner: $('planner').value, vehicle: { profile: $('vehicle').value } };
  if (!groundVehicle() && inspecting()) return inspectionParams(p);
  if (groundVehicle()) {
    Object.assign(p.vehicle, { working_width_m: num('working-width'), turn_radius_m: num('turn-radius'), reverse_allowed: $('reverse-allowed').checked });
    // a tractor's figures in a farmer's units: km/h, and litres of diesel (36 MJ, 10 kWh each)
    if (num('working-speed') !== undefined) p.vehicle.cruise_speed_mps = num('working-speed') / 3.6;
    if (num('tank-litres') !== undefined) p.vehicle.battery_wh = num('tank-litres') * WH_PER_LITRE;
    p.headland_passes = num('headland-passes');
    p.headland_order = $('headland-order').value;
    p.swath_ends = $('swath-ends').value;
    const guidance = guidanceLine();
    if (guidance) p.guidance = guidance;
    if (num('tramline-every') !== undefined) p.tramline_every = num('tramline-every');
  } else if ($('camera').value) {
    p.camera = { preset: $('camera').value };
    // the form says overlaps in percent, the API in fractions
    if (num('side-overlap') !== undefined) p.side_overlap = num('side-overlap') / 100;
    if (num('front-overlap') !== undefined) p.front_overlap = num('front-overlap') / 100;
    if (num('gsd') !== undefined) p.gsd_cm = num('gsd');
  } else {
    p.line_spacing_m = num('spacing');
  }
  // full width is an aircraft's default: sent only when another rule is chosen
  if (aircraftLineEnds() && $('line-ends').value !== 'full_width') p.swath_ends = $('line-ends').value;
  if (num('altitude') !== undefined && p.gsd_cm === undefined) p.altitude_m = num('altitude');
  if (!groundVehicle() && $('altitude-reference').value === 'terrain') {
    p.altitude_reference = 'terrain';
    p.terrain_tolerance_m = num('terrain-tolerance');
  }
  // a guidance line sets the swaths' direction
  if ($('direction').value === 'fixed' && !p.guidance) p.heading_deg = num('fixed-heading');
  if ($('direction').value === 'optimal') p.sweep_direction = 'optimal';
  if (reads('objective')) p.objective = $('objective').value;
  if (num('drones') > 1 && !groundVehicle()) {
    p.vehicles = num('drones');
    if (num('altitude-separation') !== undefined) p.altitude_separation_m = num('altitude-separation');
  }
  if (!$('pattern-box').hidden && $('pattern').value !== 'grid') p.pattern = $('pattern').value;
  if (p.pattern === 'oblique' && num('oblique-pitch') !== undefined) p.oblique_pitch_deg = num('oblique-pitch');
  if ($('landing').value === 'auto') p.landing = 'auto';
  if (!groundVehicle() && !$('wind-box').hidden && num('wind-speed') > 0) p.wind = { speed_mps: num('wind-speed'), from_deg: num('wind-from') ?? 0 };
  if (fixedWing()) {
    if (num('lead-in') !== undefined) p.lead_in_m = num('lead-in');
    if (p.landing === 'auto' && num('landing-heading') !== undefined) p.landing_heading_deg = num('landing-heading');
  }
  // one aircraft's sorties may land at the sites drawn (a fleet's drones fly from their homes)
  if (landingSites().length && !groundVehicle() && !p.vehicles) p.landing_sites = landingSites();
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

// ---- a ground vehicle's guidance line: one of the imported mission's, or an A+ line typed ----
/** Fills the guidance menu with the lines an imported file brought (`[{name, guidance}]`, the
 * event's detail). */
document.addEventListener('guidance-lines', (e) => {
  state.guidanceLines = e.detail;
  const sel = $('guidance');
  for (const o of [...sel.options].filter((o) => o.value.startsWith('imported:'))) o.remove();
  state.guidanceLines.forEach((line, i) => sel.add(new Option(`${line.name} (imported)`, `imported:${i}`)));
  if (state.guidanceLines.length) sel.value = 'imported:0';
  syncForm();
});

/** The chosen guidance line as the API takes it, or undefined. */
function guidanceLine() {
  const chosen = $('guidance').value;
  if (chosen.startsWith('imported:')) return state.guidanceLines[Number(chosen.slice('imported:'.length))]?.guidance;
  if (chosen !== 'typed') return undefined;
  // typed as the page's "go to" box takes places: latitude first
  const [lat, lon] = $('guidance-a').value.split(',').map(Number);
  return { a: [lon, lat], bearing_deg: num('guidance-bearing') };
}

/** Puts a plan's guidance line back: the imported line it is, or as an A+ line typed. */
function restoreGuidance(g) {
  const imported = state.guidanceLines.findIndex((line) => JSON.stringify(line.guidance) === JSON.stringify(g));
  $('guidance').value = !g ? '' : imported >= 0 ? `imported:${imported}` : 'typed';
  if (!g || imported >= 0) return;
  $('guidance-a').value = `${g.a[1]}, ${g.a[0]}`;
  $('guidance-bearing').value = g.bearing_deg ?? Math.round(bearing(g.a, g.b) * 1e6) / 1e6;
}

/** Puts a plan's parameters back in the form and on the map, so that a shared link shows
 * exactly what was planned. */
export function restoreParams(p) {
  if (!p) return;
  const set = (id, v) => { if (v !== undefined && v !== null) $(id).value = v; };
  set('planner', p.planner);
  set('vehicle', p.vehicle && p.vehicle.profile);
  set('working-width', p.vehicle && p.vehicle.working_width_m);
  set('turn-radius', p.vehicle && p.vehicle.turn_radius_m);
  $('reverse-allowed').checked = Boolean(p.vehicle && p.vehicle.reverse_allowed);
  $('working-speed').value = p.vehicle && p.vehicle.cruise_speed_mps && groundVehicle() ? Math.round(p.vehicle.cruise_speed_mps * 36) / 10 : '';
  $('tank-litres').value = p.vehicle && p.vehicle.battery_wh && groundVehicle() ? Math.round(p.vehicle.battery_wh / WH_PER_LITRE) : '';
  set('headland-passes', p.headland_passes);
  set('headland-order', p.headland_order);
  if (groundVehicle()) set('swath-ends', p.swath_ends);
  else $('line-ends').value = p.swath_ends || 'full_width';
  restoreGuidance(p.guidance);
  $('tramline-every').value = p.tramline_every ?? '';
  $('camera').value = (p.camera && p.camera.preset) || '';
  set('spacing', p.line_spacing_m);
  $('altitude').value = p.altitude_m ?? '';
  $('altitude-reference').value = p.altitude_reference === 'terrain' && state.terrain ? 'terrain' : 'home';
  set('terrain-tolerance', p.terrain_tolerance_m);
  $('altitude-reference').dispatchEvent(new Event('change'));
  $('gsd').value = p.gsd_cm ?? '';
  const percent = (f) => (f === undefined ? undefined : Math.round(f * 1000) / 10);
  set('side-overlap', percent(p.side_overlap));
  set('front-overlap', percent(p.front_overlap));
  $('direction').value = p.heading_deg !== undefined ? 'fixed' : p.sweep_direction === 'optimal' ? 'optimal' : 'planner';
  set('fixed-heading', p.heading_deg);
  set('objective', p.objective);
  $('drones').value = p.vehicles || 1;
  $('landing').value = p.landing || 'return';
  $('pattern').value = p.pattern || 'grid';
  set('oblique-pitch', p.oblique_pitch_deg);
  $('landing-heading').value = p.landing_heading_deg ?? '';
  $('lead-in').value = p.lead_in_m ?? '';
  $('wind-speed').value = p.wind ? p.wind.speed_mps : '';
  $('wind-from').value = p.wind ? p.wind.from_deg : 270;
  $('altitude-separation').value = p.altitude_separation_m ?? '';
  if (p.budget) {
    const [kind, value] = Object.entries(p.budget)[0];
    set('budget-kind', kind);
    set('budget', value);
  }
  if (p.targets) {
    const faces = p.targets.flatMap((t) => (typeof t === 'string' ? (['walls', 'roof'].includes(t) ? [t] : ['walls', 'roof']) : t.faces || ['walls', 'roof']));
    $('target-walls').checked = !p.targets.length || faces.includes('walls');
    $('target-roof').checked = !p.targets.length || faces.includes('roof');
    $('target-names').value = p.targets.map((t) => (typeof t === 'string' ? t : t.name)).filter((n) => !['walls', 'roof'].includes(n)).join(', ');
  }
  if (p.inspection) {
    set('range-min', p.inspection.range_m && p.inspection.range_m[0]);
    set('range-max', p.inspection.range_m && p.inspection.range_m[1]);
    set('extension', p.inspection.extension);
    set('safety-margin', p.inspection.safety_margin_m);
  }
  set('inspection-seed', p.seed);
  for (const kind of ['start', 'end']) {
    const pose = p[kind];
    if (pose && pose.position) setPose(kind, L.latLng(pose.position[1], pose.position[0]), pose.heading_deg ?? null);
  }
  state.landingSites.clearLayers();
  for (const [lng, lat] of p.landing_sites || []) addLandingSite(L.latLng(lat, lng));
  syncForm();
}

// ---- errors beside the input at fault ----
// the request member a refusal points at, and the input that sets it (the longest match wins)
const inputOf = [
  ['/line_spacing_m', 'spacing'], ['/altitude_m', 'altitude'], ['/gsd_cm', 'gsd'], ['/side_overlap', 'side-overlap'],
  ['/front_overlap', 'front-overlap'], ['/heading_deg', 'fixed-heading'], ['/vehicle/working_width_m', 'working-width'],
  ['/vehicle/turn_radius_m', 'turn-radius'], ['/vehicle', 'vehicle'], ['/headland_passes', 'headland-passes'], ['/vehicles', 'drones'],
  ['/altitude_separation_m', 'altitude-separation'], ['/budget', 'budget'], ['/inspection/range_m', 'range-min'], ['/inspection/safety_margin_m', 'safety-margin'], ['/seed', 'inspection-seed'],
  ['/targets', 'target-names'], ['/terrain_tolerance_m', 'terrain-tolerance'], ['/camera', 'camera'], ['/planner', 'planner'], ['/swath_ends', 'line-ends'],
  ['/guidance/bearing_deg', 'guidance-bearing'], ['/guidance/a', 'guidance-a'], ['/guidance', 'guidance'], ['/tramline_every', 'tramline-every'],
  ['/landing', 'landing'], ['/landing_heading_deg', 'landing-heading'], ['/lead_in_m', 'lead-in'], ['/pattern', 'pattern'], ['/oblique_pitch_deg', 'oblique-pitch'],
  ['/wind/speed_mps', 'wind-speed'], ['/wind/from_deg', 'wind-from'], ['/wind', 'wind-speed'], ['/landing_sites', 'draw-kind'],
];

export function clearFieldErrors() {
  for (const el of document.querySelectorAll('.field-error')) el.remove();
  for (const el of document.querySelectorAll('[aria-invalid=true]')) el.removeAttribute('aria-invalid');
}

/** Shows `text` under the input `id`, marks it and moves the focus to it. */
function fieldError(id, text) {
  const input = $(id);
  const note = document.createElement('span');
  note.className = 'field-error';
  note.id = `${id}-error`;
  note.textContent = text;
  (input.closest('label') || input).after(note);
  input.setAttribute('aria-invalid', 'true');
  input.setAttribute('aria-describedby', note.id);
  input.focus();
}

/** The first visible input the browser finds out of its bounds, said beside it. */
function checkBounds() {
  const bad = [...$('params').querySelectorAll('input')].find((i) => i.offsetParent !== null && !i.checkValidity());
  if (!bad) return true;
  const name = (bad.closest('label')?.firstChild?.textContent || 'this value').trim();
  const range = bad.min !== '' && bad.max !== '' ? `between ${bad.min} and ${bad.max}` : bad.min !== '' ? `at least ${bad.min}` : `at most ${bad.max}`;
  fieldError(bad.id, bad.validity.rangeUnderflow || bad.validity.rangeOverflow ? `${name} must be ${range}.` : bad.validationMessage);
  return false;
}

/** A refusal of the request: beside its input when it has one, else in the status line. */
function showRefusal(e) {
  const match = e.pointer && inputOf.filter(([p]) => e.pointer === p || e.pointer.startsWith(`${p}/`)).sort((a, b) => b[0].length - a[0].length)[0];
  const visible = match && $(match[1]).offsetParent !== null;
  if (/^\/(area|no_fly_zones|obstacles|structures|home)(\/|$)/.test(e.pointer || '')) {
    // the mission's shapes are at fault: said beside the drawing tools
    $('draw-error').textContent = e.message;
    $('draw-error').hidden = false;
    status('The mission was refused: see the drawing tools.', true);
  } else if (visible) {
    fieldError(match[1], e.message);
    status('The plan was refused: see the marked field.', true);
  } else {
    status(e.message, true);
  }
}
$('params').addEventListener('input', (e) => {
  if (e.target.getAttribute('aria-invalid') === 'true') clearFieldErrors();
});

// ---- planning ----
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

$('plan').onclick = async () => {
  clearFieldErrors();
  if (!checkBounds()) return status('A value is out of bounds: see the marked field.', true);
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
      // what the planner warns about (no viewpoint within the budget, batteries without a home)
      // is said with the result, not hidden in it
      const warnings = plan.stats.warnings || [];
      status(`planned in ${Math.round(plan.stats.planning_time_ms)} ms` + (warnings.length ? `. Note: ${warnings.join('; ')}` : ''), false, warnings.length > 0);
      // the result is what the user looks at next: the keyboard goes there too
      $('result-heading').focus();
    } else {
      status(plan.status === 'failed' ? `failed: ${plan.error}` : plan.status, plan.status === 'failed');
    }
  } catch (e) {
    showRefusal(e);
  } finally {
    $('plan').disabled = false;
    $('cancel').disabled = true;
    $('progress').hidden = true;
    state.planId = null;
  }
};

$('cancel').onclick = () => state.planId && api('DELETE', `/api/v1/plans/${state.planId}`).catch((e) => status(e.message, true));
