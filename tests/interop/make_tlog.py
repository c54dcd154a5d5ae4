"""Writes a MAVLink telemetry log (.tlog) of a plan flown up to a cut, with pymavlink, as a
ground station records an ArduPilot flight: heartbeats, positions (GLOBAL_POSITION_INT) every
2 m with GPS-like noise, the camera's feedback (CAMERA_FEEDBACK) at the plan's photos flown,
the battery (SYS_STATUS), then the way home after the stop.

usage: make_tlog.py PLAN.geojson OUT.tlog --seq N --fraction F [--noise M] [--seed S]
       [--vehicle quad|plane] [--offset-seq N --offset-m M] [--shift-m M] [--truncate]
       [--no-position] [--no-photos]
"""
import argparse
import json
import math
import random
import struct

from pymavlink.dialects.v20 import ardupilotmega as mavlink

EARTH_M_PER_DEG = 111_320.0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("plan")
    ap.add_argument("out")
    ap.add_argument("--seq", type=int, required=True)
    ap.add_argument("--fraction", type=float, required=True)
    ap.add_argument("--noise", type=float, default=0.5)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--vehicle", default="quad")
    ap.add_argument("--offset-seq", type=int)
    ap.add_argument("--offset-m", type=float, default=0.0)
    ap.add_argument("--shift-m", type=float, default=0.0)
    ap.add_argument("--truncate", action="store_true")
    ap.add_argument("--no-position", action="store_true")
    ap.add_argument("--no-photos", action="store_true")
    a = ap.parse_args()
    rng = random.Random(a.seed)
    fc = json.load(open(a.plan))
    pieces = [f for f in fc["features"] if f["properties"].get("kind") in ("sweep", "turn", "transit") and f["geometry"]["type"] == "LineString"]
    photos = next((f["geometry"]["coordinates"] for f in fc["features"] if f["properties"].get("kind") == "photos"), [])
    lon0, lat0 = pieces[0]["geometry"]["coordinates"][0][:2]
    kx = EARTH_M_PER_DEG * math.cos(math.radians(lat0))

    def local(p):
        return ((p[0] - lon0) * kx, (p[1] - lat0) * EARTH_M_PER_DEG)

    def wgs(x, y):
        return (lon0 + (x + a.shift_m) / kx, lat0 + y / EARTH_M_PER_DEG)

    # the flown path: every piece before the cut, the cut piece up to its fraction
    flown = []  # (x, y, is_sweep, seq)
    for f in pieces:
        seq = f["properties"]["seq"]
        pts = [local(p) for p in f["geometry"]["coordinates"]]
        shift = (0.0, 0.0)
        if seq == a.offset_seq:
            (x0, y0), (x1, y1) = pts[0], pts[-1]
            n = math.hypot(x1 - x0, y1 - y0) or 1.0
            shift = (-(y1 - y0) / n * a.offset_m, (x1 - x0) / n * a.offset_m)
            pts = [(x + shift[0], y + shift[1]) for x, y in pts]
        if seq == a.seq:
            total = sum(math.dist(p, q) for p, q in zip(pts, pts[1:]))
            want, walked, cut = a.fraction * total, 0.0, [pts[0]]
            for p, q in zip(pts, pts[1:]):
                step = math.dist(p, q)
                if walked + step >= want:
                    t = (want - walked) / step if step > 0 else 0.0
                    cut.append((p[0] + (q[0] - p[0]) * t, p[1] + (q[1] - p[1]) * t))
                    break
                walked += step
                cut.append(q)
            pts = cut
        flown.append((pts, f["properties"]["kind"] == "sweep", shift))
        if seq == a.seq:
            break
    else:
        raise SystemExit(f"no piece with seq {a.seq}")

    # the sweep segments flown, and the photos lying on them (a photo on no segment flown lies
    # beyond the stop)
    segments = [(p, q, shift) for pts, sweep, shift in flown if sweep for p, q in zip(pts, pts[1:])]
    shots_on = {}
    for r in (local(p) for p in photos):
        for p, q, shift in segments:
            # matched on the line as planned, taken where it was flown
            r0 = (r[0] + shift[0], r[1] + shift[1])
            d = (q[0] - p[0], q[1] - p[1])
            l2 = d[0] ** 2 + d[1] ** 2
            if l2 == 0:
                continue
            t = ((r0[0] - p[0]) * d[0] + (r0[1] - p[1]) * d[1]) / l2
            off = abs((r0[0] - p[0]) * d[1] - (r0[1] - p[1]) * d[0]) / math.sqrt(l2)
            if off <= 0.5 and -1e-6 <= t <= 1 + 1e-6:
                shots_on.setdefault((p, q), []).append((t, (p[0] + d[0] * t, p[1] + d[1] * t)))
                break
    # positions every 2 m, each photo where the track passes it: ("pos" | "shot", x, y)
    events = []
    for pts, sweep, _ in flown:
        for p, q in zip(pts, pts[1:]):
            n = max(1, int(math.dist(p, q) / 2.0))
            shots = sorted(shots_on.get((p, q), []))
            for i in range(n):
                events.append(("pos", p[0] + (q[0] - p[0]) * i / n, p[1] + (q[1] - p[1]) * i / n))
                while shots and shots[0][0] <= (i + 1) / n:
                    events.append(("shot", *shots.pop(0)[1]))
    stop = flown[-1][0][-1]
    # the way home after the stop (return to launch)
    home = local(pieces[0]["geometry"]["coordinates"][0])
    n = max(1, int(math.dist(stop, home) / 2.0))
    events.append(("rtl", 0, 0))
    events += [("pos", stop[0] + (home[0] - stop[0]) * i / n, stop[1] + (home[1] - stop[1]) * i / n) for i in range(n + 1)]

    mav = mavlink.MAVLink(None, srcSystem=1, srcComponent=1)
    gcs = mavlink.MAVLink(None, srcSystem=255, srcComponent=190)
    out = open(a.out, "wb")
    t_us = 1_700_000_000_000_000

    def write(link, msg):
        nonlocal t_us
        t_us += 100_000
        out.write(struct.pack(">Q", t_us) + msg.pack(link))

    mav_type = mavlink.MAV_TYPE_FIXED_WING if a.vehicle == "plane" else mavlink.MAV_TYPE_QUADROTOR
    positions = sum(1 for e in events if e[0] == "pos")
    i = taken = 0
    mode = 10 if a.vehicle == "plane" else 3  # ArduPilot's AUTO

    def heartbeat():
        write(mav, mavlink.MAVLink_heartbeat_message(mav_type, mavlink.MAV_AUTOPILOT_ARDUPILOTMEGA, mavlink.MAV_MODE_FLAG_CUSTOM_MODE_ENABLED, mode, 4, 3))

    for kind, x, y in events:
        if kind == "rtl":
            mode = 11 if a.vehicle == "plane" else 6  # RTL, the camera still triggering
            heartbeat()
            continue
        if kind == "shot":
            if not a.no_photos:
                plon, plat = wgs(x + rng.gauss(0, a.noise), y + rng.gauss(0, a.noise))
                write(mav, mavlink.MAVLink_camera_feedback_message(i * 100_000, 1, 0, taken, int(plat * 1e7), int(plon * 1e7), 60.0, 60.0, 0, 0, 0, 0, 0))
                taken += 1
            continue
        if i % 10 == 0:
            write(gcs, mavlink.MAVLink_heartbeat_message(mavlink.MAV_TYPE_GCS, mavlink.MAV_AUTOPILOT_INVALID, 0, 0, 0, 3))
            heartbeat()
            battery = max(5, 100 - i * 60 // positions)
            write(mav, mavlink.MAVLink_sys_status_message(0, 0, 0, 500, 15000, 2000, battery, 0, 0, 0, 0, 0, 0))
        lon, lat = wgs(x + rng.gauss(0, a.noise), y + rng.gauss(0, a.noise))
        if not a.no_position:
            write(mav, mavlink.MAVLink_global_position_int_message(i * 100, int(lat * 1e7), int(lon * 1e7), 60_000, 60_000, 0, 0, 0, 0))
        i += 1
    out.close()
    if a.truncate:
        data = open(a.out, "rb").read()
        open(a.out, "wb").write(data[: len(data) - 7])
    print(json.dumps({"positions": positions, "photos": taken, "planned_photos": len(photos)}))


if __name__ == "__main__":
    main()
