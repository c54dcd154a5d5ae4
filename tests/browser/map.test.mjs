// The map page end to end: the real server (a fresh database, no map tiles) and Debian's
// Chromium driven by playwright-core. Draws a field and a home point, edits a corner, undoes
// and redoes, refuses a hole outside the field, deletes a shape, plans it, compares two
// planners and stops comparing, imports a file by the picker (no stale result stays), reopens
// the mission from its link with every parameter, plans a tractor, shows an error beside its
// input, plans by keyboard alone, and fits 1366×768 and a 390×844 phone. The server runs from
// a folder of its own, serving the page built into the binary. Run by tests/run_all.sh after
// the build. Draws a barn and inspects it, with its 3D view. Resumes a plan from a click on its
// path. Plans it again as an oblique plan, with the DJI download's waypoint limit; draws a road
// as a corridor and plans it, and a longer one flown in hops between landing sites. Screenshots
// of each step are left
// in the temporary folder (coverplan-*.png).
import { execFileSync, spawn } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import net from 'node:net';
import os from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import assert from 'node:assert/strict';
import { chromium } from 'playwright-core';

const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
const binary = path.join(process.env.CARGO_TARGET_DIR || path.join(root, 'target'), 'debug', 'coverplan');

const freePort = () => new Promise((resolve) => {
  const s = net.createServer().listen(0, '127.0.0.1', () => { const { port } = s.address(); s.close(() => resolve(port)); });
});

async function waitFor(check, what, ms = 30000) {
  const until = Date.now() + ms;
  for (;;) {
    try { if (await check()) return; } catch { /* not yet */ }
    if (Date.now() > until) throw new Error(`timed out waiting for ${what}`);
    await new Promise((r) => setTimeout(r, 100));
  }
}

const dir = mkdtempSync(path.join(os.tmpdir(), 'coverplan-browser-'));
const port = await freePort();
const base = `http://127.0.0.1:${port}`;
const server = spawn(binary, ['serve', '--addr', `127.0.0.1:${port}`, '--database-url', path.join(dir, 'page.db'), '--workers', '2', '--tile-url', ''], { cwd: dir, stdio: ['ignore', 'inherit', 'inherit'] });
let browser;
try {
  await waitFor(async () => (await fetch(`${base}/healthz`)).ok, 'the server');
  browser = await chromium.launch({
    executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  const foreign = [];
  page.on('request', (r) => { if (!r.url().startsWith(base) && !r.url().startsWith('data:')) foreign.push(r.url()); });
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  // a mission without an elevation model answers 404 to the page's look for one
  const noModel = (m) => /status of 404/.test(m.text()) && /\/terrain$/.test(m.location().url || '');
  // a refusal the test asks for is logged by the browser too
  let refusalsAsked = 0;
  const asked422 = (m) => /status of 422/.test(m.text()) && refusalsAsked > 0 && refusalsAsked--;
  page.on('console', (m) => { if (m.type() === 'error' && !noModel(m) && !asked422(m)) errors.push(m.text()); });

  const shot = (name) => page.screenshot({ path: path.join(os.tmpdir(), `coverplan-${name}.png`) });
  const state = (f) => page.evaluate(f);
  const fieldCount = () => state(() => window.coverplan.state.fields.getLayers().length);
  const hectares = async () => Number((await page.textContent('#mission-area')).match(/([\d.]+) ha/)[1]);
  await page.setViewportSize({ width: 1366, height: 768 });
  await page.goto(base);
  await page.waitForSelector('body[data-ready=true]');
  // first visit: a prompt on the empty map, the tool's own words, Plan in sight at 1366×768
  assert.ok(await page.isVisible('#first-step'), 'a first step is shown on the empty map');
  assert.match(await page.textContent('#first-step'), /Draw/);
  assert.equal(await page.textContent('#mission-area'), 'no field yet');
  assert.notEqual(await page.textContent('label:has(#draw-kind)'), await page.textContent('#draw'), 'the select and the button say different things');
  const planBox = await page.locator('#plan').boundingBox();
  assert.ok(planBox.y + planBox.height <= 768, `Plan in sight at 1366×768 (${planBox.y})`);
  await shot('first-visit');
  // the form comes from the API: planners by readable names, the recommended one marked
  const planners = await page.$$eval('#planner option', (o) => o.map((x) => x.value));
  assert.ok(!planners.includes('patrol'), 'a patrol has its own form');
  assert.match(await page.textContent('#planner option[value=boustrophedon]'), /Back and forth.*\(recommended\)/);
  assert.equal(await page.locator('#vehicle optgroup[label="Fixed-wing aircraft"] option[value=generic_fixed_wing]').count(), 1, 'vehicles grouped by kind');
  for (const id of ['boustrophedon', 'e_spiral', 'eg_cpp', 'auto', 'line_gtsp']) assert.ok(planners.includes(id), `${id} in ${planners}`);
  const vehicles = await page.$$eval('#vehicle option', (o) => o.map((x) => x.value));
  assert.ok(vehicles.includes('iris') && vehicles.includes('maja'), `${vehicles}`);
  assert.ok(await page.$$eval('#camera option', (o) => o.length) > 1);

  // draw a field: four clicks, then the first vertex again
  const box = await page.locator('#map').boundingBox();
  const at = (dx, dy) => [box.x + box.width / 2 + dx, box.y + box.height / 2 + dy];
  await page.selectOption('#draw-kind', 'field');
  await page.click('#draw');
  for (const [dx, dy] of [[-120, -90], [120, -90], [140, 90], [-120, 90], [-120, -90]]) {
    await page.mouse.click(...at(dx, dy));
    await page.waitForTimeout(150);
  }
  assert.equal(await fieldCount(), 1, 'one field drawn');
  assert.ok(!(await page.isVisible('#first-step')), 'the prompt goes once a field is drawn');
  const drawn = await hectares();
  assert.ok(drawn > 0, `the field's area is shown: ${await page.textContent('#mission-area')}`);

  // edit a corner: drag the first vertex outwards, the area grows; Escape ends editing
  await page.click('#edit');
  assert.equal(await page.getAttribute('#edit', 'aria-pressed'), 'true');
  await page.mouse.move(...at(-120, -90));
  await page.mouse.down();
  await page.mouse.move(...at(-160, -130), { steps: 8 });
  await page.mouse.up();
  await page.keyboard.press('Escape');
  assert.equal(await state(() => window.coverplan.map.pm.globalEditModeEnabled()), false, 'Escape ends editing');
  const edited = await hectares();
  assert.ok(edited > drawn * 1.05, `a corner moved out: ${drawn} ha → ${edited} ha`);
  await shot('edited');
  // undo puts the corner back, redo moves it again
  await page.click('#undo');
  assert.equal(await hectares(), drawn, 'undo restores the field');
  await page.click('#redo');
  assert.equal(await hectares(), edited, 'redo moves the corner again');
  await page.keyboard.press('Control+z');
  assert.equal(await hectares(), drawn, 'Ctrl+Z undoes');

  // a hole outside the field is refused beside the drawing tools; the field keeps no hole
  await page.selectOption('#draw-kind', 'hole');
  await page.click('#draw');
  for (const [dx, dy] of [[160, -40], [220, -40], [220, 40], [160, 40], [160, -40]]) {
    await page.mouse.click(...at(dx, dy));
    await page.waitForTimeout(150);
  }
  assert.ok(await page.isVisible('#draw-error'), 'the refusal is shown');
  assert.match(await page.textContent('#draw-error'), /inside a field/);
  assert.equal(await state(() => window.coverplan.state.fields.getLayers()[0].getLatLngs().length), 1, 'no hole was added');
  // one inside is cut into it, and its area leaves the field's
  await page.click('#draw');
  for (const [dx, dy] of [[-20, -20], [30, -20], [30, 20], [-20, 20], [-20, -20]]) {
    await page.mouse.click(...at(dx, dy));
    await page.waitForTimeout(150);
  }
  assert.equal(await state(() => window.coverplan.state.fields.getLayers()[0].getLatLngs().length), 2, 'the hole is cut');
  assert.ok(await hectares() < drawn, 'the hole is left out of the area');
  await page.click('#undo');
  // a zone drawn, then deleted by itself
  await page.selectOption('#draw-kind', 'nfz');
  await page.click('#draw');
  for (const [dx, dy] of [[40, 30], [90, 30], [90, 70], [40, 70], [40, 30]]) {
    await page.mouse.click(...at(dx, dy));
    await page.waitForTimeout(150);
  }
  assert.equal(await state(() => window.coverplan.state.zones.getLayers().length), 1, 'a zone drawn');
  await page.click('#remove');
  await page.mouse.click(...at(65, 50));
  assert.equal(await state(() => window.coverplan.state.zones.getLayers().length), 0, 'the zone deleted');
  assert.equal(await fieldCount(), 1, 'the field stays');
  await page.keyboard.press('Escape');
  // a zone typed as corners, without the mouse: drawn, then undone
  const corner = (dx, dy) => page.evaluate(([x, y]) => { const p = window.coverplan.map.containerPointToLatLng([x, y]); return `${p.lat.toFixed(6)}, ${p.lng.toFixed(6)}`; }, [box.width / 2 + dx, box.height / 2 + dy]);
  await page.selectOption('#draw-kind', 'nfz');
  await page.fill('#point-at', [await corner(40, 30), await corner(90, 30), await corner(90, 70)].join('; '));
  await page.click('#draw');
  assert.equal(await state(() => window.coverplan.state.zones.getLayers().length), 1, 'a zone from typed corners');
  await page.click('#undo');
  assert.equal(await state(() => window.coverplan.state.zones.getLayers().length), 0);
  // an outline that would cross itself: the corner is refused, and the page says so
  await page.selectOption('#draw-kind', 'field');
  await page.click('#draw');
  for (const [dx, dy] of [[200, -100], [300, 0], [300, -100], [200, 0]]) {
    await page.mouse.click(...at(dx, dy));
    await page.waitForTimeout(150);
  }
  assert.match(await page.textContent('#draw-error'), /cross itself/);
  await page.keyboard.press('Escape');
  assert.equal(await fieldCount(), 1, 'no crossed field');

  await page.selectOption('#draw-kind', 'home');
  await page.click('#draw');
  await page.mouse.click(...at(-160, 120));
  await waitFor(() => page.evaluate(() => !!window.coverplan.state.poses.home), 'the home marker');
  assert.equal(await page.evaluate(() => window.coverplan.map.pm.globalDrawModeEnabled()), false, 'placing home ends the mode');
  // Escape ends a drawing left half done, and nothing is added
  await page.selectOption('#draw-kind', 'nfz');
  await page.click('#draw');
  await page.mouse.click(...at(-60, -40));
  await page.keyboard.press('Escape');
  assert.equal(await page.evaluate(() => window.coverplan.map.pm.globalDrawModeEnabled()), false, 'Escape ends the mode');
  assert.equal(await page.evaluate(() => window.coverplan.state.zones.getLayers().length), 0, 'no zone from a drawing left half done');

  // plan it
  await page.selectOption('#planner', 'boustrophedon');
  await page.selectOption('#vehicle', 'iris'); // a small battery: the plan needs several sorties
  await page.fill('#spacing', '20');
  assert.ok(await page.isVisible('#line-ends-box'), 'line ends for a planner that lays lines');
  await page.selectOption('#line-ends', 'balanced');
  await page.click('#plan');
  await page.waitForSelector('td[data-figure=length]', { timeout: 60000 });
  assert.match(await page.textContent('#status'), /planned/);
  const missionId = new URL(page.url()).searchParams.get('mission');
  assert.ok(missionId, 'the URL names the mission');
  const sweeps = await page.$$eval('path[stroke="#1565c0"]', (p) => p.length);
  assert.ok(sweeps >= 5, `${sweeps} sweep lines drawn`);
  assert.ok(await page.$$eval('.arrow', (a) => a.length) >= 5, 'direction arrows');
  assert.match(await page.textContent('td[data-figure=coverage]'), /%/);
  // the energy chart counts on across sorties instead of restarting at each
  const sorties = Number(await page.textContent('td[data-figure=sorties]'));
  assert.ok(sorties >= 2, `${sorties} sorties: the field should need several batteries`);
  const chart = await page.evaluate(() => window.coverplan.state.chart.map((p) => p.e));
  assert.ok(chart.every((e, i) => i === 0 || e >= chart[i - 1]), 'energy used never goes down along the path');
  const tableJ = await state(() => window.coverplan.state.result.stats.energy_j);
  assert.ok(Math.abs(chart[chart.length - 1] - tableJ) <= 0.001 * tableJ, `the chart ends at the table's energy: ${chart[chart.length - 1]} J, ${tableJ} J`);
  // rows only where they apply: a survey shows no inspection, fleet or ground rows
  const rows = await page.$$eval('#figures tbody td:first-child', (t) => t.map((x) => x.textContent));
  for (const absent of ['points seen', 'viewpoints', 'targets', 'last landing', 'conflicts', 'mainland worked', 'turn shapes']) assert.ok(!rows.includes(absent), `no ${absent} row for a survey: ${rows}`);
  for (const present of ['flight time', 'energy', 'line spacing', 'coverage']) assert.ok(rows.includes(present), `${present} shown: ${rows}`);
  await shot('planned');
  const download = await page.getAttribute('#download', 'href');
  assert.ok((await fetch(base + download)).ok, 'the download link serves the trajectory');
  // every format of the menu downloads; flight files of several sorties come as a zip
  // the menu is the server's list of formats, in its order, by their labels
  const formats = await page.$$eval('#download-format option', (o) => o.map((x) => x.value));
  const served = await (await fetch(`${base}/api/v1/formats`)).json();
  assert.deepEqual(formats, served.map((f) => f.id));
  assert.deepEqual(formats.slice().sort(), ['geojson', 'isoxml', 'kml', 'kmz', 'plan', 'waypoints', 'wpml']);
  for (const format of formats) {
    await page.selectOption('#download-format', format);
    const commands = served.find((f) => f.id === format).firmware_commands;
    assert.equal(await page.isVisible('#firmware-box'), commands, `autopilot choice for ${format}`);
    const href = await page.getAttribute('#download', 'href');
    assert.match(href, new RegExp(`format=${format}`));
    const r = await fetch(base + href);
    assert.ok(r.ok, `${format}: ${r.status}`);
    assert.match(r.headers.get('content-disposition'), /^attachment; filename="New_field/);
  }
  // a KML file dropped on the map becomes a new mission with the same field
  const kml = await (await fetch(`${base}/api/v1/plans/${download.split('/')[4]}/trajectory?format=kml`)).text();
  await page.evaluate((text) => {
    const transfer = new DataTransfer();
    transfer.items.add(new File([text], 'field.kml', { type: 'application/vnd.google-earth.kml+xml' }));
    document.getElementById('map').dispatchEvent(new DragEvent('drop', { dataTransfer: transfer, bubbles: true, cancelable: true }));
  }, kml);
  await waitFor(async () => /imported field\.kml/.test(await page.textContent('#status')), 'the dropped file');
  assert.match(await page.textContent('#status'), /line strings were dropped/, 'the page says what the import left out');
  const imported = new URL(page.url()).searchParams.get('mission');
  assert.ok(imported && imported !== missionId, 'the drop made a new mission');
  assert.equal(await fieldCount(), 1, 'its field is drawn');
  // one mission at a time: the last mission's figures and download are gone
  assert.equal(await page.$$eval('#figures tbody tr', (r) => r.length), 0, 'no stale figures');
  assert.ok(!(await page.isVisible('#download-box')), 'no stale download');
  assert.equal(await page.inputValue('#mission-name'), 'New field', 'named by the KML document');
  // the same by the file picker (phones and keyboards have no drag and drop)
  const kmlPath = path.join(dir, 'Home farm.kml');
  writeFileSync(kmlPath, kml.replace('<name>New field</name>', '<name>Home farm</name>'));
  await page.evaluate(() => { document.getElementById('status').textContent = ''; });
  await page.setInputFiles('#import-file', kmlPath);
  await waitFor(async () => /imported Home farm\.kml/.test(await page.textContent('#status')), 'the picked file');
  assert.doesNotMatch(await page.textContent('#status'), /\/doc\.kml|\/Home/, 'messages without pointers into the file');
  assert.equal(await page.inputValue('#mission-name'), 'Home farm');
  await page.goto(`${base}/?mission=${missionId}`);
  await page.waitForSelector('body[data-ready=true]');
  await page.waitForSelector('td[data-figure=length]');
  assert.equal(await page.inputValue('#line-ends'), 'balanced', 'the plan\'s line ends restored');

  // the saved mission is what was drawn
  const saved = await (await fetch(`${base}/api/v1/missions/${missionId}`)).json();
  assert.equal(saved.area.coordinates.length, 1);
  assert.ok(saved.home, 'home saved');

  // compare with a second planner
  await page.check('#compare');
  await page.selectOption('#planner', 'e_spiral');
  assert.ok(!(await page.isVisible('#line-ends-box')), 'no line ends for a spiral');
  await page.click('#plan');
  await waitFor(() => page.isVisible('#col-b'), 'the comparison column', 60000);
  const cells = await page.$$eval('#figures tbody tr:first-child td', (t) => t.map((x) => x.textContent));
  assert.deepEqual(cells.slice(1), ['e_spiral', 'boustrophedon']);
  assert.deepEqual([await page.textContent('#col-a'), await page.textContent('#col-b')], ['e_spiral', 'boustrophedon (kept)'], 'the columns say what differs');
  await shot('compared');
  // unticking the box drops the comparison: its column and its faded lines
  const fadedBefore = await page.$$eval('path.leaflet-interactive', (p) => p.filter((x) => Number(x.getAttribute('stroke-opacity')) < 0.5).length);
  assert.ok(fadedBefore > 0, 'the kept plan is drawn faded');
  await page.uncheck('#compare');
  assert.ok(!(await page.isVisible('#col-b')), 'no compare column');
  assert.equal(await page.$$eval('path.leaflet-interactive', (p) => p.filter((x) => Number(x.getAttribute('stroke-opacity')) < 0.5).length), 0, 'no faded lines');

  // three drones share the field: each drawn in its colour, each listed with its figures
  await page.selectOption('#planner', 'boustrophedon');
  await page.fill('#drones', '3');
  await page.dispatchEvent('#drones', 'change');
  assert.ok(await page.isVisible('#layers-box'), 'layer spacing is offered to a fleet');
  await page.evaluate(() => { document.getElementById('status').textContent = ''; });
  await page.click('#plan');
  await waitFor(async () => /planned/.test(await page.textContent('#status')), 'the fleet plan', 60000);
  await waitFor(() => page.isVisible('#fleet-figures'), 'the fleet table');
  assert.equal(await page.$$eval('#fleet-figures tbody tr', (rows) => rows.length), 3, 'a row per drone');
  const strokes = await page.$$eval('path.leaflet-interactive', (paths) => [...new Set(paths.map((p) => p.getAttribute('stroke')))]);
  assert.ok(strokes.length >= 3, `each drone in its own colour: ${strokes}`);
  await page.fill('#drones', '1');
  await page.dispatchEvent('#drones', 'change');

  // a fixed wing: how its flights end and its lead-in, sent as asked
  assert.ok(await page.isVisible('#ends-box') && !(await page.isVisible('#lead-in-box')), 'a multirotor chooses how flights end, without a lead-in');
  await page.selectOption('#vehicle', 'generic_fixed_wing');
  assert.ok(await page.isVisible('#lead-in-box') && !(await page.isVisible('#landing-heading-box')), 'a fixed wing has a lead-in; a heading only for a landing');
  await page.selectOption('#landing', 'auto');
  assert.ok(await page.isVisible('#landing-heading-box'), 'the landing heading once it lands');
  await page.fill('#landing-heading', '270');
  await page.fill('#lead-in', '150');
  // and a wind: a click on the dial's east side makes it blow east, from the west
  await page.fill('#wind-speed', '5');
  const dial = await page.locator('#wind-dial').boundingBox();
  await page.mouse.click(dial.x + dial.width - 2, dial.y + dial.height / 2);
  assert.equal(await page.inputValue('#wind-from'), '270', 'a click east of the dial: a west wind');
  await page.evaluate(() => { document.getElementById('status').textContent = ''; });
  await page.click('#plan');
  await waitFor(async () => /planned/.test(await page.textContent('#status')), 'the fixed-wing plan', 90000);
  const wingSent = (await (await fetch(`${base}/api/v1/missions/${missionId}/plans`)).json()).find((p) => p.params.vehicle.profile === 'generic_fixed_wing').params;
  assert.deepEqual([wingSent.landing, wingSent.landing_heading_deg, wingSent.lead_in_m], ['auto', 270, 150], 'landing, heading and lead-in sent');
  assert.deepEqual(wingSent.wind, { speed_mps: 5, from_deg: 270 }, 'the wind sent');
  assert.match(await page.textContent('td[data-figure=wind]'), /5\.0 m\/s from 270°/, 'the wind the plan was made for');
  await page.fill('#wind-speed', '');
  await page.selectOption('#landing', 'return');

  // a tractor: its implement's fields instead of a camera, the headland planner, passes drawn
  await page.selectOption('#vehicle', 'tractor_sprayer');
  assert.ok(await page.isVisible('#ground-box'), 'the implement and headland fields');
  assert.ok(!(await page.isVisible('#camera-box')) && !(await page.isVisible('#spacing-box')), 'no camera or spacing for a tractor');
  assert.equal(await page.inputValue('#planner'), 'headland');
  await page.fill('#working-width', '12');
  await page.fill('#working-speed', '9');
  await page.fill('#tank-litres', '150');
  await page.selectOption('#swath-ends', 'centre_line');
  // the farm's guidance line typed as an A+ line through the field's centre, a tramline every third swath
  const centre = await page.evaluate(() => { const c = window.coverplan.state.fields.getBounds().getCenter(); return [c.lat, c.lng]; });
  await page.selectOption('#guidance', 'typed');
  assert.ok(!(await page.isVisible('#direction-box')), 'no swath direction beside a guidance line');
  await page.fill('#guidance-a', `${centre[0].toFixed(6)}, ${centre[1].toFixed(6)}`);
  await page.fill('#guidance-bearing', '30');
  await page.fill('#tramline-every', '3');
  await page.evaluate(() => { document.getElementById('status').textContent = ''; });
  await page.click('#plan');
  await waitFor(async () => /planned/.test(await page.textContent('#status')), 'the tractor plan', 60000);
  await waitFor(async () => (await page.$$('path.kind-headland')).length > 0, 'the headland passes');
  assert.ok((await page.$$('path.kind-sweep')).length > 0 && (await page.$$('path.kind-turn')).length > 0, 'swaths and turns');
  assert.equal(await page.textContent('td[data-figure="turns leaving the field"]'), '0');
  assert.match(await page.textContent('td[data-figure="turn shapes"]'), /\d+ U/);
  for (const id of ['#altitude-box', '#gsd-box', '#overlap-box', '#camera-box', '#reference-box']) assert.ok(!(await page.isVisible(id)), `no ${id} for a tractor`);
  assert.match(await page.textContent('td[data-figure=fuel]'), /l of diesel/);
  const tractorParams = (await (await fetch(`${base}/api/v1/missions/${missionId}/plans`)).json()).find((p) => p.params.vehicle.profile === 'tractor_sprayer').params;
  const tractorSent = tractorParams.vehicle;
  assert.deepEqual([tractorSent.cruise_speed_mps, tractorSent.battery_wh], [2.5, 1500000], 'km/h and litres sent as m/s and Wh');
  assert.deepEqual(tractorParams.guidance, { a: [Number(centre[1].toFixed(6)), Number(centre[0].toFixed(6))], bearing_deg: 30 }, 'the A+ line sent as [lon, lat]');
  assert.equal(tractorParams.tramline_every, 3);
  assert.equal(tractorParams.heading_deg, undefined, 'no heading beside the guidance line');
  assert.ok((await page.$$('path.kind-sweep.tramline')).length > 0, 'tramlines drawn');
  assert.match(await page.textContent('td[data-figure=tramlines]'), /^\d+$/);
  assert.ok(await page.isVisible('td[data-figure="working time"]'), 'working time, not flight time');
  const tractorRows = await page.$$eval('#figures tbody td:first-child', (t) => t.map((x) => x.textContent));
  for (const absent of ['sorties', 'photos', 'energy', 'flight time', 'altitude']) assert.ok(!tractorRows.includes(absent), `no ${absent} for a tractor: ${tractorRows}`);
  await shot('tractor');
  await page.selectOption('#guidance', '');
  await page.fill('#tramline-every', '');
  await page.selectOption('#vehicle', 'generic_multirotor');
  assert.equal(await page.inputValue('#planner'), 'boustrophedon', 'back to a drone planner');

  // a patrol of two UAVs: their paths and the visits per cell as a heat map
  await page.click('#patrol-box summary');
  await page.fill('#patrol-uavs', '2');
  await page.fill('#patrol-cycles', '400');
  await page.fill('#patrol-cell', '15');
  await page.click('#patrol');
  await waitFor(async () => /patrolled 400 cycles/.test(await page.textContent('#status')), 'the patrol', 60000);
  assert.ok(await page.isVisible('#patrol-figures'), 'the patrol figures');
  const cellFills = await page.$$eval('path.visits-cell', (cells) => cells.map((c) => c.getAttribute('fill')));
  const listed = await page.textContent('td[data-patrol=cells]');
  assert.match(await page.textContent('td[data-patrol="each spot is seen every"]'), /[\d.]+ min on average/);
  assert.equal(cellFills.length, Number(listed.split(' ')[0]), `a cell drawn per free cell (${listed})`);
  assert.ok(new Set(cellFills).size > 1, 'the heat map shades cells by their visits');

  // a barn drawn with its height and name, inspected: the path and viewpoints on the map, the
  // structure, the path and the points seen and not seen in the 3D view
  await page.selectOption('#draw-kind', 'structure');
  assert.ok(await page.isVisible('#height-box') && await page.isVisible('#structure-name-box'), 'a structure has a height and a name');
  await page.fill('#obstacle-height', '10');
  await page.fill('#structure-name', 'barn');
  await page.click('#draw');
  // wider than the snapping distance (20 px), or each click snaps to the first vertex
  for (const [dx, dy] of [[0, 0], [40, 0], [40, 28], [0, 28], [0, 0]]) {
    await page.mouse.click(...at(dx, dy));
    await page.waitForTimeout(150);
  }
  assert.equal(await page.evaluate(() => window.coverplan.state.structures.getLayers().length), 1, 'one structure drawn');
  await page.selectOption('#planner', 'inspection');
  await page.dispatchEvent('#planner', 'change');
  assert.ok(await page.isVisible('#inspection-box') && !(await page.isVisible('#spacing-box')), 'the inspection fields instead of the line spacing');
  assert.match(await page.textContent('#camera option[value=""]'), /default/, 'an inspection without a chosen camera takes the default preset');
  await page.selectOption('#vehicle', 'iris');
  // the home is some 300 m from the barn: there and back, and around it
  await page.fill('#budget', '1500');
  await page.fill('#target-names', 'barn');
  await page.evaluate(() => { document.getElementById('status').textContent = ''; });
  await page.click('#plan');
  await waitFor(async () => /planned/.test(await page.textContent('#status')), 'the inspection', 90000);
  assert.match(await page.textContent('td[data-figure="points seen"]'), /%/);
  assert.match(await page.textContent('td[data-figure="targets"]'), /barn walls \d+ %/);
  const view = await page.evaluate(() => window.coverplan.state.view3d);
  assert.ok(view.drawn && view.structures === 1 && view.viewpoints > 0 && view.seen > 0, `3D view: ${JSON.stringify(view)}`);
  assert.equal(await page.$$eval('path.viewpoint', (v) => v.length), view.viewpoints, 'each viewpoint on the map');
  const saved3d = await (await fetch(`${base}/api/v1/missions/${missionId}`)).json();
  assert.equal(saved3d.structures.features[0].properties.name, 'barn', 'the structure is saved with the mission');
  // the 3D view draws seen points green and unseen ones red
  const shades = await page.evaluate(() => {
    const gl = document.querySelector('#view3d canvas');
    const c = document.createElement('canvas');
    c.width = gl.width;
    c.height = gl.height;
    const ctx = c.getContext('2d');
    ctx.drawImage(gl, 0, 0);
    const px = ctx.getImageData(0, 0, c.width, c.height).data;
    let green = 0, red = 0;
    for (let i = 0; i < px.length; i += 4) {
      if (px[i + 1] > px[i] + 40 && px[i + 1] > px[i + 2] + 40) green += 1;
      if (px[i] > px[i + 1] + 80 && px[i] > px[i + 2] + 80) red += 1;
    }
    return { green, red };
  });
  assert.ok(shades.green > 0, `seen points drawn: ${JSON.stringify(shades)}`);
  assert.ok(view.unseen === 0 || shades.red > 0, `unseen points drawn: ${JSON.stringify(shades)}`);
  await page.locator('#view3d').screenshot({ path: path.join(os.tmpdir(), 'coverplan-inspection-3d.png') });

  // a camera plan from a start pose with a heading, then the shared link restores all of it
  await page.selectOption('#planner', 'boustrophedon');
  await page.selectOption('#camera', { index: 1 });
  const camera = await page.inputValue('#camera');
  // GSD and altitude are one choice: typing one empties the other
  await page.fill('#altitude', '80');
  await page.fill('#gsd', '2');
  assert.equal(await page.inputValue('#altitude'), '', 'a GSD empties the altitude');
  assert.match(await page.textContent('#preview'), /altitude [\d.]+ m/);
  await page.fill('#altitude', '60');
  assert.equal(await page.inputValue('#gsd'), '', 'an altitude empties the GSD');
  // overlaps in percent
  await page.fill('#side-overlap', '60');
  await page.fill('#front-overlap', '75');
  await waitFor(async () => /GSD [\d.]+ cm\/px · lines [\d.]+ m apart · a photo every [\d.]+ m · sweeps [\d.]+ km: at least \d+ min, \d+ batter/.test(await page.textContent('#preview')), 'the figures before planning');
  await page.selectOption('#draw-kind', 'start');
  await page.fill('#pose-heading', '90');
  await page.click('#draw');
  await page.mouse.click(...at(-140, 100));
  await waitFor(() => page.evaluate(() => !!window.coverplan.state.poses.start), 'the start marker');
  // the last plan's "planned in …" is still shown: clear it, so that only this plan's counts
  await page.evaluate(() => { document.getElementById('status').textContent = ''; });
  await page.click('#plan');
  await waitFor(async () => /planned/.test(await page.textContent('#status')), 'the camera plan', 60000);
  await page.goto(`${base}/?mission=${missionId}`);
  await page.waitForSelector('body[data-ready=true]');
  await page.waitForSelector('td[data-figure=length]');
  const restored = {
    planner: await page.inputValue('#planner'),
    camera: await page.inputValue('#camera'),
    altitude: await page.inputValue('#altitude'),
    side: await page.inputValue('#side-overlap'),
    front: await page.inputValue('#front-overlap'),
    start: await page.evaluate(() => { const m = window.coverplan.state.poses.start; return m && m.cpHeading; }),
  };
  assert.deepEqual(restored, { planner: 'boustrophedon', camera, altitude: '60', side: '60', front: '75', start: 90 });
  const sent = (await (await fetch(`${base}/api/v1/missions/${missionId}/plans`)).json()).find((p) => p.status === 'succeeded').params;
  assert.deepEqual([sent.side_overlap, sent.front_overlap], [0.6, 0.75], 'the API gets fractions');
  assert.match(await page.textContent('td[data-figure=altitude]'), /^60\.0 m above home · GSD [\d.]+ cm\/px$/, 'the altitude flown and its GSD');
  await page.screenshot({ path: path.join(os.tmpdir(), 'coverplan-page.png') });

  // the flight stopped a third of the way along a line: a click there plans the rest, shown
  // over the original, which stays faded beside it
  const stopped = await state(() => {
    const { map, state: s } = window.coverplan;
    const sweeps = s.result.fc.features.filter((f) => f.properties.kind === 'sweep');
    const c = sweeps[Math.floor(sweeps.length / 2)].geometry.coordinates;
    const [a, b] = [c[0], c[c.length - 1]];
    const at = L.latLng(a[1] + 0.3 * (b[1] - a[1]), a[0] + 0.3 * (b[0] - a[0]));
    map.setView(at, map.getZoom(), { animate: false });
    const p = map.latLngToContainerPoint(at);
    const r = map.getContainer().getBoundingClientRect();
    return [r.left + p.x, r.top + p.y];
  });
  // CI once saw the first click go unanswered (the map still settling after setView): a person
  // clicks again
  for (let tries = 1; ; tries += 1) {
    await page.mouse.click(...stopped);
    try {
      await page.waitForSelector('.resume-here', { timeout: 10000 });
      break;
    } catch (e) {
      if (tries === 3) throw e;
    }
  }
  assert.match(await page.textContent('.resume-box'), /stop here \(sweep, (29|30|31) % along\)/);
  await page.click('.resume-here');
  await waitFor(async () => /resumed:/.test(await page.textContent('#status')), 'the resumed plan', 60000);
  assert.match(await page.textContent('td[data-figure="resumed at"]'), /(29|30|31) % along/);
  assert.ok(await state(() => !!window.coverplan.state.compared), 'the original stays, faded');
  assert.deepEqual([await page.textContent('#col-a'), await page.textContent('#col-b')], ['what is left', 'the original (kept)']);
  await shot('resumed');

  // the flight of that plan stopped halfway along a line, its telemetry log (written with
  // pymavlink, tests/interop/make_tlog.py) chosen on the page: the rest is planned, the track
  // flown drawn beside it
  const resumedId = await state(() => window.coverplan.state.result.planId);
  const fc = await (await fetch(`${base}/api/v1/plans/${resumedId}/trajectory`)).json();
  const lines = fc.features.filter((f) => f.properties.kind === 'sweep');
  const logDir = mkdtempSync(path.join(os.tmpdir(), 'coverplan-log-'));
  writeFileSync(path.join(logDir, 'plan.geojson'), JSON.stringify(fc));
  const python = process.env.COVERPLAN_PYTHON || path.join(os.homedir(), '.cache/coverplan-venv/bin/python');
  const seq = String(lines[Math.floor(lines.length / 2)].properties.seq);
  execFileSync(python, [path.join(root, 'tests/interop/make_tlog.py'), path.join(logDir, 'plan.geojson'), path.join(logDir, 'flight.tlog'), '--seq', seq, '--fraction', '0.5']);
  assert.ok(await page.isVisible('#resume-log'), 'a shown plan offers to read its flight log');
  await page.evaluate(() => { document.getElementById('status').textContent = ''; });
  await page.setInputFiles('#resume-log', path.join(logDir, 'flight.tlog'));
  await waitFor(async () => /resumed:/.test(await page.textContent('#status')), 'the plan resumed from the log', 60000);
  assert.ok(await page.locator('path.kind-flown').count() > 0, 'the track flown is drawn');
  rmSync(logDir, { recursive: true, force: true });
  await shot('resumed-from-log');

  // the field again as five passes for a 3D model, the gimbal pitched on four, each pass's
  // figures shown; DJI's download offers the controller's waypoint limit, 99 by default
  await page.selectOption('#pattern', 'oblique');
  assert.ok(await page.isVisible('#oblique-pitch'), 'an oblique plan asks for the gimbal pitch');
  await page.fill('#oblique-pitch', '-50');
  await page.evaluate(() => { document.getElementById('status').textContent = ''; });
  await page.click('#plan');
  await waitFor(async () => /planned/.test(await page.textContent('#status')), 'the oblique plan', 90000);
  const passes = await page.textContent('td[data-figure=passes]');
  assert.equal(passes.split(';').length, 5, `five passes: ${passes}`);
  assert.match(passes, /^nadir: \d+ photos, [\d.]+ km; \d+° at -50°/);
  await page.selectOption('#download-format', 'wpml');
  assert.ok(await page.isVisible('#download-max-waypoints'), 'a controller limit for DJI routes');
  assert.equal(await page.getAttribute('#download-max-waypoints', 'placeholder'), 'default 99');
  await page.fill('#download-max-waypoints', '60');
  assert.match(await page.getAttribute('#download', 'href'), /format=wpml&max_waypoints=60$/);
  await page.selectOption('#download-format', 'kml');
  assert.ok(!(await page.isVisible('#download-max-waypoints')), 'no limit for Google Earth');
  await page.selectOption('#pattern', 'grid');
  await shot('oblique');

  // a road drawn as its centre line with a width, planned by planner corridor, reopened whole
  await page.goto(`${base}/`);
  await page.waitForSelector('body[data-ready=true]');
  await page.selectOption('#draw-kind', 'centre-line');
  assert.ok(await page.isVisible('#corridor-width'), 'a corridor asks for its width');
  await page.fill('#corridor-width', '40');
  await page.fill('#point-at', '51.500, 6.050; 51.503, 6.056; 51.502, 6.064');
  await page.click('#draw');
  await waitFor(async () => /1 corridor · [\d.]+ km/.test(await page.textContent('#mission-area')), 'the corridor');
  await page.selectOption('#vehicle', 'generic_multirotor');
  await page.selectOption('#planner', 'corridor');
  await page.selectOption('#camera', '');
  await page.fill('#spacing', '15');
  await page.evaluate(() => { document.getElementById('status').textContent = ''; });
  await page.click('#plan');
  await waitFor(async () => /planned/.test(await page.textContent('#status')), 'the corridor plan', 60000);
  const roadLines = await state(() => window.coverplan.state.result.fc.features.filter((f) => f.properties.kind === 'sweep').length);
  assert.ok(roadLines >= 3, `a 40 m corridor at 15 m: three lines or more, ${roadLines} flown`);
  const road = await state(() => window.coverplan.state.missionId);
  await page.goto(`${base}/?mission=${road}`);
  await page.waitForSelector('body[data-ready=true]');
  assert.deepEqual(await state(() => window.coverplan.state.corridors.getLayers().map((l) => [l.cpWidth, l.getLatLngs().length])), [[40, 3]], 'the corridor comes back');
  await shot('corridor');

  // a longer road flown in hops: home at one end, landing sites along it where sorties land
  await page.goto(`${base}/`);
  await page.waitForSelector('body[data-ready=true]');
  await page.selectOption('#draw-kind', 'centre-line');
  await page.fill('#corridor-width', '40');
  await page.fill('#point-at', '51.500, 6.050; 51.503, 6.080; 51.500, 6.110');
  await page.click('#draw');
  await page.selectOption('#draw-kind', 'home');
  await page.fill('#point-at', '51.4995, 6.0495');
  await page.click('#draw');
  await page.selectOption('#draw-kind', 'landing-site');
  assert.equal(await page.textContent('#draw'), 'Place', 'a landing site is a point');
  for (const at of ['51.5025, 6.068', '51.5025, 6.092', '51.5005, 6.1105']) {
    await page.fill('#point-at', at);
    await page.click('#draw');
  }
  assert.equal(await state(() => window.coverplan.state.landingSites.getLayers().length), 3, 'three landing sites placed');
  await page.selectOption('#vehicle', 'iris');
  await page.selectOption('#planner', 'corridor');
  await page.selectOption('#camera', '');
  await page.fill('#spacing', '15');
  await page.evaluate(() => { document.getElementById('status').textContent = ''; });
  await page.click('#plan');
  await waitFor(async () => /planned/.test(await page.textContent('#status')), 'the corridor flown in hops', 90000);
  const hops = await state(() => {
    const { fc, params } = window.coverplan.state.result;
    const firsts = new Map();
    for (const f of fc.features) if (f.properties.sortie && f.geometry.type === 'LineString' && !firsts.has(f.properties.sortie)) firsts.set(f.properties.sortie, f.geometry.coordinates[0]);
    const near = (a, b) => Math.abs(a[0] - b[0]) < 1e-6 && Math.abs(a[1] - b[1]) < 1e-6;
    return { sites: params.landing_sites.length, sorties: firsts.size, fromSites: [...firsts.values()].filter((p) => params.landing_sites.some((s) => near(p, s))).length };
  });
  assert.equal(hops.sites, 3, 'the plan asked for the landing sites');
  assert.ok(hops.sorties >= 2 && hops.fromSites >= 1, `sorties take off from landing sites: ${JSON.stringify(hops)}`);
  await shot('landing-sites');

  // a hilly field: its elevation model from the file picker, shaded under the field; planned at
  // 60 m above the ground, with the profile of ground, altitude and band
  const hills = JSON.parse(readFileSync(path.join(root, 'tests/fixtures/terrain/hills-11.json'), 'utf8'));
  const created = await (await fetch(`${base}/api/v1/missions`, { method: 'POST', headers: { 'content-type': 'application/json' }, body: JSON.stringify({ name: 'Hills', area: hills.area, home: hills.home }) })).json();
  await page.goto(`${base}/?mission=${created.id}`);
  await page.waitForSelector('body[data-ready=true]');
  assert.equal(await page.inputValue('#altitude-reference'), 'home', 'no model yet: above home');
  await page.setInputFiles('#terrain-file', path.join(root, 'tests/fixtures/terrain/hills-11.tif'));
  await waitFor(() => page.evaluate(() => !!window.coverplan.state.terrain), 'the elevation model');
  assert.match(await page.textContent('#terrain-info'), /EPSG:32632/);
  assert.equal(await page.locator('img.leaflet-image-layer').count(), 1, 'the shaded relief is drawn');
  assert.equal(await page.inputValue('#altitude-reference'), 'terrain', 'a model given is a model to follow');
  await page.selectOption('#vehicle', 'generic_multirotor');
  await page.selectOption('#camera', '');
  await page.fill('#spacing', '60');
  await page.fill('#altitude', '60');
  await page.fill('#terrain-tolerance', '5');
  await page.evaluate(() => { document.getElementById('status').textContent = ''; });
  await page.click('#plan');
  await waitFor(async () => /planned/.test(await page.textContent('#status')), 'the plan over terrain', 60000);
  const profile = await page.evaluate(() => window.coverplan.state.profile);
  assert.ok(profile.length > 20, `profile of ${profile.length} points`);
  const lowest = Math.min(...profile.map((p) => p.z - p.ground));
  assert.ok(lowest >= 55 - 0.05, `at least 55 m above the ground at every vertex: ${lowest}`);
  assert.ok(await page.isVisible('#profile'), 'the profile is shown');
  await page.screenshot({ path: path.join(os.tmpdir(), 'coverplan-terrain.png') });
  await page.locator('#profile').screenshot({ path: path.join(os.tmpdir(), 'coverplan-terrain-profile.png') });
  await page.goto(`${base}/?mission=${missionId}`);
  await page.waitForSelector('body[data-ready=true]');

  await page.waitForSelector('td[data-figure=length]');

  // an error beside its input: the browser's bounds first, then the server's refusal
  await page.selectOption('#camera', '');
  await page.fill('#spacing', '0.1');
  await page.click('#plan');
  assert.equal(await state(() => document.activeElement.id), 'spacing', 'the input at fault has the focus');
  assert.equal(await page.getAttribute('#spacing', 'aria-invalid'), 'true');
  assert.match(await page.textContent('#spacing-error'), /between 0\.5 and 2000/);
  const [inputBox, barBox] = [await page.locator('#spacing').boundingBox(), await page.locator('.plan-bar').boundingBox()];
  assert.ok(inputBox.y >= 0 && inputBox.y + inputBox.height <= barBox.y, `the input at fault is in sight, above the Plan bar (${inputBox.y}, bar at ${barBox.y})`);
  assert.ok(await page.isVisible('td[data-figure=length]'), 'nothing was planned, nothing was lost');
  await page.evaluate(() => document.getElementById('spacing').removeAttribute('min'));
  refusalsAsked = 1;
  await page.click('#plan');
  await waitFor(() => page.isVisible('#spacing-error'), 'the server\'s refusal beside the spacing');
  assert.doesNotMatch(await page.textContent('#spacing-error'), /\/line_spacing_m/, 'in words, without a pointer');
  assert.equal(await state(() => document.activeElement.id), 'spacing');
  await shot('error-beside-input');
  await page.fill('#spacing', '20');
  assert.equal(await page.$$eval('.field-error', (e) => e.length), 0, 'fixing the input clears its error');

  // keyboard only: Plan is reached in few Tab presses (the plan's shapes are not in the tab
  // order), Enter plans, and the focus moves to the result
  await page.goto(`${base}/?mission=${missionId}`);
  await page.waitForSelector('td[data-figure=length]');
  await page.focus('#mission-name');
  let presses = 0;
  while ((await state(() => document.activeElement.id)) !== 'plan' && presses < 80) {
    await page.keyboard.press('Tab');
    presses += 1;
  }
  assert.ok(presses < 60, `Plan reached in ${presses} Tab presses`);
  const outline = await state(() => getComputedStyle(document.activeElement).outlineStyle);
  assert.notEqual(outline, 'none', 'the focus is visible');
  await page.evaluate(() => { document.getElementById('status').textContent = ''; });
  await page.keyboard.press('Enter');
  await waitFor(async () => /planned/.test(await page.textContent('#status')), 'the plan by keyboard', 60000);
  assert.equal(await state(() => document.activeElement.id), 'result-heading', 'the focus goes to the result');

  // a phone: the map and the form are both there, Plan in sight, finger-sized and 16 px inputs
  await page.setViewportSize({ width: 390, height: 844 });
  assert.ok((await page.locator('#map').boundingBox()).width > 300, 'the map spans a phone screen');
  const phonePlan = await page.locator('#plan').boundingBox();
  assert.ok(phonePlan.y >= 0 && phonePlan.y + phonePlan.height <= 844, `Plan in sight on a phone (${phonePlan.y})`);
  assert.ok(phonePlan.height >= 44, `a 44 px Plan button: ${phonePlan.height}`);
  assert.equal(await state(() => getComputedStyle(document.getElementById('spacing')).fontSize), '16px', '16 px inputs');
  assert.ok((await page.locator('#compare').boundingBox()).height >= 24, 'a finger-sized checkbox');
  await shot('phone');

  // a farm of three fields: each planned, coloured by its plan's status, the schedule as
  // machines by days; a click on a field's stretch of a day opens its plan
  await page.setViewportSize({ width: 1280, height: 800 });
  const square = (east) => {
    const [lon, lat, d] = [6.06 + east, 51.5, 0.0015];
    return [[[lon, lat], [lon + d, lat], [lon + d, lat + d], [lon, lat + d], [lon, lat]]];
  };
  const farmMission = await (await fetch(`${base}/api/v1/missions`, {
    method: 'POST', headers: { 'content-type': 'application/json' },
    body: JSON.stringify({ name: 'Farm', area: { type: 'MultiPolygon', coordinates: [square(0), square(0.004), square(0.008)] }, home: [6.059, 51.4995] }),
  })).json();
  await page.goto(`${base}/?mission=${farmMission.id}`);
  await page.waitForSelector('body[data-ready=true]');
  await page.click('#farm-box summary');
  await page.fill('#farm-machines', '2');
  await page.fill('#farm-hours', '8');
  await page.click('#farm-plan');
  await page.waitForSelector('#farm-gantt:not([hidden])', { timeout: 60000 });
  const farmStatuses = await state(() => window.coverplan.state.farm.polygons.map((p) => p.cpStatus));
  assert.deepEqual(farmStatuses, ['succeeded', 'succeeded', 'succeeded'], 'every field planned and coloured');
  const bars = await page.$$eval('.gantt-work', (b) => b.map((x) => Number(x.dataset.field)));
  assert.deepEqual([...new Set(bars)].sort(), [0, 1, 2], `each field worked in the chart: ${bars}`);
  assert.match(await page.textContent('#farm-gantt'), /last machine home .* no schedule under [\d.]+ h/);
  assert.equal(await page.locator('#farm-gantt tbody tr').count(), 2, 'a row per machine');
  const flights = await page.getAttribute('#farm-flights', 'href');
  const flightsZip = await page.evaluate(async (href) => { const r = await fetch(href); return [r.status, r.headers.get('content-type')]; }, flights);
  assert.deepEqual(flightsZip, [200, 'application/zip'], `the day's flight plans: ${flights}`);
  await page.click('.gantt-work[data-field="1"]');
  await waitFor(async () => /: its plan$/.test(await page.textContent('#status')), 'the field\'s plan');
  const opened = await state(() => window.coverplan.state.result.planId);
  assert.equal(opened, (await state(() => window.coverplan.state.farm.plan.fields[1].plan_id)), 'the plan of the field clicked');
  await shot('farm');

  // once the server has a key, the page asks for one, keeps it for the tab and sends it
  await page.setViewportSize({ width: 1280, height: 800 });
  const made = await new Promise((resolve, reject) => {
    const cli = spawn(binary, ['keys', 'create', '--tenant', 'default', '--database-url', path.join(dir, 'page.db')], { stdio: ['ignore', 'pipe', 'inherit'] });
    let out = '';
    cli.stdout.on('data', (d) => { out += d; });
    cli.on('exit', (code) => (code === 0 ? resolve(out) : reject(new Error(`keys create: ${code}`))));
  });
  const key = made.trim().split('\n').pop();
  const errorsBefore = errors.length;
  assert.equal((await fetch(`${base}/api/v1/missions/${missionId}`)).status, 401, 'the API now needs the key');
  const asked = [];
  page.on('dialog', (d) => { asked.push(d.message()); d.accept(key); });
  await page.goto(`${base}/?mission=${missionId}`);
  await page.waitForSelector('body[data-ready=true]');
  await page.waitForSelector('td[data-figure=length]');
  assert.equal(asked.length, 1, `asked once for the key: ${asked}`);
  assert.equal(await page.evaluate(() => sessionStorage.getItem('coverplan.apiKey')), key);
  const downloaded = page.waitForEvent('download');
  await page.click('#download');
  assert.match((await downloaded).suggestedFilename(), /^New_field/, 'the download sends the key');
  // the browser logs the refusals that made the page ask; nothing else
  const refused = errors.splice(errorsBefore).filter((e) => !/status of 401/.test(e));
  assert.deepEqual(refused, [], 'no other errors once keys are needed');

  assert.deepEqual(foreign, [], 'nothing is loaded from outside the server');
  assert.deepEqual(errors, [], 'no script errors');
  console.log(`map page: ok (${sweeps} sweeps drawn; screenshot in ${path.join(os.tmpdir(), 'coverplan-page.png')})`);
} finally {
  if (browser) await browser.close();
  server.kill('SIGTERM');
  rmSync(dir, { recursive: true, force: true });
}
