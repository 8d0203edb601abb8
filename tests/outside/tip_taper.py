#!/usr/bin/env python3
"""The smallest taper one quadrilateral can have at a sharp input corner (a tip).

usage (the judge's venv has scipy):
    /tmp/venv/bin/python tests/outside/tip_taper.py [--angles 6,7,7.5,8,8.5,9,10]

At a tip of t degrees the element A B C D has its corner A at the tip and its sides A-B and A-D
along the boundary. The judge asks every corner to be within [min(45, sharpest input corner) - 0.5,
135.5] and the taper (the larger ratio of two opposite edges) to be at most 10. The search
(Nelder-Mead from a grid of starts, deterministic) moves B along one side, D along the other and C
anywhere, and reports the smallest taper with B, C and D at most 135 degrees. It does so twice:
C free, and C shared by three elements in all (the element at the tip and two others, each at
most 135 at C, so C is at least 90), the way the rules close a tip (a kite whose far corner
the next row takes in two elements).
Last line: 'no quad within taper 10 at T deg or under (C free), at U deg or under (C in three
elements)', T and U the largest angles tried that have none."""
import argparse

import numpy as np
from scipy.optimize import minimize

UPPER, TAPER = 135.0, 10.0


def corners(p):
    nxt, prv = np.roll(p, -1, 0), np.roll(p, 1, 0)
    a, b = nxt - p, prv - p
    g = np.degrees(np.arctan2(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], (a * b).sum(1)))
    return np.where(g < 0, 360 + g, g)


def quad(z, tip):
    d, cx, cy = z
    t = np.radians(tip)
    return np.array([[0.0, 0.0], [1.0, 0.0], [cx, cy], [d * np.cos(t), d * np.sin(t)]])


def cost(z, tip, least_c):
    p = quad(z, tip)
    g = corners(p)
    e = np.linalg.norm(np.roll(p, -1, 0) - p, axis=1)
    taper = max(e[0] / e[2], e[2] / e[0], e[1] / e[3], e[3] / e[1])
    # corners past the window, and C under what its other elements leave it
    past = np.maximum(g[1:] - UPPER, 0).sum() + np.maximum(tip - 0.5 - g[1:], 0).sum()
    past += max(least_c - g[2], 0)
    return taper + 10 * past


def best_taper(tip, least_c):
    best = np.inf
    for d in (0.6, 0.8, 1.0, 1.3):
        for cx in (0.8, 1.0, 1.2):
            r = minimize(cost, [d, cx, 0.1], args=(tip, least_c), method="Nelder-Mead",
                         options=dict(maxiter=5000, xatol=1e-10, fatol=1e-10))
            best = min(best, r.fun)
    return best


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--angles", default="6,7,7.5,8,8.5,9,10")
    a = ap.parse_args()
    tips = [float(x) for x in a.angles.split(",")]
    print("tip (deg) | best taper, C free | best taper, C in three elements")
    under_free = under_three = None
    for tip in tips:
        free, three = best_taper(tip, 0.0), best_taper(tip, 360.0 - 2 * UPPER)
        print(f"{tip:g} | {free:.2f} | {three:.2f}")
        if free > TAPER:
            under_free = tip
        if three > TAPER:
            under_three = tip
    words = lambda t: f"{t:g} deg" if t is not None else "the angles tried"
    print(f"no quad within taper 10 at {words(under_free)} or under (C free), "
          f"at {words(under_three)} or under (C in three elements)")


if __name__ == "__main__":
    main()
