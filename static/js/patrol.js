// Patrols: several UAVs revisiting the cells of a grid over the field (NC-Drone and the methods
// it was compared with). The form, the run, and the result: each UAV's path in its colour and
// the visits per cell as a heat map.

import { $, api, status } from './api.js';
import { map, notForDrawing, state } from './map.js';
import { saveMission } from './mission.js';
import { droneColour } from './result.js';

const num = (id) => ($(id).value === '' ? undefined : Number($(id).value));
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

export function patrolParams() {
  const p = { uavs: num('patrol-uavs'), strategy: $('patrol-strategy').value, cycles: num('patrol-cycles'), seed: num('patrol-seed') };
  if ($('camera').value && num('altitude') !== undefined) {
    // the plan form's camera and altitude set the cells: the square the footprint covers
    p.camera = { preset: $('camera').value };
    p.altitude_m = num('altitude');
  } else {
    p.cell_size_m = num('patrol-cell');
  }
  return p;
}

/** Cells from white (fewest visits) to deep red (most): evenness shows as one flat colour. */
function heat(share) {
  const g = Math.round(235 - 200 * share);
  return `rgb(230, ${g}, ${Math.round(g * 0.6)})`;
}

export function clearPatrol() {
  if (state.patrol) map.removeLayer(state.patrol.layer);
  state.patrol = null;
  $('patrol-figures').hidden = true;
}

function showPatrol(patrol, fc) {
  clearPatrol();
  const layer = L.featureGroup();
  const cells = fc.features.filter((f) => f.properties.kind === 'visits');
  const visits = cells.map((f) => f.properties.visits);
  const [least, most] = [Math.min(...visits), Math.max(...visits)];
  L.geoJSON({ type: 'FeatureCollection', features: cells }, {
    style: (f) => ({ weight: 0, fillColor: heat(most > least ? (f.properties.visits - least) / (most - least) : 0), fillOpacity: 0.55, className: 'visits-cell' }),
    onEachFeature: (f, l) => l.bindTooltip(`${f.properties.visits} visits`),
  }).addTo(layer);
  for (const f of fc.features.filter((f) => f.properties.kind === 'patrol')) {
    L.geoJSON(f, { style: { color: droneColour(f.properties.uav), weight: 1.5, opacity: 0.8 } })
      .bindTooltip(`UAV ${f.properties.uav + 1}: ${f.properties.turns} turns, ${(f.properties.length_m / 1000).toFixed(1)} km`).addTo(layer);
  }
  state.patrol = { layer: notForDrawing(layer).addTo(map), stats: patrol.stats };
  const s = patrol.stats;
  // a cycle is one move of every UAV to a neighbouring cell: its time turns cycles into minutes
  const cycleS = s.uavs.length ? Math.max(...s.uavs.map((u) => u.duration_s)) / s.cycles : 0;
  const minutes = (cycles) => `${((cycles * cycleS) / 60).toFixed(1)} min`;
  const meanGap = visits.length ? (s.cycles * visits.length) / Math.max(1, visits.reduce((a, b) => a + b, 0)) : 0;
  const rows = [
    ['cells', `${s.free_cells} of ${s.cell_size_m.toFixed(1)} m`],
    ['each spot is seen every', `${minutes(meanGap)} on average`],
    ['typical wait, long waits weighted', `${minutes(s.qmi)} (quadratic mean of the gaps, QMI)`],
    ['visits per cell', `${least} to ${most} (spread ${s.sdf.toFixed(2)}, SDF)`],
    ['turns', `${s.ntm} (a U-turn counts 2)`],
    ['patrol time', minutes(s.cycles)],
    ['energy', `${(s.energy_j / 3600).toFixed(0)} Wh`],
  ];
  $('patrol-figures').tBodies[0].innerHTML = rows.map(([k, v]) => `<tr><td>${k}</td><td data-patrol="${k}">${v}</td></tr>`).join('');
  $('patrol-figures').hidden = false;
}

$('patrol').onclick = async () => {
  try {
    $('patrol').disabled = true;
    await saveMission();
    const queued = await api('POST', `/api/v1/missions/${state.missionId}/patrols`, patrolParams());
    let patrol = queued;
    while (['queued', 'running'].includes(patrol.status)) {
      status(`patrol ${patrol.status}…`);
      await sleep(300);
      patrol = await api('GET', `/api/v1/patrols/${queued.id}`);
    }
    if (patrol.status !== 'succeeded') {
      status(patrol.status === 'failed' ? `patrol failed: ${patrol.error}` : patrol.status, patrol.status === 'failed');
      return;
    }
    showPatrol(patrol, await api('GET', `/api/v1/patrols/${queued.id}/trajectory`));
    status(`patrolled ${patrol.stats.cycles} cycles in ${Math.round(patrol.stats.planning_time_ms)} ms`);
  } catch (e) {
    status(e.message, true);
  } finally {
    $('patrol').disabled = false;
  }
};
