"""The per-region figures of Apostolidis et al. 2022 (bench/data/apostolidis2022/paper_results.csv), read
for bench/paper/table.py and bench/papers/table.py (standard library only)."""
import csv


def read(csv_path, metric_key=lambda metric: metric):
    """{(method, metric_key(metric)): {roi 1..20: value, or None where the method could not plan it}}"""
    paper = {}
    with open(csv_path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    header = rows[0]
    for r in rows[1:]:
        if len(r) < 3:
            continue
        vals = {}
        for k in range(1, 21):
            try:
                vals[k] = float(r[header.index(f"ROI{k}")])
            except ValueError:
                vals[k] = None  # "Χ": the method could not plan that region
        paper[(r[0], metric_key(r[1]))] = vals
    return paper
