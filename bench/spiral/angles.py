"""Turn-angle distribution at the coverage waypoints of planned missions (the paper's Tables I-III measure):
usage: angles.py LABEL@DIR[,DIR...] ...  (each DIR holds a plan's paths.geojson). Prints a markdown table:
per label the share of waypoint angles in 30-degree bins (180 = straight on), the mean angle and the count
of reversals (angle under 45 degrees), summed over the DIRs. Coordinates are WGS84; angles are taken in a
local equirectangular frame (exact enough at region scale)."""
import json, math, sys

print("| plans | waypoints | 0-30 | 30-60 | 60-90 | 90-120 | 120-150 | 150-180 | mean deg | under 45 deg |")
print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
for arg in sys.argv[1:]:
    label, dirs = arg.split("@", 1)
    bins, angles, under45, waypoints = [0] * 6, [], 0, 0
    for d in dirs.split(","):
        for f in json.load(open(f"{d}/paths.geojson"))["features"]:
            if f["properties"].get("kind") != "coverage":
                continue
            pts = f["geometry"]["coordinates"]
            lat0 = math.radians(pts[0][1])
            xy = [(lon * 111320.0 * math.cos(lat0), lat * 110540.0) for lon, lat in pts]
            waypoints += len(xy)
            for a, b, c in zip(xy, xy[1:], xy[2:]):
                ux, uy, vx, vy = a[0] - b[0], a[1] - b[1], c[0] - b[0], c[1] - b[1]
                deg = math.degrees(math.atan2(abs(ux * vy - uy * vx), ux * vx + uy * vy))
                angles.append(deg)
                bins[min(5, int(deg // 30))] += 1
                under45 += deg < 45
    n = max(1, len(angles))
    print(f"| {label} | {waypoints} | " + " | ".join(f"{100 * b / n:.1f} %" for b in bins)
          + f" | {sum(angles) / n:.1f} | {under45} |")
