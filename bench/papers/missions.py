#!/usr/bin/env python3
"""Stand-in missions for the papers' tables whose inputs are not published (bench/papers/run.sh).

usage: missions.py testbed ROI.json AREA_M2 OUT.json       the ROI scaled about its centroid to AREA_M2,
                                                           the paper's multi-robot settings (§3.2)
       missions.py hong SIDES UAVS OUT.json                 a regular polygon of SIDES vertices (Hong §4.1)
       missions.py thesis-6040 MODE OUT.json                a 4.89 ha slightly irregular field, 2 UAVs 60/40
Deterministic: no randomness but the missions' seeds. Standard library only.
"""
import json
import math
import sys

LON0, LAT0 = 9.0, 45.0  # Hong's and the thesis's stand-ins: a flat field south of Milan
MX, MY = 111320.0 * math.cos(math.radians(LAT0)), 110540.0


def ll(x, y):
    """Local metres (x east, y north) from (LON0, LAT0) to [lon, lat]."""
    return [round(LON0 + x / MX, 9), round(LAT0 + y / MY, 9)]


def ring_area_m2(ring):
    """Shoelace area of a [lon, lat] ring in an equirectangular frame at its mean latitude."""
    lat = sum(p[1] for p in ring) / len(ring)
    kx = math.radians(1) * 6371008.8 * math.cos(math.radians(lat))
    ky = math.radians(1) * 6371008.8
    xy = [(p[0] * kx, p[1] * ky) for p in ring]
    return abs(sum(xy[i][0] * xy[i - 1][1] - xy[i - 1][0] * xy[i][1] for i in range(len(xy)))) / 2


def testbed(roi, area, out):
    """Apostolidis §3.2: ds 47 m, 60 m altitude, a 73.4 degree HFOV, 3 m/s, 25 min batteries; the ROI and its no-fly zones
    scaled about the outer ring's centroid so that the free area (the outer ring less the no-fly zones,
    which lie inside it apart) is AREA_M2."""
    m = json.load(open(roi))
    outer = m["area"]["coordinates"][0]
    free = ring_area_m2(outer) - sum(ring_area_m2(z["coordinates"][0]) for z in m["no_fly_zones"])
    s = math.sqrt(float(area) / free)
    cx = sum(p[0] for p in outer[:-1]) / (len(outer) - 1)
    cy = sum(p[1] for p in outer[:-1]) / (len(outer) - 1)

    def scale(rings):
        return [[[round(cx + (p[0] - cx) * s, 10), round(cy + (p[1] - cy) * s, 10)] for p in r] for r in rings]

    m["area"]["coordinates"] = scale(m["area"]["coordinates"])
    m["no_fly_zones"] = [dict(z, coordinates=scale(z["coordinates"])) for z in m["no_fly_zones"]]
    m["name"] = f"stand-in for a testbed of {float(area):.0f} m2 ({roi.split('/')[-1]} scaled by {s:.4f})"
    # the RGB camera of all UAVs: 73.4 degrees HFOV at 60 m, the overlap po that gives ds = 47 m
    # (ds = (2 - po) h tan(HFOV / 2), eq. 13); the evaluator sweeps the camera's footprint, 89.4 m
    half = 60 * math.tan(math.radians(73.4 / 2))
    m.pop("spacing_m", None)
    m["camera"] = {"altitude_m": 60, "hfov_deg": 73.4, "overlap": round(2 - 47 / half, 6)}
    m["uavs"] = [{"speed_mps": 3, "endurance_min": 25}]
    json.dump(m, open(out, "w"), indent=1)


def hong(sides, uavs, out):
    """Hong §4.1: a regular polygon (circumradius 22 m, centre 45 m east of the first depot, a vertex
    pointing east), lines 5 m apart; depots at (0, 0), (0, 5), (0, -5), (0, 10), (0, -10) m; the paper's
    joint MILP (every UAV in one model, every line, no node limit but the time limit)."""
    sides, uavs = int(sides), int(uavs)
    ring = [ll(45 + 22 * math.cos(2 * math.pi * k / sides), 22 * math.sin(2 * math.pi * k / sides))
            for k in range(sides)]
    ring.append(ring[0])
    depots = [(0, 0), (0, 5), (0, -5), (0, 10), (0, -10)][:uavs]
    m = {"name": f"Hong 2021 stand-in: {sides}-gon, {uavs} UAVs", "area": {"type": "Polygon", "coordinates": [ring]},
         "no_fly_zones": [], "spacing_m": 5, "mode": "strict", "planner": "milp", "seed": 1,
         "planner_params": {"max_uavs_per_milp": 10, "max_segments": 60, "node_limit": 10000000, "model": "exact",
                            "time_limit_s": 30},
         "uavs": [{"id": f"UAV{i + 1}", "start": ll(*d)} for i, d in enumerate(depots)]}
    json.dump(m, open(out, "w"), indent=1)


def thesis_6040(mode, out):
    """Mondinelli §5.3.2: a single field of 4.89 ha with a slightly irregular geometry (not published):
    here a quadrilateral of 4.89 ha, 2 UAVs with shares 60/40, ds 10 m, seeded random starts."""
    pts = [(0, 0), (260, -12), (245, 190), (-8, 176)]
    a = abs(sum(pts[i][0] * pts[i - 1][1] - pts[i - 1][0] * pts[i][1] for i in range(4))) / 2
    k = math.sqrt(48900 / a)
    ring = [ll(x * k, y * k) for x, y in pts]
    ring.append(ring[0])
    m = {"name": f"Mondinelli 2025 Table 5.8-5.9 stand-in ({mode})", "area": {"type": "Polygon", "coordinates": [ring]},
         "no_fly_zones": [], "spacing_m": 10, "mode": mode, "planner": "darp", "seed": 1,
         "uavs": [{"id": "red", "share": 0.6, "speed_mps": 3}, {"id": "green", "share": 0.4, "speed_mps": 3}]}
    json.dump(m, open(out, "w"), indent=1)


if __name__ == "__main__":
    what, args = sys.argv[1], sys.argv[2:]
    {"testbed": testbed, "hong": hong, "thesis-6040": thesis_6040}[what](*args)
