// Whole farm: every field of the mission planned as a job of its own and shared among machines
// over working days (POST /api/v1/farm-plans). The fields are coloured by their plan's status as
// they go, the schedule is a chart of machines by days, and a click on a field or on its stretch
// of a day opens that field's plan.

import { $, api, escapeHtml, status } from './api.js';
import { map, notForDrawing, state } from './map.js';
import { polygonsOf, saveMission } from './mission.js';
import { planParams } from './plan.js';
import { showPlan } from './result.js';

const num = (id) => ($(id).value === '' ? undefined : Number($(id).value));
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
export const FIELD_COLOURS = { queued: '#9e9e9e', running: '#1e88e5', succeeded: '#2e7d32', failed: '#c62828', cancelled: '#6d4c41', refused: '#c62828' };

$('farm-start').value = new Date().toISOString().slice(0, 10);

export function clearFarm() {
  if (state.farm) map.removeLayer(state.farm.layer);
  state.farm = null;
  $('farm-gantt').hidden = true;
  $('farm-gantt').innerHTML = '';
}

/** The request: the saved mission's polygons as the fields, machines at home (else the first field). */
function farmRequest(missionId) {
  const params = planParams();
  // one vehicle a field: the machines are the farm's
  delete params.vehicles;
  delete params.altitude_separation_m;
  const home = state.poses.home && state.poses.home.getLatLng();
  const depot = home || state.fields.getLayers()[0].getBounds().getCenter();
  const machines = Array.from({ length: num('farm-machines') || 1 }, (_, k) => ({ name: `machine ${k + 1}`, depot: [depot.lng, depot.lat] }));
  const window = { start_date: $('farm-start').value, days: num('farm-days'), hours_per_day: num('farm-hours') };
  return { name: $('mission-name').value, mission_id: missionId, machines, window, params };
}

const fieldStatus = (f) => (f.status || (f.error_code ? 'refused' : 'queued'));

async function openField(farm, index) {
  const field = farm.fields[index];
  if (!field || field.status !== 'succeeded') {
    status(`${field ? field.name : 'this field'}: ${field && field.error ? field.error : 'no plan yet'}`, !!(field && field.error));
    return;
  }
  await showPlan(await api('GET', `/api/v1/plans/${field.plan_id}`));
  status(`${field.name}: its plan`);
}

/** The fields over the mission's, coloured by status; drawn once, restyled as the farm goes. */
function drawFields(farm, area) {
  if (!state.farm.polygons) {
    const layer = L.featureGroup();
    state.farm.polygons = polygonsOf(area).map((rings, i) => {
      const polygon = L.polygon(rings, { weight: 2, fillOpacity: 0.35, className: 'farm-field' }).bindTooltip('');
      polygon.on('click', () => openField(state.farm.plan, i).catch((e) => status(e.message, true)));
      return polygon.addTo(layer);
    });
    state.farm.layer = notForDrawing(layer).addTo(map);
  }
  farm.fields.forEach((f, i) => {
    const polygon = state.farm.polygons[i];
    if (!polygon) return;
    const s = fieldStatus(f);
    polygon.setStyle({ color: FIELD_COLOURS[s], fillColor: FIELD_COLOURS[s] });
    polygon.cpStatus = s;
    polygon.setTooltipContent(`${escapeHtml(f.name)}: ${s}${f.work_s ? `, ${(f.work_s / 3600).toFixed(1)} h` : ''}`);
  });
}

const clock = (s) => s.slice(0, 5);

/** Machines by days: each day a strip of its hours, each leg a bar; work bars open their field. */
function drawGantt(farm) {
  const s = farm.schedule;
  const dayHours = (farm.window.hours_per_day || 10);
  const dates = [...new Set(s.machines.flatMap((m) => m.days.map((d) => `${d.day}|${d.date}`)))].sort((a, b) => Number(a.split('|')[0]) - Number(b.split('|')[0]));
  const head = dates.map((d) => `<th scope="col">day ${d.split('|')[0]}<br><small>${d.split('|')[1]}</small></th>`).join('');
  const rows = s.machines.map((m, k) => {
    const hours = (farm.machines[k].hours_per_day || dayHours) * 3600;
    const cells = dates.map((d) => {
      const day = m.days.find((x) => x.day === Number(d.split('|')[0]));
      if (!day) return '<td></td>';
      const bars = day.legs.map((l) => {
        const style = `left:${((100 * l.start_s) / hours).toFixed(2)}%;width:${((100 * (l.end_s - l.start_s)) / hours).toFixed(2)}%`;
        const name = l.field !== undefined ? farm.fields[l.field].name : 'home';
        const what = l.kind === 'work' ? `${name}${l.finishes_field ? '' : ' (continued later)'}` : l.kind === 'transit' ? `to ${name}` : 'refill';
        const field = l.kind === 'work' ? ` data-field="${l.field}" tabindex="0" role="button"` : '';
        return `<span class="gantt-leg gantt-${l.kind}" style="${style}"${field} title="${escapeHtml(`${clock(l.start)}–${clock(l.end)} ${what}`)}"></span>`;
      }).join('');
      return `<td><div class="gantt-day">${bars}</div></td>`;
    }).join('');
    return `<tr><th scope="row">${escapeHtml(m.machine)}<br><small>${m.fields} ${m.fields === 1 ? 'field' : 'fields'}</small></th>${cells}</tr>`;
  }).join('');
  const h = (x) => `${(x / 3600).toFixed(1)} h`;
  const figures = `<p class="figure">last machine home ${s.ends_at.replace('T', ' ')}; working time ${h(s.makespan_s)}, no schedule under ${h(s.lower_bound_s)}; `
    + `${Math.round(100 * s.transit_share)} % driving between fields; ${s.days_used} ${s.days_used === 1 ? 'day' : 'days'}${s.fits_window ? '' : ` (more than the ${farm.window.days} asked)`}`
    + `${s.unscheduled.length ? `; ${s.unscheduled.length} fields not scheduled` : ''}. <a href="${farm.schedule_csv_url}" download>Schedule as CSV</a> · `
    + `<a href="/api/v1/farm-plans/${farm.id}/taskdata" download>ISOXML</a> · `
    + `<a id="farm-flights" href="/api/v1/farm-plans/${farm.id}/flights?format=plan" download>Flight plans by day</a></p>`;
  const box = $('farm-gantt');
  box.innerHTML = `${figures}<div class="gantt-scroll"><table class="gantt"><thead><tr><th></th>${head}</tr></thead><tbody>${rows}</tbody></table></div>`;
  box.hidden = false;
  for (const bar of box.querySelectorAll('[data-field]')) {
    const open = () => openField(farm, Number(bar.dataset.field)).catch((e) => status(e.message, true));
    bar.onclick = open;
    bar.onkeydown = (e) => { if (e.key === 'Enter' || e.key === ' ') { e.preventDefault(); open(); } };
  }
}

$('farm-plan').onclick = async () => {
  try {
    $('farm-plan').disabled = true;
    const mission = await saveMission();
    clearFarm();
    state.farm = { plan: null, layer: null, polygons: null };
    let farm = await api('POST', '/api/v1/farm-plans', farmRequest(mission.id));
    while (farm.status === 'planning') {
      state.farm.plan = farm;
      drawFields(farm, mission.area);
      status(`farm: ${farm.fields_done} of ${farm.fields_total} fields planned…`);
      await sleep(500);
      farm = await api('GET', `/api/v1/farm-plans/${farm.id}`);
    }
    state.farm.plan = farm;
    drawFields(farm, mission.area);
    if (farm.schedule) {
      drawGantt(farm);
      status(`farm: ${farm.fields_total} fields scheduled over ${farm.schedule.days_used} days`);
    } else {
      status(`farm: ${farm.status}`, farm.status === 'failed');
    }
  } catch (e) {
    status(e.message, true);
  } finally {
    $('farm-plan').disabled = false;
  }
};
