#!/usr/bin/env python3
"""Writes 40 random domains with lines that reach the boundary or each other
(a partition, an edge crack, a T-junction, two lines meeting inside; ends
written with six decimals) to the folder given, for the outside judge:
    python3 tests/partitions/make_random_set.py /tmp/randparts
    ../shared/bench/judge --set /tmp/randparts"""
import json, os, random, sys

out = sys.argv[1]
os.makedirs(out, exist_ok=True)
random.seed(7)

def pt_on(poly, k, t):
    a = poly[k]; b = poly[(k + 1) % len(poly)]
    return [round(a[0] + (b[0] - a[0]) * t, 6), round(a[1] + (b[1] - a[1]) * t, 6)]

for i in range(40):
    w = random.uniform(3, 6); h = random.uniform(2, 4)
    poly = [[0, 0], [w, 0], [w, h], [0, h]]
    if random.random() < 0.5:
        poly = [[0, 0], [w, 0], [w, h * 0.6], [w * 0.6, h], [0, h]]
    n = len(poly)
    lines = []
    kind = random.choice(['partition', 'crack', 'tee', 'two'])
    k1 = random.randrange(n); k2 = (k1 + random.randrange(1, n)) % n
    p = pt_on(poly, k1, random.uniform(0.25, 0.75)); q = pt_on(poly, k2, random.uniform(0.25, 0.75))
    if kind == 'partition':
        lines.append({"points": [p, q]})
    elif kind == 'crack':
        m = [round((p[0] + w / 2) / 2, 6), round((p[1] + h / 2) / 2, 6)]
        lines.append({"points": [p, m], "crack": True})
    elif kind == 'tee':
        lines.append({"points": [p, q]})
        mid = [round((p[0] + q[0]) / 2, 6), round((p[1] + q[1]) / 2, 6)]
        k3 = random.choice([k for k in range(n) if k not in (k1, k2)] or [k1])
        lines.append({"points": [mid, pt_on(poly, k3, random.uniform(0.3, 0.7))]})
    else:
        c = [round(w * random.uniform(0.35, 0.65), 6), round(h * random.uniform(0.35, 0.55), 6)]
        lines.append({"points": [p, c]}); lines.append({"points": [c, q]})
    d = {"name": f"r{i}-{kind}", "size": round(random.uniform(0.15, 0.3), 3), "outer": {"points": poly}, "lines": lines}
    json.dump(d, open(os.path.join(out, f"r{i:02d}.json"), "w"))
