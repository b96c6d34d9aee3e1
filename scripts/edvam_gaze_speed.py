#!/usr/bin/env python3
"""World-gaze speed distribution of an EDVAM log (../shared/data/traces/edvam-gaze), for the saccade
threshold of acuity/saccade.c (docs/gaze.md "Measurements"). Not part of the build or the tests.

Gaze in the world = normalise(L - C) (point of gaze minus camera position, both rounded to 0.1 in
the file); speed = the angle between consecutive samples (atan2 of |a x b| and a.b) over their time
step. Printed for all steps and for steps whose two samples have confidence >= 0.8; percentiles by
linear interpolation. Usage: scripts/edvam_gaze_speed.py FILE...
"""
import csv
import math
import sys


def pct(values, p):
    v = sorted(values)
    k = (len(v) - 1) * p
    f = math.floor(k)
    c = min(f + 1, len(v) - 1)
    return v[f] + (v[c] - v[f]) * (k - f)


def unit(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v] if n > 0 else None


def angle_deg(a, b):
    c = (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
    return math.degrees(math.atan2(math.sqrt(sum(x * x for x in c)), sum(x * y for x, y in zip(a, b))))


for path in sys.argv[1:]:
    rows = list(csv.reader(open(path, newline="")))[1:]
    t = [float(r[1]) for r in rows]
    conf = [float(r[11]) for r in rows]
    gaze = [unit([float(r[2 + i]) - float(r[5 + i]) for i in range(3)]) for r in rows]
    dist = [math.dist([float(r[2 + i]) for i in range(3)], [float(r[5 + i]) for i in range(3)]) for r in rows]
    every, confident = [], []
    for i in range(1, len(rows)):
        if gaze[i] is None or gaze[i - 1] is None or t[i] <= t[i - 1]:
            continue
        s = angle_deg(gaze[i - 1], gaze[i]) / (t[i] - t[i - 1])
        every.append(s)
        if conf[i] >= 0.8 and conf[i - 1] >= 0.8:
            confident.append(s)
    print("%s: %d steps; gaze distance median %.2f, p5 %.2f" % (path.split("/")[-1], len(every), pct(dist, 0.5),
                                                              pct(dist, 0.05)))
    for name, a in (("all steps", every), ("confidence >= 0.8", confident)):
        print("  %-18s" % name, " ".join("p%g %.1f" % (100 * p, pct(a, p)) for p in (0.5, 0.75, 0.9, 0.95, 0.99)),
              "max %.1f;" % max(a), " ".join("> %d: %.1f %%" % (th, 100.0 * sum(x > th for x in a) / len(a))
                                             for th in (30, 50, 100, 200)))
