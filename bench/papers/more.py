#!/usr/bin/env python3
"""The sections of bench/results/papers.md after Apostolidis's Tables 3-5 and Fig. 9 (bench/papers/run.sh):
Apostolidis Tables 7-10, Mondinelli Tables 5.1-5.9, Hong Tables 1-2 and the field trial, Balampanis
Tables I-IV. Reads the runs' plan.json / evaluation.json / study.json / trajectory CSVs.

usage: more.py WORK "SECTIONS"      (standard library only)
"""
import csv
import glob
import json
import math
import os
import sys

work, sections = sys.argv[1], sys.argv[2].split()
out = []


def load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def para(*lines):
    out.append("")
    out.extend(lines)


def table(head, rows, align=None):
    out.append("")
    out.append("| " + " | ".join(head) + " |")
    out.append("|" + "|".join(align or (["---"] + ["---:"] * (len(head) - 1))) + "|")
    for r in rows:
        out.append("| " + " | ".join(str(c) for c in r) + " |")


# ---- Apostolidis 2022, Tables 7-10 -------------------------------------------------------------------------
PAPER_T7 = {1: (95.28, 74.01, 1, 23.25, 8.00, 0.00, 31.25, 0.40), 2: (95.31, 77.01, 1, 12.70, 11.00, 0.00, 23.70, 0.44),
            3: (95.22, 81.43, 1, 8.48, 14.00, 0.00, 22.48, 0.44), 5: (95.76, 78.39, 1, 5.32, 20.00, 0.00, 25.32, 0.46),
            7: (95.28, 84.96, 1, 4.28, 26.00, 0.00, 30.28, 0.52), 9: (95.30, 84.68, 1, 3.21, 32.00, 0.00, 35.21, 0.50),
            12: (95.62, 86.99, 1, 2.15, 41.00, 0.00, 43.15, 0.44), 15: (95.30, 90.52, 1, 2.15, 50.00, 0.00, 52.15, 0.56)}
PAPER_T8 = {1: (97.66, 83.95, 8, 193.13, 8.00, 55.92, 257.05, 3.93), 2: (97.68, 83.57, 4, 96.50, 11.00, 32.97, 140.47, 4.15),
            3: (97.53, 85.17, 3, 65.07, 14.00, 27.98, 107.05, 4.50), 5: (97.67, 85.64, 2, 39.98, 20.00, 19.99, 79.97, 4.91),
            7: (97.50, 86.44, 2, 28.46, 26.00, 25.99, 80.45, 6.20), 9: (97.86, 88.31, 1, 22.28, 32.00, 0.00, 54.28, 3.45),
            12: (97.68, 88.46, 1, 16.97, 41.00, 0.00, 57.97, 3.51), 15: (97.52, 86.64, 1, 13.78, 50.00, 0.00, 63.78, 3.56)}
PAPER_T9 = {1: 2.88, 2: 2.69, 3: 2.75, 5: 2.73, 7: 2.78, 9: 2.77, 12: 2.96, 15: 2.75}
PAPER_T10 = {1: 16.49, 2: 16.72, 3: 16.19, 5: 16.34, 7: 16.42, 9: 16.08, 12: 16.34, 15: 16.70}


def study_section():
    out.append("")
    out.append("## Apostolidis 2022, Tables 7–10 (the UAV-count study and its compute times)")
    para("The paper's §3.2: ds = 47 m, 60 m altitude, 3 m/s, 25-minute batteries, deployment 5 + 3 min per UAV "
         "(eq. 18), 3 min per battery change and the ROI-sized detour of eq. 19, 0.017228 EUR per minute (eq. 21), "
         "1 to 15 UAVs, the camera's footprint (89.4 m) swept by the evaluator. Our `uavcover study` applies the same eq. 15–22 (c1 = 3 s and c2 = 1 m/s, which the paper "
         "does not give) to our DARP plans (defaults, strict mode), each scored by the one evaluator (1 m lattice). **The testbeds are not published**: the paper gives only their areas, 222 720 m² "
         "(#3) and 1 814 063 m² (#4). The stand-ins are two of the paper's 20 regions scaled about their centroids "
         "until their free areas are those (`bench/papers/missions.py testbed`): region 13 (2 no-fly zones) for "
         "#3, region 11 (1 no-fly zone) for #4, so shapes, and with them turns and batteries, differ. Each cell is the paper's / "
         "ours; the flight time is the longest UAV's (eq. 17), and ours includes each UAV's legs from and back to "
         "its take-off point (drawn from the seed in its share's part of the area), which is why it falls more "
         "slowly than the paper's beyond 9 UAVs.")
    for tb, paper, times in ((3, PAPER_T7, PAPER_T9), (4, PAPER_T8, PAPER_T10)):
        s = load(os.path.join(work, "study", f"testbed{tb}", "study.json"))
        m = load(os.path.join(work, "study", f"testbed{tb}.json"))
        if not s:
            para(f"Testbed #{tb}: no study.json (the run failed).")
            continue
        para(f"**Testbed #{tb}** (Table {7 if tb == 3 else 8}; compute times Table {9 if tb == 3 else 10}), "
             f"stand-in: {m['name'] if m else '?'}. Recommended by ours: {s.get('recommended_uavs')} UAVs; the fewest "
             f"that finish on one battery each: {s.get('min_uavs_single_battery')} (the paper: "
             f"{'3 by total time, 1 battery from 1 UAV' if tb == 3 else '9 by total time and the first on one battery'}).")
        rows = []
        for r in s["rows"]:
            n = r["uavs"]
            p = paper.get(n)
            if "error" in r:
                rows.append([n, "error: " + r["error"]] + [""] * 9)
                continue
            mine = (100 * r["poc"], 100 * r["pooc"], r["batteries_per_uav"], r["flight_time_min"],
                    r["deployment_time_min"], r["change_battery_delay_min"], r["total_time_min"], r["cost_eur"])
            cells = [n]
            for k, v in enumerate(mine):
                pv = "–" if p is None else (f"{p[k]:.0f}" if k == 2 else f"{p[k]:.2f}")
                cells.append(f"{pv} / **{v:.0f}**" if k == 2 else f"{pv} / **{v:.2f}**")
            cells.append(f"{times.get(n, '–')} / **{r['compute_time_s']:.2f}**")
            rows.append(cells)
        table(["UAVs", "PoC %", "PoOC %", "batteries / UAV", "flight time min", "deployment min",
               "battery-change delay min", "total min", "cost EUR", "compute s (paper: overall execution)"], rows)
    para("Compute times: the paper's Java implementation on its own machine (Tables 9–10: 2.79 s and 16.41 s on "
         "average, nearly independent of the UAV count, the grid optimisation taking almost all of it); ours is "
         "the whole `plan()` call on this machine (2 cores, under `nice`), for the stand-ins.")
    para("**The field trials' time estimates are not rerun: their ROIs are not published.** §5.2 (precision "
         "agriculture: 2 UAVs, 18 m, 90 % overlap, ds ≈ 14 m, 2 m/s, 525 images) flew 7.56 min against an estimated "
         "14.6 min for one UAV; §5.3 (search and rescue: 3 UAVs with shares 15/40/45 %, 50 m) flew 8.7 min against "
         "more than 21 min estimated for one. `uavcover study` gives that estimate for any drawn area.")


# ---- Mondinelli 2025 -----------------------------------------------------------------------------------------
def trajectory_end_s(path):
    """The segment-form trajectory CSV's last row is the end of the flight: its t."""
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
        return float(rows[-1]["t"]) if rows else None
    except (OSError, ValueError, KeyError):
        return None


def uav_durations_s(ev):
    """eq. 15 per UAV (seconds) from evaluation.json."""
    try:
        return [60 * u["flight_duration_min"] for u in ev["uavs"]]
    except (KeyError, TypeError):
        return None


def thesis_section():
    out.append("")
    out.append("## Mondinelli 2025, Tables 5.1–5.3 and 5.8–5.9")
    d = os.path.join(work, "thesis", "rectangle")
    pl, ev = load(os.path.join(d, "plan.json")), load(os.path.join(d, "evaluation.json"))
    if not pl or not ev:
        para("The rectangle: no plan (the run failed).")
        return
    para("**The rectangle** (§5.2.1): 200 m north–south × 100 m, 3 UAVs, ds = 10 m, strict mode, equal shares, "
         "seeded random starts inside the field, 3 m/s (`bench/data/mondinelli2025/rectangle_3uav.json`; the "
         "thesis publishes no coordinates, so only the shape and size match). Its trajectories use a mean speed "
         "of 3 m/s with |v| ≤ 5 m/s and |a| ≤ 4 m/s² per axis (polynomials of order 5); ours here is the "
         "`trajectory` export of the same plan (lines at up to 3 m/s, fillet arcs, a_max = 4 m/s²), and eq. 15 "
         "beside it. Length excludes the legs from and to the take-off point, as the thesis's; the flight times "
         "include them, as the thesis's. Table 5.2 is the thesis's DARP (Java), per drone; its drones are named "
         "by colour, ours in the mission's order.")
    thesis = [("red", 681, 262, 18), ("green", 641, 234, 19), ("yellow", 680, 252, 14)]
    eq15 = uav_durations_s(ev) or [None] * len(pl["uavs"])
    rows, tr_total, tr_max = [], 0.0, 0.0
    for k, u in enumerate(pl["uavs"]):
        t = trajectory_end_s(os.path.join(work, "thesis", "rectangle-export", "trajectory", u["id"] + ".csv"))
        th = thesis[k] if k < len(thesis) else ("", "", "", "")
        if t is not None:
            tr_total += t
            tr_max = max(tr_max, t)
        rows.append([u["id"], f"{th[1]} / **{u['coverage_length_m']:.0f}**",
                     f"{th[2]} / **{t:.0f}**" if t is not None else f"{th[2]} / X",
                     f"**{eq15[k]:.0f}**" if eq15[k] is not None else "X", f"{th[3]} / **{u['turns']}**"])
    table(["drone (thesis / ours)", "length m", "flight time s (trajectory)", "flight time s (eq. 15)", "turns"], rows)
    cov = sum(u["coverage_length_m"] for u in pl["uavs"])
    turns = sum(u["turns"] for u in pl["uavs"])
    e_sum = sum(x for x in eq15 if x is not None)
    e_max = max(x for x in eq15 if x is not None)
    para("Table 5.3, on both bases: the thesis sums the flight time over the UAVs; ours (`flight_time_min`, eq. 17) "
         "is the longest UAV's, the mission's duration.")
    table(["planner", "total length m", "total flight time s (sum over UAVs)", "flight time s (longest UAV)",
           "total turns", "compute s"],
          [["POPCORN (thesis)", 1960, 732, "", 116, 7], ["DARP, Java (thesis)", 2002, 748, "", 51, 3],
           ["**ours, DARP: trajectory**", f"**{cov:.0f}**", f"**{tr_total:.0f}**", f"**{tr_max:.0f}**", f"**{turns}**",
            f"**{pl['totals']['compute_time_s']:.2f}**"],
           ["**ours, DARP: eq. 15**", f"**{cov:.0f}**", f"**{e_sum:.0f}**", f"**{e_max:.0f}**", f"**{turns}**", ""]])
    para(f"PoC of our plan: {100 * ev['poc']:.2f} % (the thesis: full coverage, not measured). Our DARP against "
         "POPCORN on this rectangle with every planner is in [compare.md](compare.md).")

    rows = []
    thesis89 = {"strict": [("red", 2760, 60, 40), ("green", 1840, 40, 31)],
                "coverage": [("red", 2920, 59.3, 44), ("green", 2000, 40.7, 31)]}
    poc = {}
    for mode in ("strict", "coverage"):
        d = os.path.join(work, "thesis", f"field6040-{mode}")
        pl, ev = load(os.path.join(d, "plan.json")), load(os.path.join(d, "evaluation.json"))
        if not pl or not ev:
            continue
        poc[mode] = 100 * ev["poc"]
        for k, u in enumerate(pl["uavs"]):
            th = thesis89[mode][k]
            rows.append([f"{'5.8 strictly in poly' if mode == 'strict' else '5.9 better coverage'}", u["id"],
                         f"{th[1]} / **{u['coverage_length_m']:.0f}**", f"{th[2]} / **{100 * u['share_actual']:.1f}**",
                         f"{th[3]} / **{u['turns']}**"])
    if rows:
        para("**The 60/40 field** (§5.3.2, Tables 5.8–5.9): 2 UAVs with shares 60 % and 40 %, ds = 10 m, strict "
             "then coverage mode. **The field is not published** (4.89 ha, \"slightly irregular\"): the stand-in is "
             "a quadrilateral of 4.89 ha (`bench/papers/missions.py thesis-6040`). Real portion is the share of the "
             "free area the UAV's region holds. Each cell: the thesis / ours.")
        table(["table", "drone", "length m", "real portion %", "turns"], rows, ["---", "---", "---:", "---:", "---:"])
        if len(poc) == 2:
            para(f"Coverage: the thesis reports 92 % strictly in poly and 97 % with better coverage (its measure is not "
                 f"given); ours by the one evaluator {poc['strict']:.2f} % and {poc['coverage']:.2f} %.")
    para("**Not rerun, because the thesis does not publish the fields**: Tables 5.4–5.6 (the 7.29 ha complex field "
         "of the Parco Agricolo Sud, POPCORN's 7 paths against DARP's 2) and Table 5.7 (the 9.79 ha field with two "
         "pylons, 3 UAVs). Their measures are the ones above; any field can be compared with `uavcover compare`.")


# ---- Hong 2021 -----------------------------------------------------------------------------------------------
PAPER_T2 = {  # (sides, uavs): (max, avg)
    (3, 2): (180.31, 165.02), (4, 2): (260.69, 237.57), (5, 2): (238.12, 206.39), (6, 2): (260.38, 243.83),
    (3, 3): (143.98, 142.43), (4, 3): (214.42, 171.08), (5, 3): (175.67, 160.13), (6, 3): (202.30, 182.37),
    (3, 4): (140.76, 134.89), (4, 4): (149.73, 138.83), (5, 4): (153.75, 127.43), (6, 4): (170.59, 145.74),
    (3, 5): (137.20, 130.67), (4, 5): (146.77, 137.16), (5, 5): (148.57, 125.96), (6, 5): (143.45, 133.29)}
NAMES = {3: "triangle", 4: "tetragon", 5: "pentagon", 6: "hexagon"}


def hong_distances(pl):
    """Per UAV: the MILP's travel distance (depot -> its waypoints -> depot), the planner's own figure."""
    ds = []
    for u in pl["uavs"]:
        d = u.get("diagnostics", {}).get("distance_m")
        ds.append(d if d is not None else u["length_m"])
    return ds


def hong_section():
    out.append("")
    out.append("## Hong 2021, Tables 1–2 (the joint MILP)")
    para("The paper's §4.1: a polygon, waypoints 5 m apart on back-and-forth lines, depots at (0, 0), (0, 5), "
         "(0, −5), (0, 10), (0, −10) m, the min-max + mean travel-distance MILP (eq. 3–9) solved jointly for all "
         "UAVs (Gurobi, MATLAB, a 2.6 GHz i7). Ours: the `milp` planner with `max_uavs_per_milp` 10, `max_segments` "
         "60, `model: exact` (one node per waypoint, the back-and-forth constraint), no node limit, COIN-OR CBC. "
         "**The polygons' vertices are not published**: the stand-ins are regular polygons of circumradius 22 m "
         "centred 45 m east of the first depot (`bench/papers/missions.py hong`; the pentagon gives 8 lines, the "
         "paper's 16 waypoints and 19 nodes), so distances compare in size, not exactly.")
    p = load(os.path.join(work, "hong", "p5u3", "plan.json"))
    if p:
        ds = hong_distances(p)
        cl = (p.get("planner_diagnostics", {}).get("clusters") or [{}])[0]
        wp = [u.get("diagnostics", {}).get("sequence") for u in p["uavs"]]
        rows = []
        paper1 = [(4, 143.86), (4, 154.96), (8, 214.42)]
        for k, u in enumerate(p["uavs"]):
            n = sum(1 for _ in (wp[k] or []))
            rows.append([u["id"], f"{paper1[k][0]} / **{2 * len(u.get('diagnostics', {}).get('legs', [])) or n}**",
                         f"{paper1[k][1]:.2f} / **{ds[k]:.2f}**"])
        para("**Table 1** (the pentagon, 3 UAVs; each cell the paper / ours):")
        table(["UAV", "waypoints", "travel distance m"], rows)
        para(f"Average travel distance: the paper 171.08 m, ours **{sum(ds) / len(ds):.2f} m**; the MILP: "
             f"{cl.get('nodes', '?')} nodes, {cl.get('variables', '?')} variables ({cl.get('binaries', '?')} binary), "
             f"{cl.get('rows', '?')} rows (the paper: 19 nodes, 1103 variables), status {cl.get('status', '?')}, "
             f"gap {cl.get('gap', '?')}; solved in **{p['totals']['compute_time_s']:.2f} s** for the whole plan "
             "(the paper: 0.80 s for the optimisation).")
    rows = []
    for uavs in (2, 3, 4, 5):
        cells = [f"{uavs} UAVs"]
        for sides in (3, 4, 5, 6):
            pl = load(os.path.join(work, "hong", f"p{sides}u{uavs}", "plan.json"))
            pm, pa = PAPER_T2[(sides, uavs)]
            if not pl:
                cells.append(f"{pm:.0f} / X, {pa:.0f} / X")
                continue
            ds = hong_distances(pl)
            cells.append(f"{pm:.0f} / **{max(ds):.0f}**, {pa:.0f} / **{sum(ds) / len(ds):.0f}**"
                         + ("" if pl.get("complete", True) else " (time limit)"))
        rows.append(cells)
    para("**Table 2**: maximum, average travel distance in metres (the paper / ours):")
    table(["UAVs"] + [NAMES[s] for s in (3, 4, 5, 6)], rows)
    times = []
    for f in sorted(glob.glob(os.path.join(work, "hong", "p*u*", "plan.json"))):
        pl = load(f)
        if pl:
            times.append(pl["totals"]["compute_time_s"])
    if times:
        para(f"Compute: {min(times):.2f}–{max(times):.2f} s per plan over the 16 cases (CBC, 2 cores, under `nice`).")
    para("**The field trial's planned distances** (§5: two hexacopters, three areas, 28 nodes, 306.96 m and "
         "306.43 m, objective 613.65): the three areas' coordinates are not published, so they are not rerun here; "
         "`bench/milp/run.sh` solves a 28-node, 3-area, 2-UAV stand-in ([milp.md](milp.md)).")


# ---- Balampanis 2017 -----------------------------------------------------------------------------------------
def path_metrics(paths_geojson):
    """Total path (m), min / max step between consecutive waypoints, min / max angle at a waypoint (180 =
    straight on), over the coverage paths of every UAV, in a local equirectangular frame."""
    g = load(paths_geojson)
    if not g:
        return None
    total, steps, angles = 0.0, [], []
    for f in g["features"]:
        if f["properties"].get("kind") != "coverage":
            continue
        pts = f["geometry"]["coordinates"]
        lat0 = math.radians(pts[0][1])
        xy = [(lon * 111320.0 * math.cos(lat0), lat * 110540.0) for lon, lat in pts]
        for a, b in zip(xy, xy[1:]):
            d = math.hypot(b[0] - a[0], b[1] - a[1])
            if d > 1e-6:
                steps.append(d)
                total += d
        for a, b, c in zip(xy, xy[1:], xy[2:]):
            ux, uy, vx, vy = a[0] - b[0], a[1] - b[1], c[0] - b[0], c[1] - b[1]
            if math.hypot(ux, uy) > 1e-6 and math.hypot(vx, vy) > 1e-6:
                angles.append(math.degrees(math.atan2(abs(ux * vy - uy * vx), ux * vx + uy * vy)))
    if not steps:
        return None
    return total, min(steps), max(steps), min(angles), max(angles), sum(angles) / len(angles)


def spiral_section():
    out.append("")
    out.append("## Balampanis 2017, Tables I–IV (valley sensitivity and Lloyd steps)")
    para("The paper's areas (Fig. 6's test area, the Abaco coast of Fig. 1) are not published. The stand-in is a "
         "coastal bay like the paper's (`bench/spiral/coastline.py` at radius 100 m, about 500 triangles, a path of the paper's length: inlets, two islands, 3 UAVs "
         "with the paper's Fig. 1 shares 30/40/30 %, ds 20 m), planned by our `spiral` planner with its "
         "`valley_sensitivity` (S_s) and `lloyd_iterations` set as in the paper's tables. The metrics are the "
         "paper's: the total path, the shortest and longest step between consecutive waypoints, and the smallest "
         "and largest angle at a waypoint (180 = straight on), over the coverage paths of the 3 UAVs; the mean "
         "angle beside them.")
    runs = {}
    for d in glob.glob(os.path.join(work, "spiral", "v*-l*")):
        if not os.path.isdir(d):
            continue
        name = os.path.basename(d)
        s, l = name[1:].split("-l")
        runs[(float(s), int(l))] = (path_metrics(os.path.join(d, "paths.geojson")), load(os.path.join(d, "plan.json")))

    def rows_for(keys):
        rows = []
        for k in keys:
            if k not in runs or not runs[k][0]:
                continue
            t, smin, smax, amin, amax, amean = runs[k][0]
            rows.append([f"{k[0]:g}", k[1], f"**{t:.0f}**", f"**{smin:.2f}**", f"**{smax:.2f}**", f"**{amin:.2f}**",
                         f"**{amax:.2f}**", f"{amean:.1f}"])
        return rows

    head = ["S_s", "Lloyd", "total path m", "min distance m", "max distance m", "min angle deg", "max angle deg",
            "mean angle deg"]
    para("**Tables I and III** (the paper, Table I, S_s 2 / 4: total 7139.51 / 8515.79 m, min distance 9.87 / 10.63 m, "
         "max 226.51 / 191.72 m, min angle 20.60 / 5.09°, max 179.89 / 179.99°; Table III on the Abaco coast, S_s "
         "2 / 3 / 5: total 3807.88 / 4185.54 / 4344.05 m, min distance 12.90 m each, max 216.87 / 127.52 / "
         "118.24 m, min angle 11.56 / 11.69 / 0.85°, max 179.67 / 179.67 / 179.91°). The paper finds a larger S_s "
         "gives a longer path with wider angles; ours:")
    table(head, rows_for([(2.0, 10), (3.0, 10), (4.0, 10), (5.0, 10), (6.0, 10)]))
    ends = [runs.get((2.0, 10)), runs.get((6.0, 10))]
    if all(e and e[0] for e in ends):
        a, b = ends[0][0], ends[1][0]
        para(f"From S_s 2 to 6 our total path goes from {a[0]:.0f} m to {b[0]:.0f} m "
             f"({'longer, as the paper finds' if b[0] > a[0] else 'shorter, unlike the paper'}) and the mean angle "
             f"from {a[5]:.1f}° to {b[5]:.1f}° ({'wider, as the paper finds' if b[5] > a[5] else 'not wider'}). A "
             "smallest angle of 0° is a turn straight back at a waypoint (a spiral level that ends in a dead end); "
             "the shortest steps are between centroids of the small triangles the mesh refines along the coast.")
    para("**Table II** (the paper's current algorithm at S_s 6, Lloyd 10 / 30 / 60: total 6958.26 / 7144.34 / "
         "7098.88 m, min distance 10.41 / 12.99 / 12.99 m, max 144.13 / 174.32 / 94.11 m; the previous algorithm "
         "of its ref. [12] is not ours to rerun):")
    table(head, rows_for([(6.0, 10), (6.0, 30), (6.0, 60)]))
    rows = []
    paper4 = {10: 0.2, 60: 0.86, 100: 1.008}
    for l in (10, 60, 100):
        k = (2.0, l)
        if k not in runs or not runs[k][1]:
            continue
        mesh = runs[k][1].get("planner_diagnostics", {}).get("mesh", {})
        rows.append([l, paper4[l], f"**{mesh.get('lloyd_s', float('nan')):.3f}**",
                     f"{mesh.get('lloyd_cpu_s', float('nan')):.3f}", mesh.get("triangles", "")])
    para("**Table IV** (Lloyd time in seconds for the whole area; the paper also times each UAS's configuration "
         "space, 0.064–0.6 s: our spiral meshes the whole area once and partitions that mesh, so a UAV has a mesh "
         "of its own only with its own camera):")
    table(["Lloyd steps", "paper s (all)", "ours s", "ours CPU s", "triangles"], rows)


for name, fn in (("study", study_section), ("thesis", thesis_section), ("hong", hong_section),
                 ("spiral", spiral_section)):
    if name in sections:
        fn()
print("\n".join(out))
