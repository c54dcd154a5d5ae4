// coverplan's map page: draw a mission, plan it, look at the result. ES modules, no build step:
// api.js (the server), map.js (the map and its state), mission.js, terrain.js, plan.js, result.js,
// resume.js, patrol.js, farm.js.

import { $, api, status } from './js/api.js';
import { map } from './js/map.js';
import { clearMission, drawMission, listMissions } from './js/mission.js';
import { fillForm, restoreParams } from './js/plan.js';
import { clearResult, showPlan } from './js/result.js';
import './js/resume.js';
import { clearPatrol } from './js/patrol.js';
import { clearFarm } from './js/farm.js';

// map tiles: only when the server is configured with a tile URL (works offline without)
api('GET', '/api/v1/ui-config').then((c) => {
  if (c && c.tile_url) L.tileLayer(c.tile_url, { maxZoom: 20, attribution: c.tile_attribution || '' }).addTo(map);
}).catch(() => {});

$('clear').onclick = () => { clearMission(); history.replaceState(null, '', '/'); };

// one mission at a time: a result belongs to the mission as it was planned, so any change to the
// mission (an edit, an undo, Clear, an import, opening another) takes its result, comparison and
// download away
document.addEventListener('mission-changed', () => { clearResult(); clearPatrol(); clearFarm(); });

/** Opens a saved mission with its latest plan and that plan's parameters (a shared link). */
async function openMission(id) {
  const m = await api('GET', `/api/v1/missions/${id}`);
  drawMission(m);
  history.replaceState(null, '', `/?mission=${id}`);
  const plans = await api('GET', `/api/v1/missions/${id}/plans`);
  const latest = plans.find((p) => p.status === 'succeeded');
  if (latest) {
    restoreParams(latest.params);
    await showPlan(latest);
  }
  $('missions').value = id;
}
$('missions').onchange = (e) => e.target.value && openMission(e.target.value).catch((err) => status(err.message, true));

// start
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
