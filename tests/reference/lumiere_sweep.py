#!/usr/bin/env python3
"""Time lumiere at growing sample counts against a reference; CSV as mitsuba_bench.py.

    python tests/reference/lumiere_sweep.py --lumiere target/release/lumiere \
        --scene cornell --reference REF.exr --width W --height H \
        --terms L0,L1,L2 --spp 1,2,4,8,... --out OUT.csv \
        [--estimator NAME] [-- EXTRA LUMIERE RENDER OPTIONS]

Runs `lumiere render` once per sample count (seed = the run's number, so
every image has fresh samples), takes the render time lumiere prints (the
passes only, not loading the scene or writing the image, as
mitsuba_bench.py times only its renders), and measures RMSE and relMSE
against the reference with lumiere's definitions. Writes
`renderer,estimator,spp,seconds,rmse,relmse` rows (renderer `lumiere`).
"""

import argparse
import csv
import os
import re
import resource
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mitsuba_bench import image_error, parse_spp  # noqa: E402


def read_exr(path):
    import mitsuba as mi
    if mi.variant() is None:
        mi.set_variant("scalar_rgb")
    bmp = mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, srgb_gamma=False)
    return np.array(bmp, dtype=np.float32)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--lumiere", default="target/release/lumiere", help="the lumiere binary (release)")
    ap.add_argument("--scene", default="cornell")
    ap.add_argument("--reference", required=True)
    ap.add_argument("--width", type=int, required=True)
    ap.add_argument("--height", type=int, required=True)
    ap.add_argument("--terms", default="L0,L1,L2")
    ap.add_argument("--spp", type=parse_spp, required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--estimator", default="default", help="the CSV's estimator column")
    ap.add_argument("--seed", type=int, default=1, help="seed of the first render (then +1 each)")
    ap.add_argument("extra", nargs="*", help="more `lumiere render` options (after --)")
    args = ap.parse_args(argv)

    reference = read_exr(args.reference)
    rows = []
    print(f"{'spp':>7} {'seconds':>9} {'cpu s':>9} {'rmse':>11} {'relmse':>11}")
    with tempfile.TemporaryDirectory() as tmp:
        image = os.path.join(tmp, "image.exr")
        for i, spp in enumerate(args.spp):
            cmd = [args.lumiere, "render", args.scene, "--width", str(args.width), "--height",
                   str(args.height), "--terms", args.terms, "--spp", str(spp),
                   "--seed", str(args.seed + i), "-o", image, *args.extra]
            r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
            out = subprocess.run(cmd, check=True, capture_output=True, text=True)
            r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpu = r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime  # whole process
            m = re.search(r"(\d+) spp, ([0-9.]+) s", out.stdout + out.stderr)
            if not m:
                print(f"error: no render time in lumiere's output:\n{out.stdout}{out.stderr}", file=sys.stderr)
                return 2
            rmse, relmse = image_error(read_exr(image), reference)
            rows.append(("lumiere", args.estimator, spp, float(m.group(2)), rmse, relmse))
            print(f"{spp:>7} {float(m.group(2)):>9.3f} {cpu:>9.3f} {rmse:>11.4e} {relmse:>11.4e}", flush=True)

    with open(args.out, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["renderer", "estimator", "spp", "seconds", "rmse", "relmse"])
        for r in rows:
            w.writerow([r[0], r[1], r[2], f"{r[3]:.6f}", f"{r[4]:.6e}", f"{r[5]:.6e}"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
