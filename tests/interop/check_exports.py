"""Reads coverplan's exported files with independent readers and checks what they hold.

usage: check_exports.py DIR

DIR/manifest.json (written by tests/it/db/interop.rs) lists the files and what each must hold:
  {"files": [{"file", "format", "waypoints": [[lat, lon], ...], "pieces", "fields", "holes",
              "zones", "photo_lines", "photos"}]}
"photos" (the plan's photo count, when its sweeps are straight lines) is checked against the
photos an autopilot triggering by distance takes along the MAVLink files; their extra waypoints
where a line's photos start and stop must lie on the planned lines.
An oblique plan adds "passes" ([{"pitch", "heading"}] in flight order; heading a compass bearing,
null on the nadir pass) and, for PX4, "waypoint_headings" (the yaw its waypoints hold, pass by
pass): the MAVLink files pitch the gimbal once a pass
(MAV_CMD_DO_GIMBAL_MANAGER_PITCHYAW) and hold each oblique pass's heading (ArduPilot:
MAV_CMD_CONDITION_YAW), the WPML file turns and pitches with rotateYaw and gimbalRotate, and the
GeoJSON photos name their pass, pitch and heading.
A plan over terrain adds "frame" (the MAVLink frame of positions: 0 above mean sea level, 10 above
the ground), "heights" (each waypoint's altitude in that frame) and "home_alt" (the ground at home,
above mean sea level).
"missions" (optional) lists flights cut into missions for a controller's waypoint limit:
  [{"parts": [file, ...], "format", "max_waypoints", "photos", "zones"}]: each part read by the same
readers, within the limit (WPML placemarks; MAVLink items after home), each beginning at the
waypoint where the one before ended, and together taking at least the plan's photos (lines are
triggered from end to end there).
"sorties" (optional) lists flights split into sorties between landing sites:
  [{"parts": [file, ...], "format", "homes": [[lat, lon], ...], "landings": [[lat, lon] or null, ...]}]:
each sortie's file read by the same readers takes off from its own home (the home item, QGC's
planned home, or the first waypoint of WPML) and, where it lands elsewhere, lands there itself
(NAV_LAND at that place, WPML's finishAction autoLand) instead of returning to launch.
Readers: pymavlink's waypoint loader (QGC WPL 110), jsonschema with qgc-plan.schema.json (the
.plan format as QGroundControl documents it), fastkml (KML, KMZ), the standard library's XML
parser (GeoJSON, DJI WPML). ISOXML is read by check_isoxml.mjs with the isoxml library.
"""

import io
import json
import sys
import zipfile
import xml.etree.ElementTree as ET
from pathlib import Path

import jsonschema
from fastkml import kml
from pymavlink import mavutil, mavwp

HERE = Path(__file__).parent
TOLERANCE_DEG = 1e-7  # about 1 cm
TOLERANCE_M = 0.011  # the files' centimetres
# QGroundControl's AltitudeMode of each MAVLink frame
ALTITUDE_MODES = {3: 1, 0: 2, 10: 4}
NAV_WAYPOINT = mavutil.mavlink.MAV_CMD_NAV_WAYPOINT
NAV_TAKEOFF = mavutil.mavlink.MAV_CMD_NAV_TAKEOFF
ENDS = {mavutil.mavlink.MAV_CMD_NAV_RETURN_TO_LAUNCH, mavutil.mavlink.MAV_CMD_NAV_LAND}
CAM_TRIGG_DIST = mavutil.mavlink.MAV_CMD_DO_SET_CAM_TRIGG_DIST
GIMBAL_PITCHYAW = mavutil.mavlink.MAV_CMD_DO_GIMBAL_MANAGER_PITCHYAW
CONDITION_YAW = mavutil.mavlink.MAV_CMD_CONDITION_YAW
ANGLE_TOLERANCE_DEG = 0.01
WPML = "{http://www.dji.com/wpmz/1.0.6}"
KML = "{http://www.opengis.net/kml/2.2}"


def same_point(f, e):
    return abs(f[0] - e[0]) <= TOLERANCE_DEG and abs(f[1] - e[1]) <= TOLERANCE_DEG


def same_points(found, expected, what, extras_on_legs=False):
    """The planned points in order; with `extras_on_legs`, other points may come between two
    planned ones if they lie on the leg between them. Returns the indices of the planned ones."""
    if not extras_on_legs:
        assert len(found) == len(expected), f"{what}: {len(found)} waypoints, expected {len(expected)}"
        for k, (f, e) in enumerate(zip(found, expected)):
            assert same_point(f, e), f"{what}: waypoint {k} at {f}, expected {e}"
        return list(range(len(found)))
    matched, k = [], 0
    for i, f in enumerate(found):
        if k < len(expected) and same_point(f, expected[k]):
            matched.append(i)
            k += 1
            continue
        assert 0 < k < len(expected) and on_leg(f, expected[k - 1], expected[k]), f"{what}: waypoint {i} at {f} is neither the next planned point {expected[min(k, len(expected) - 1)]} nor on the leg to it"
    assert k == len(expected), f"{what}: {k} of {len(expected)} planned points found"
    return matched


def on_leg(p, a, b):
    """Whether p lies on the segment from a to b (degrees, within about a centimetre)."""
    (ay, ax), (by, bx), (py, px) = a, b, p
    dx, dy = bx - ax, by - ay
    length2 = dx * dx + dy * dy
    t = ((px - ax) * dx + (py - ay) * dy) / length2 if length2 else 0.0
    return -1e-9 <= t <= 1 + 1e-9 and abs((px - ax) * dy - (py - ay) * dx) / max(length2 ** 0.5, 1e-12) <= TOLERANCE_DEG


def autopilot_distance(firmware, a, b):
    """Metres between (lat, lon) points as the autopilot measures them when it triggers by
    distance: ArduPilot's Location::get_distance (111 318.845 m a degree, longitude scaled at the
    mean latitude), PX4's haversine on a 6 371 km sphere."""
    import math

    if firmware == "ardupilot":
        scale = max(math.cos(math.radians((a[0] + b[0]) / 2)), 0.01)
        return 111318.84502145034 * math.hypot(b[0] - a[0], (b[1] - a[1]) * scale)
    la, lb = math.radians(a[0]), math.radians(b[0])
    h = math.sin((lb - la) / 2) ** 2 + math.cos(la) * math.cos(lb) * math.sin(math.radians(b[1] - a[1]) / 2) ** 2
    return 2 * 6371000.0 * math.asin(min(1.0, math.sqrt(h)))


def photos_agree(taken, spec, what):
    """The photos taken are the plan's, within one a line: the written step allows for the
    autopilot's checking the distance 50 times a second, which this exact rule does not."""
    assert abs(taken - spec["photos"]) <= spec["photo_lines"], f"{what}: an autopilot takes {taken} photos, the plan shows {spec['photos']}"


def autopilot_photos(items, firmware="ardupilot"):
    """Photos an autopilot triggering by distance takes along (command, p1, p3, lat, lon) items,
    in its own metric: one when a distance is set with "trigger now", then one whenever it is
    that distance from the last, until a distance of 0. ArduPilot's and PX4's rule."""
    photos, at, distance = [], None, 0.0
    for command, p1, p3, lat, lon in items:
        if command == CAM_TRIGG_DIST:
            distance = p1
            if p3 == 1 and at is not None:
                photos.append(at)
            continue
        if command != NAV_WAYPOINT:
            continue
        to = (lat, lon)
        if at is not None and distance > 0:
            start = at
            along = lambda s: (start[0] + (to[0] - start[0]) * s, start[1] + (to[1] - start[1]) * s)
            s = 0.0
            while autopilot_distance(firmware, photos[-1], along(1.0)) >= distance:
                lo, hi = s, 1.0
                for _ in range(60):
                    mid = (lo + hi) / 2
                    if autopilot_distance(firmware, photos[-1], along(mid)) < distance:
                        lo = mid
                    else:
                        hi = mid
                s = hi
                photos.append(along(s))
        at = to
    return photos


def same_heights(found, spec, what, offset=0.0, planned=None):
    """Each waypoint's altitude against the planned one (less `offset`), when the plan says them;
    `planned`: the indices of the planned waypoints among those found."""
    if "heights" not in spec:
        return
    if planned is not None:
        found = [found[i] for i in planned]
    expected = [h - offset for h in spec["heights"]]
    assert len(found) == len(expected), f"{what}: {len(found)} heights, expected {len(expected)}"
    for k, (f, e) in enumerate(zip(found, expected)):
        assert abs(f - e) <= TOLERANCE_M, f"{what}: waypoint {k} at {f} m, planned {e} m"


def check_waypoints(path, spec):
    loader = mavwp.MAVWPLoader()
    count = loader.load(str(path))
    items = [loader.wp(i) for i in range(1, count)]  # item 0 is home
    assert items[0].command == NAV_TAKEOFF, f"first item is {items[0].command}, not a take-off"
    assert items[-1].command in ENDS, f"last item is {items[-1].command}, not a return or landing"
    without_position = {mavutil.mavlink.MAV_CMD_NAV_RETURN_TO_LAUNCH}
    for i in items:
        expected_frame = 2 if i.command >= 100 or i.command in without_position else spec.get("frame", 3)
        assert i.frame == expected_frame, f"item {i.seq}: frame {i.frame}"
    if "home_alt" in spec:
        assert abs(loader.wp(0).z - spec["home_alt"]) <= TOLERANCE_M, f"home at {loader.wp(0).z} m, the ground at {spec['home_alt']} m"
    planned = same_points([(i.x, i.y) for i in items if i.command == NAV_WAYPOINT], spec["waypoints"], path.name, extras_on_legs=True)
    same_heights([i.z for i in items if i.command == NAV_WAYPOINT], spec, path.name, planned=planned)
    if "photos" in spec:
        taken = autopilot_photos([(i.command, i.param1, i.param3, i.x, i.y) for i in items])
        photos_agree(len(taken), spec, path.name)
    first_waypoint = next(k for k, i in enumerate(items) if i.command == NAV_WAYPOINT)
    speeds = [i.param2 for i in items[:first_waypoint] if i.command == mavutil.mavlink.MAV_CMD_DO_CHANGE_SPEED]
    assert speeds and speeds[0] > 0, "the speed is set before the first waypoint"
    # a line's camera starts with "trigger now" (a line of one photo: a distance of 0)
    starts = sum(1 for i in items if i.command == CAM_TRIGG_DIST and (i.param1 > 0 or i.param3 == 1))
    assert starts == spec["photo_lines"], f"camera started {starts} times, expected {spec['photo_lines']}"
    check_camera_poses([(i.command, i.param1, i.param4) for i in items], spec, path.name)


def same_angles(found, expected, what):
    assert len(found) == len(expected), f"{what}: {found}, expected {expected}"
    for f, e in zip(found, expected):
        assert abs((f - e + 180) % 360 - 180) <= ANGLE_TOLERANCE_DEG, f"{what}: {found}, expected {expected}"


def check_camera_poses(items, spec, what):
    """items: (command, param1, param4) in order. One gimbal pitch a pass, in order; every oblique
    pass's heading held (ArduPilot's CONDITION_YAW after its waypoints)."""
    if "passes" not in spec:
        return
    same_angles([p1 for c, p1, _ in items if c == GIMBAL_PITCHYAW], [p["pitch"] for p in spec["passes"]], f"{what}: gimbal pitches")
    held = []
    for c, p1, _ in items:
        if c == CONDITION_YAW and (not held or abs(held[-1] - p1) > ANGLE_TOLERANCE_DEG):
            held.append(p1)
    same_angles(held, [p["heading"] for p in spec["passes"] if p["heading"] is not None], f"{what}: headings held")
    # PX4 reads the heading from each waypoint's yaw (param 4; null keeps the current one)
    if "waypoint_headings" in spec:
        faced = []
        for c, _, p4 in items:
            if c == NAV_WAYPOINT and p4 is not None and p4 == p4 and (not faced or abs(faced[-1] - p4) > ANGLE_TOLERANCE_DEG):
                faced.append(p4)
        same_angles(faced, spec["waypoint_headings"], f"{what}: waypoints' yaw")


def ring_area(points):
    """Signed area of a [lat, lon] ring in the (lon, lat) plane: negative when clockwise."""
    return sum(a[1] * b[0] - b[1] * a[0] for a, b in zip(points, points[1:] + points[:1])) / 2


def check_plan(path, spec):
    plan = json.loads(path.read_text())
    jsonschema.validate(plan, json.loads((HERE / "qgc-plan.schema.json").read_text()))
    items = plan["mission"]["items"]
    assert [i["doJumpId"] for i in items] == list(range(1, len(items) + 1)), "doJumpId must count from 1"
    waypoints = [i for i in items if i["command"] == NAV_WAYPOINT]
    planned = same_points([(i["params"][4], i["params"][5]) for i in waypoints], spec["waypoints"], path.name, extras_on_legs=True)
    frame = spec.get("frame", 3)
    assert plan["mission"]["globalPlanAltitudeMode"] == ALTITUDE_MODES[frame]
    assert all(i["frame"] == frame and i["AltitudeMode"] == ALTITUDE_MODES[frame] for i in waypoints), f"{path.name}: every waypoint in frame {frame}"
    same_heights([i["Altitude"] for i in waypoints], spec, path.name, planned=planned)
    if "photos" in spec:
        taken = autopilot_photos([(i["command"], i["params"][0], i["params"][2], i["params"][4], i["params"][5]) for i in items])
        photos_agree(len(taken), spec, path.name)
    check_camera_poses([(i["command"], i["params"][0], i["params"][3]) for i in items], spec, path.name)
    if "home_alt" in spec:
        assert abs(plan["mission"]["plannedHomePosition"][2] - spec["home_alt"]) <= TOLERANCE_M, "home on the ground"
    fences = plan["geoFence"]["polygons"]
    inclusion = [f for f in fences if f["inclusion"]]
    assert len(inclusion) == 1, "one inclusion fence"
    home = plan["mission"]["plannedHomePosition"][:2]
    flown = [(i["params"][4], i["params"][5]) for i in items if i["frame"] != 2] + [tuple(home)]
    outside = [p for p in flown if not inside(p, inclusion[0]["polygon"])]
    assert not outside, f"{path.name}: {len(outside)} points of the flight outside the inclusion fence, first {outside[:1]}"
    assert sum(1 for f in fences if not f["inclusion"]) == spec["zones"], "one exclusion fence per no-fly zone"
    for f in fences:
        assert ring_area(f["polygon"]) < 0, "fence polygons are written clockwise"


def inside(point, ring):
    """Whether point (lat, lon) lies inside ring ([lat, lon] corners, not closed): the even-odd rule."""
    y, x = point
    within = False
    for i, (ay, ax) in enumerate(ring):
        by, bx = ring[i - 1]
        if (ay > y) != (by > y) and x < (bx - ax) * (y - ay) / (by - ay) + ax:
            within = not within
    return within


def placemarks(feature):
    for child in getattr(feature, "features", None) or []:
        if type(child).__name__ == "Placemark":
            yield child
        else:
            yield from placemarks(child)


def check_kml(text, spec, name):
    document = kml.KML.from_string(text)
    marks = [p for f in document.features for p in placemarks(f)]
    polygons = [p for p in marks if type(p.geometry).__name__ == "Polygon"]
    lines = [p for p in marks if type(p.geometry).__name__ == "LineString"]
    assert len(polygons) == spec["fields"] + spec["zones"], f"{name}: {len(polygons)} polygons"
    holes = sum(len(list(p.geometry.interiors)) for p in polygons)
    assert holes == spec["holes"], f"{name}: {holes} holes, expected {spec['holes']}"
    assert len(lines) == spec["pieces"], f"{name}: {len(lines)} flown pieces, expected {spec['pieces']}"
    for p in polygons:
        lon, lat = list(p.geometry.exterior.coords)[0][:2]
        assert -180 <= lon <= 180 and -90 <= lat <= 90
    if spec.get("frame") == 0:
        # heights above mean sea level: absolute, and every flown point's height is a planned one
        modes = {e.text for e in ET.fromstring(text).iter(f"{KML}altitudeMode")} - {"clampToGround"}
        assert modes == {"absolute"}, f"{name}: altitude modes {modes}"
        planned = spec["heights"]
        for line in lines:
            for point in line.geometry.coords:
                assert any(abs(point[2] - h) <= TOLERANCE_M for h in planned), f"{name}: a point at {point[2]} m was not planned"


def check_geojson(path, spec):
    collection = json.loads(path.read_text())
    assert collection["type"] == "FeatureCollection" and "crs" not in collection
    flown = [f for f in collection["features"] if f["properties"].get("kind") in ("sweep", "turn", "transit")]
    assert len(flown) == spec["pieces"], f"{len(flown)} flown pieces, expected {spec['pieces']}"
    assert all(f["geometry"]["type"] == "LineString" for f in flown)
    assert [f["properties"]["seq"] for f in flown] == sorted(f["properties"]["seq"] for f in flown), "pieces in flight order"
    if "passes" in spec:
        photos = [f["properties"] for f in collection["features"] if f["properties"].get("kind") == "photos"]
        assert [p["pass"] for p in photos] == list(range(1, len(spec["passes"]) + 1)), "one MultiPoint of photos a pass"
        same_angles([p["gimbal_pitch_deg"] for p in photos], [p["pitch"] for p in spec["passes"]], "photos' gimbal pitch")
        assert [p.get("camera_heading_deg") is None for p in photos] == [p["heading"] is None for p in spec["passes"]]


def check_wpml(path, spec):
    with zipfile.ZipFile(path) as z:
        names = set(z.namelist())
        assert {"wpmz/template.kml", "wpmz/waylines.wpml"} <= names, f"{path.name}: {names}"
        waylines = ET.fromstring(z.read("wpmz/waylines.wpml"))
        template = ET.fromstring(z.read("wpmz/template.kml"))
    marks = waylines.findall(f".//{KML}Placemark")
    assert [int(m.find(f"{WPML}index").text) for m in marks] == list(range(len(marks))), "indices count from 0"
    assert waylines.find(f".//{WPML}executeHeightMode").text == "relativeToStartPoint"
    points = []
    for m in marks:
        lon, lat = map(float, m.find(f"{KML}Point/{KML}coordinates").text.split(","))
        points.append((lat, lon))
        # over terrain a waypoint may lie below the take-off point
        assert "heights" in spec or float(m.find(f"{WPML}executeHeight").text) > 0
        assert 0 < float(m.find(f"{WPML}waypointSpeed").text) <= 15
    planned = same_points(points, spec["waypoints"], path.name, extras_on_legs=True)
    heights = [float(m.find(f"{WPML}executeHeight").text) for m in marks]
    same_heights(heights, spec, path.name, spec.get("home_alt", 0.0), planned=planned)
    # a photo at the group's first waypoint and one every step until its last (DJI's
    # multipleDistance), at most one group a line
    groups = [g for g in waylines.findall(f".//{WPML}actionGroup") if g.find(f".//{WPML}actionTriggerType").text == "multipleDistance"]
    assert 0 < len(groups) <= spec["photo_lines"], f"{len(groups)} photo groups for {spec['photo_lines']} lines"
    if "passes" in spec:
        params = lambda func: [a.find(f"{WPML}actionActuatorFuncParam") for a in waylines.iter(f"{WPML}action") if a.find(f"{WPML}actionActuatorFunc").text == func]
        pitches = [float(p.find(f"{WPML}gimbalPitchRotateAngle").text) for p in params("gimbalRotate")]
        same_angles(pitches, [p["pitch"] for p in spec["passes"]], f"{path.name}: gimbalRotate")
        turns = [float(p.find(f"{WPML}aircraftHeading").text) for p in params("rotateYaw")]
        same_angles(turns, [p["heading"] for p in spec["passes"] if p["heading"] is not None], f"{path.name}: rotateYaw")
    if "photos" in spec:
        taken = 0
        for g in groups:
            start, end = int(g.find(f"{WPML}actionGroupStartIndex").text), int(g.find(f"{WPML}actionGroupEndIndex").text)
            step = float(g.find(f".//{WPML}actionTriggerParam").text)
            length = sum(autopilot_distance("px4", points[k], points[k + 1]) for k in range(start, end))
            taken += 1 + (int(length / step + 1e-6) if step > 0 else 0)
        photos_agree(taken, spec, path.name)
    assert len(template.findall(f".//{KML}Placemark")) == len(marks)


def mission_points(path, fmt):
    """The positions ([lat, lon]) of a mission's waypoints, its item count, and the photos its
    camera takes."""
    if fmt == "wpml":
        with zipfile.ZipFile(path) as z:
            waylines = ET.fromstring(z.read("wpmz/waylines.wpml"))
        marks = waylines.findall(f".//{KML}Placemark")
        points = [tuple(reversed([float(v) for v in m.find(f"{KML}Point/{KML}coordinates").text.split(",")])) for m in marks]
        taken = 0
        for g in waylines.findall(f".//{WPML}actionGroup"):
            if g.find(f".//{WPML}actionTriggerType").text != "multipleDistance":
                continue
            start, end = int(g.find(f"{WPML}actionGroupStartIndex").text), int(g.find(f"{WPML}actionGroupEndIndex").text)
            step = float(g.find(f".//{WPML}actionTriggerParam").text)
            length = sum(autopilot_distance("px4", points[k], points[k + 1]) for k in range(start, end))
            taken += 1 + (int(length / step + 1e-6) if step > 0 else 0)
        return points, len(marks), taken
    _, rows = mavlink_mission(path, fmt)
    points = [(r[3], r[4]) for r in rows if r[0] == NAV_WAYPOINT]
    return points, len(rows), len(autopilot_photos(rows))


def mavlink_mission(path, fmt):
    """A MAVLink mission's home ((lat, lon): the WPL home item, the .plan's planned home) and its
    items after home as (command, param1, param3, lat, lon)."""
    if fmt == "plan":
        plan = json.loads(path.read_text())
        jsonschema.validate(plan, json.loads((HERE / "qgc-plan.schema.json").read_text()))
        rows = [(i["command"], i["params"][0], i["params"][2], i["params"][4], i["params"][5]) for i in plan["mission"]["items"]]
        return tuple(plan["mission"]["plannedHomePosition"][:2]), rows
    loader = mavwp.MAVWPLoader()
    count = loader.load(str(path))
    rows = [(i.command, i.param1, i.param3, i.x, i.y) for i in (loader.wp(k) for k in range(1, count))]
    return (loader.wp(0).x, loader.wp(0).y), rows


def check_missions(folder, spec):
    photos, previous_end = 0, None
    for name in spec["parts"]:
        points, count, taken = mission_points(folder / name, spec["format"])
        assert count <= spec["max_waypoints"], f"{name}: {count} waypoints, the limit {spec['max_waypoints']}"
        if previous_end is not None:
            assert same_point(points[0], previous_end), f"{name} begins at {points[0]}, the mission before ended at {previous_end}"
        previous_end = points[-1]
        photos += taken
    assert photos >= spec["photos"], f"{spec['format']}: the missions take {photos} photos, the plan {spec['photos']}"


def check_sorties(folder, spec):
    assert len(spec["parts"]) == len(spec["homes"]) >= 2, f"{spec['format']}: {len(spec['parts'])} files for {len(spec['homes'])} sorties"
    for name, home, landing in zip(spec["parts"], spec["homes"], spec["landings"]):
        path = folder / name
        if spec["format"] == "wpml":
            with zipfile.ZipFile(path) as z:
                waylines = ET.fromstring(z.read("wpmz/waylines.wpml"))
            finish = waylines.find(f".//{WPML}finishAction").text
            assert finish == ("autoLand" if landing else "goHome"), f"{name}: finishAction {finish}"
            continue
        launch, rows = mavlink_mission(path, spec["format"])
        command, last = rows[-1][0], rows[-1][3:]
        assert same_point(launch, home), f"{name}: home {launch}, the sortie takes off at {home}"
        if landing:
            assert command == mavutil.mavlink.MAV_CMD_NAV_LAND and same_point(last, landing), f"{name}: ends with {command} at {last}, not a landing at {landing}"
        else:
            assert command == mavutil.mavlink.MAV_CMD_NAV_RETURN_TO_LAUNCH, f"{name}: ends with {command}, not a return to launch"


def main(folder):
    folder = Path(folder)
    manifest = json.loads((folder / "manifest.json").read_text())
    passed = failed = 0
    for spec in (f for f in manifest["files"] if f["format"] != "isoxml"):  # check_isoxml.mjs reads those
        path = folder / spec["file"]
        try:
            fmt = spec["format"]
            if fmt == "geojson":
                check_geojson(path, spec)
            elif fmt == "waypoints":
                check_waypoints(path, spec)
            elif fmt == "plan":
                check_plan(path, spec)
            elif fmt == "kml":
                check_kml(path.read_bytes(), spec, path.name)
            elif fmt == "kmz":
                with zipfile.ZipFile(path) as z:
                    check_kml(z.read("doc.kml"), spec, path.name)
            elif fmt == "wpml":
                check_wpml(path, spec)
            else:
                raise AssertionError(f"no check for format {fmt}")
            passed += 1
        except Exception as e:  # report every file, then fail
            failed += 1
            print(f"FAIL {spec['file']}: {type(e).__name__}: {e}")
    for section, check in (("missions", check_missions), ("sorties", check_sorties)):
        for spec in manifest.get(section, []):
            try:
                check(folder, spec)
                passed += 1
            except Exception as e:
                failed += 1
                print(f"FAIL {section} {spec['format']}: {type(e).__name__}: {e}")
    print(f"{passed} passed, {failed} failed")
    sys.exit(1 if failed or not passed else 0)


if __name__ == "__main__":
    main(sys.argv[1])
