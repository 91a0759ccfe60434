#!/usr/bin/env python3
"""Time each renderer needs to reach given relMSE levels, from bench CSVs.

    python tests/reference/time_to_error.py A.csv B.csv ... [--targets 1e-2,1e-3]

Reads rows `renderer,estimator,spp,seconds,rmse,relmse` (mitsuba_bench.py,
lumiere_sweep.py), groups them by (renderer, estimator), and for each target
interpolates the time linearly in log(seconds)-log(relMSE) between the two
measured renders that bracket it (extrapolating from the last two, marked
`~`, if none does). The first group is the baseline of the ratio column.
"""

import argparse
import csv
import math
import sys


def time_to(rows, target):
    """(seconds, extrapolated) at which relMSE reaches target, log-log."""
    pts = sorted((r["seconds"], r["relmse"]) for r in rows)
    for (t0, e0), (t1, e1) in zip(pts, pts[1:]):
        if e0 >= target >= e1 and e0 != e1:
            f = (math.log(target) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(t0) + f * (math.log(t1) - math.log(t0))), False
    if pts and pts[0][1] <= target:
        return None, False  # already below at the first point: measure smaller spp
    if len(pts) < 2:
        return None, True
    (t0, e0), (t1, e1) = pts[-2], pts[-1]
    if e1 >= e0:
        return None, True
    f = (math.log(target) - math.log(e0)) / (math.log(e1) - math.log(e0))
    return math.exp(math.log(t0) + f * (math.log(t1) - math.log(t0))), True


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("csv", nargs="+")
    ap.add_argument("--targets", default="1e-2,1e-3")
    args = ap.parse_args(argv)
    targets = [float(t) for t in args.targets.split(",")]

    groups = {}
    for path in args.csv:
        with open(path, newline="") as f:
            for r in csv.DictReader(f):
                key = (r["renderer"], r["estimator"])
                groups.setdefault(key, []).append(
                    {"spp": int(r["spp"]), "seconds": float(r["seconds"]), "relmse": float(r["relmse"])})

    base = None
    head = f"{'renderer':<10} {'estimator':<28}" + "".join(
        f" {'t(' + format(t, 'g') + ')':>10} {'ratio':>6}" for t in targets)
    print(head)
    for key, rows in groups.items():
        times = [time_to(rows, t) for t in targets]
        if base is None:
            base = times
        cells = []
        for (t, extra), (b, _) in zip(times, base):
            cells.append(f" {'—' if t is None else ('~' if extra else '') + format(t, '.2f') + ' s':>10}"
                         f" {'' if t is None or b is None else format(t / b, '.2f'):>6}")
        print(f"{key[0]:<10} {key[1]:<28}" + "".join(cells))
    return 0


if __name__ == "__main__":
    sys.exit(main())
