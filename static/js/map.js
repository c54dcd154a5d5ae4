// The map and what is drawn on it, shared by the mission, plan and result parts.

export const map = L.map('map', { zoomControl: true }).setView([51.5, 6.06], 15);
L.control.scale({ imperial: false }).addTo(map);
// the plan's path above the mission's shapes (the overlay pane), so that its pieces answer the
// pointer inside a field: a tooltip, a click to resume from
map.createPane('result').style.zIndex = 450;

export const state = {
  missionId: null,
  fields: L.featureGroup().addTo(map), // polygons with holes
  corridors: L.featureGroup().addTo(map), // centre lines with cpWidth (m)
  zones: L.featureGroup().addTo(map),
  obstacles: L.featureGroup().addTo(map),
  structures: L.featureGroup().addTo(map), // to inspect: polygons or circles with cpHeight, cpBase, cpName
  poses: { home: null, start: null, end: null },
  landingSites: L.featureGroup().addTo(map), // the plan's landing sites: markers
  result: null, // { layer, photos, fc, stats, params }
  compared: null,
  planId: null,
  patrol: null, // { layer, stats }
  farm: null, // { plan, layer, polygons }: a farm plan of the mission's fields
  guidanceLines: [], // an imported file's guidance lines: [{ name, guidance }]
};

/** Results are not drawn on: shapes drawn over a plan snap to the mission, not to its lines. */
export function notForDrawing(group) {
  group.eachLayer((l) => {
    if (l.eachLayer) notForDrawing(l);
    Object.assign(l.options, { snapIgnore: true, pmIgnore: true });
  });
  return group;
}

window.coverplan = { map, state }; // for the browser test and the curious
