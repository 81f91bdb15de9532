#!/usr/bin/env python3
"""Writes a coastline-like mission: a bay with many inlets (radius 600 m +- 40 %) and two islands,
3 UAVs with the paper's Fig. 1 shares 30/40/30 %, ds 20 m. Deterministic (no randomness).
usage: coastline.py OUT.json [PLANNER] [SPACING_M] [RADIUS_M]"""
import json, math, sys

out = sys.argv[1]
planner = sys.argv[2] if len(sys.argv) > 2 else "spiral"
ds = float(sys.argv[3]) if len(sys.argv) > 3 else 20.0
radius = float(sys.argv[4]) if len(sys.argv) > 4 else 600.0
lon0, lat0 = 24.40, 40.93
mx, my = 111320.0 * math.cos(math.radians(lat0)), 110540.0


def ll(x, y):
    return [round(lon0 + x / mx, 8), round(lat0 + y / my, 8)]


def ring(cx, cy, r, terms, n):
    pts = []
    for i in range(n):
        t = 2 * math.pi * i / n
        f = 1 + sum(a * math.sin(k * t + p) for a, k, p in terms)
        pts.append(ll(cx + r * f * math.cos(t), cy + r * f * math.sin(t)))
    pts.append(pts[0])
    return pts


outer = ring(0, 0, radius, [(0.22, 5, 0.0), (0.12, 13, 1.0), (0.06, 29, 2.0)], 240)
islands = [ring(0.25 * radius, 0.1 * radius, 0.12 * radius, [(0.2, 3, 0.5)], 24),
           ring(-0.3 * radius, -0.25 * radius, 0.08 * radius, [(0.25, 4, 0.2)], 24)]
mission = {
    "name": f"coastline-like bay, radius {radius:.0f} m",
    "area": {"type": "Polygon", "coordinates": [outer] + [list(reversed(i)) for i in islands]},
    "spacing_m": ds,
    "planner": planner,
    "uavs": [{"id": "a", "share": 0.3, "start": ll(-radius, 0)},
             {"id": "b", "share": 0.4, "start": ll(0, -radius)},
             {"id": "c", "share": 0.3, "start": ll(radius, 0)}],
    "seed": 1,
}
json.dump(mission, open(out, "w"), indent=1)
