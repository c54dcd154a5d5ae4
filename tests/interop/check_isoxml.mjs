// Reads coverplan's ISOXML TaskData exports with the isoxml library (ISO 11783-10) and checks
// what they hold. usage: node check_isoxml.mjs DIR, where DIR/manifest.json lists the files:
// {"files": [{"file", "format": "isoxml", "fields", "holes", "zones", "swath_width_mm", "lines",
// "headland_passes"?, "guidance"?, "tramlines"?, "tasks"? (default: one per partfield)}]}, each
// task working a partfield of the file: a ground plan's headland passes are curve
// patterns, its tramline swaths tram lines (line strings of type 3) of the partfield; the
// farm's guidance line it followed ({"a": [lon, lat], "b"?: [lon, lat], "bearing_deg"?}) is an AB
// or A+ pattern propagating to both sides, read back to 1 cm and 0.01°.
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { ISOXMLManager } from 'isoxml';

const dir = process.argv[2];
const manifest = JSON.parse(readFileSync(join(dir, 'manifest.json'), 'utf8'));
let passed = 0;
let failed = 0;
// the library keeps enumerations as the strings of the file
const code = (value) => Number(value);
const check = (ok, message) => { if (!ok) throw new Error(message); };

for (const spec of manifest.files.filter((f) => f.format === 'isoxml')) {
  try {
    const manager = new ISOXMLManager();
    await manager.parseISOXMLFile(new Uint8Array(readFileSync(join(dir, spec.file))), 'application/zip');
    check(manager.getWarnings().length === 0, `warnings: ${manager.getWarnings().join('; ')}`);
    const partfields = manager.getEntitiesOfTag('PFD');
    check(partfields.length === spec.fields, `${partfields.length} partfields, expected ${spec.fields}`);
    const polygons = partfields.flatMap((p) => p.attributes.PolygonnonTreatmentZoneonly ?? []);
    const boundaries = polygons.filter((p) => code(p.attributes.PolygonType) === 1);
    const obstacles = polygons.filter((p) => code(p.attributes.PolygonType) === 6);
    check(boundaries.length === spec.fields, `${boundaries.length} boundaries`);
    check(obstacles.length === spec.zones, `${obstacles.length} obstacles, expected ${spec.zones}`);
    const rings = boundaries.flatMap((b) => b.attributes.LineString);
    const holes = rings.filter((r) => code(r.attributes.LineStringType) === 2).length;
    check(holes === spec.holes, `${holes} interior rings, expected ${spec.holes}`);
    for (const ring of rings) {
      for (const point of ring.attributes.Point) {
        const { PointNorth: lat, PointEast: lon } = point.attributes;
        check(Math.abs(lat) <= 90 && Math.abs(lon) <= 180, `point (${lat}, ${lon}) out of range`);
      }
    }
    const patterns = partfields.flatMap((p) => p.attributes.GuidanceGroup ?? []).flatMap((g) => g.attributes.GuidancePattern);
    const lines = patterns.filter((p) => code(p.attributes.GuidancePatternType) === 1);
    const curves = patterns.filter((p) => code(p.attributes.GuidancePatternType) === 3);
    const aPlus = patterns.filter((p) => code(p.attributes.GuidancePatternType) === 2);
    check(lines.length + curves.length + aPlus.length === patterns.length, 'guidance patterns are AB lines, A+ lines or curves');
    if (spec.guidance) {
      const g = spec.guidance;
      const farm = patterns.filter((p) => ['AB line', 'A+ line'].includes(p.attributes.GuidancePatternDesignator));
      check(farm.length === spec.fields, `${farm.length} farm guidance lines, expected one per partfield`);
      for (const p of farm) {
        check(code(p.attributes.GuidancePatternPropagationDirection) === 1, 'the farm line propagates to both sides');
        const points = p.attributes.LineString[0].attributes.Point.map((q) => [Number(q.attributes.PointEast), Number(q.attributes.PointNorth)]);
        // metres between two positions, near enough for a centimetre
        const metres = (u, v) => Math.hypot((u[0] - v[0]) * 111320 * Math.cos((u[1] * Math.PI) / 180), (u[1] - v[1]) * 110540);
        check(metres(points[0], g.a) < 0.01, `point A ${points[0]} is not ${g.a}`);
        if (g.b) {
          check(code(p.attributes.GuidancePatternType) === 1 && points.length === 2 && metres(points[1], g.b) < 0.01, `point B ${points[1]} is not ${g.b}`);
        } else {
          check(code(p.attributes.GuidancePatternType) === 2 && points.length === 1, 'an A+ line has its point A only');
          check(Math.abs(Number(p.attributes.GuidancePatternHeading) - g.bearing_deg) < 0.01, `heading ${p.attributes.GuidancePatternHeading} is not ${g.bearing_deg}`);
        }
      }
    }
    const swaths = lines.filter((p) => code(p.attributes.GuidancePatternPropagationDirection) === 4);
    check(swaths.length === spec.lines, `${swaths.length} swaths, expected ${spec.lines}`);
    check(curves.length === (spec.headland_passes ?? 0), `${curves.length} headland curves, expected ${spec.headland_passes ?? 0}`);
    for (const p of patterns) {
      const [line] = p.attributes.LineString;
      check(code(line.attributes.LineStringType) === 5 && line.attributes.LineStringWidth === spec.swath_width_mm, 'a guidance line string is as wide as the swath');
      const type = code(p.attributes.GuidancePatternType);
      const expected = type === 3 ? line.attributes.Point.length >= 3 : line.attributes.Point.length === (type === 2 ? 1 : 2);
      check(expected, 'an AB line has two points, an A+ line one, a curve three or more');
    }
    const tramlines = partfields.flatMap((p) => p.attributes.LineString ?? []).filter((l) => code(l.attributes.LineStringType) === 3);
    check(tramlines.length === (spec.tramlines ?? 0), `${tramlines.length} tram lines, expected ${spec.tramlines ?? 0}`);
    for (const t of tramlines) {
      check(t.attributes.Point.length === 2 && t.attributes.LineStringWidth === spec.swath_width_mm, 'a tram line is a swath: two points, its width');
    }
    const tasks = manager.getEntitiesOfTag('TSK');
    check(tasks.length === (spec.tasks ?? spec.fields), `${tasks.length} tasks, expected ${spec.tasks ?? spec.fields}`);
    const partfieldIds = new Set(partfields.map((p) => manager.getReferenceByEntity(p).xmlId));
    for (const t of tasks) {
      const field = t.attributes.PartfieldIdRef;
      check(field && partfieldIds.has(field.xmlId), `task ${t.attributes.TaskDesignator} works no partfield of the file`);
    }
    passed += 1;
  } catch (e) {
    failed += 1;
    console.log(`FAIL ${spec.file}: ${e.message}`);
  }
}
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed || !passed ? 1 : 0);
