// The parameters form (from the API's lists), the request it makes, and the planning loop.

import { $, api, escapeHtml, status } from './api.js';
import { state } from './map.js';
import { saveMission, setPose } from './mission.js';
import { fillFormats, keepForComparison, showPlan } from './result.js';

// ---- the parameter form, from the API's lists ----
export async function fillForm() {
  const [planners, vehicles, cameras] = await Promise.all([api('GET', '/api/v1/planners'), api('GET', '/api/v1/vehicles'), api('GET', '/api/v1/cameras'), fillFormats()]);
  catalogue = new Map(planners.map((p) => [p.id, p]));
  $('planner').innerHTML = planners.map((p) => `<option value="${p.id}" title="${escapeHtml(p.description)}">${p.id}</option>`).join('');
  $('vehicle').innerHTML = vehicles.map((v) => `<option value="${v.profile}" data-kind="${v.kind}" title="${escapeHtml(v.description)}">${v.profile} (${v.kind.replace('_', ' ')})</option>`).join('');
  $('vehicle').value = 'generic_multirotor';
  $('camera').innerHTML += cameras.map((c) => `<option value="${c.id}">${escapeHtml(c.name || c.id)}</option>`).join('');
  syncForm();
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
  const ground = groundVehicle();
  const inspection = !ground && inspecting();
  $('ground-box').hidden = !ground;
  $('inspection-box').hidden = !inspection;
  for (const id of ['camera-box', 'layers-box']) $(id).hidden = ground;
  // an inspection always has a camera: leaving it unset means the planner's default preset
  $('camera').options[0].textContent = inspection ? 'default: DJI Mavic 3 Enterprise (wide)' : 'none: give the line spacing';
  $('drones').closest('.row').hidden = ground || inspection;
  for (const id of ['altitude-box', 'direction-box', 'overlap-box']) $(id).hidden = inspection;
  const camera = !ground && $('camera').value !== '';
  $('spacing-box').hidden = camera || ground || inspection;
  $('line-ends-box').hidden = !aircraftLineEnds();
  $('fixed-heading-box').hidden = inspection || $('direction').value !== 'fixed';
  $('objective-box').hidden = !reads('objective');
  $('layers-box').hidden = ground || inspection || !(num('drones') > 1);
  $('reference-box').hidden = ground || inspection;
  $('tolerance-box').hidden = $('altitude-reference').value !== 'terrain';
}
['camera', 'direction', 'planner', 'drones', 'vehicle', 'altitude-reference'].forEach((id) => $(id).addEventListener('change', syncForm));

/** An aircraft's plan by a planner that lays parallel lines: the line-end rule applies. */
const aircraftLineEnds = () => !groundVehicle() && !inspecting() && reads('swath_ends');

const num = (id) => ($(id).value === '' ? undefined : Number($(id).value));

/** An inspection's request: the budget, the faces, the camera's reach and the search. */
function inspectionParams(p) {
  p.budget = { [$('budget-kind').value]: num('budget') };
  const faces = [['walls', 'target-walls'], ['roof', 'target-roof']].filter(([, id]) => $(id).checked).map(([face]) => face);
  const names = $('target-names').value.split(',').map((n) => n.trim()).filter(Boolean);
  const both = faces.length === 2;
  p.targets = names.length ? names.map((name) => (both ? name : { name, faces })) : both ? [] : faces;
  p.inspection = { range_m: [num('range-min'), num('range-max')], extension: $('extension').value, show_unseen: true };
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
    p.headland_passes = num('headland-passes');
    p.headland_order = $('headland-order').value;
    p.swath_ends = $('swath-ends').value;
  } else if ($('camera').value) {
    p.camera = { preset: $('camera').value };
    p.side_overlap = num('side-overlap');
    p.front_overlap = num('front-overlap');
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
  if ($('direction').value === 'fixed') p.heading_deg = num('fixed-heading');
  if ($('direction').value === 'optimal') p.sweep_direction = 'optimal';
  if (reads('objective')) p.objective = $('objective').value;
  if (num('drones') > 1 && !groundVehicle()) {
    p.vehicles = num('drones');
    if (num('altitude-separation') !== undefined) p.altitude_separation_m = num('altitude-separation');
  }
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
  set('headland-passes', p.headland_passes);
  set('headland-order', p.headland_order);
  if (groundVehicle()) set('swath-ends', p.swath_ends);
  else $('line-ends').value = p.swath_ends || 'full_width';
  $('camera').value = (p.camera && p.camera.preset) || '';
  set('spacing', p.line_spacing_m);
  set('altitude', p.altitude_m);
  $('altitude-reference').value = p.altitude_reference === 'terrain' && state.terrain ? 'terrain' : 'home';
  set('terrain-tolerance', p.terrain_tolerance_m);
  $('altitude-reference').dispatchEvent(new Event('change'));
  set('gsd', p.gsd_cm);
  set('side-overlap', p.side_overlap);
  set('front-overlap', p.front_overlap);
  $('direction').value = p.heading_deg !== undefined ? 'fixed' : p.sweep_direction === 'optimal' ? 'optimal' : 'planner';
  set('fixed-heading', p.heading_deg);
  set('objective', p.objective);
  $('drones').value = p.vehicles || 1;
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
  }
  set('inspection-seed', p.seed);
  for (const kind of ['start', 'end']) {
    const pose = p[kind];
    if (pose && pose.position) setPose(kind, L.latLng(pose.position[1], pose.position[0]), pose.heading_deg ?? null);
  }
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
