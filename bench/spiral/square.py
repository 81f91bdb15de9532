#!/usr/bin/env python3
"""A square mission for the spiral speed runs: side (m) at ds 20 m, 3 UAVs 30/40/30 % at three corners.
usage: square.py SIDE_M LLOYD_STEPS local|cgal OUT.json"""
import json, math, sys
side, lloyd, method, out = float(sys.argv[1]), int(sys.argv[2]), sys.argv[3], sys.argv[4]
lon0, lat0 = 24.40, 40.93
mx, my = 111320.0 * math.cos(math.radians(lat0)), 110540.0
h = side / 2
ring = [[lon0 + x / mx, lat0 + y / my] for x, y in [(-h, -h), (h, -h), (h, h), (-h, h), (-h, -h)]]
json.dump({"name": f"square {side:.0f} m", "area": {"type": "Polygon", "coordinates": [ring]}, "spacing_m": 20,
           "planner": "spiral", "planner_params": {"lloyd_iterations": lloyd, "lloyd_method": method},
           "uavs": [{"id": "a", "share": 0.3, "start": ring[0]}, {"id": "b", "share": 0.4, "start": ring[1]},
                    {"id": "c", "share": 0.3, "start": ring[2]}], "seed": 1}, open(out, "w"))
