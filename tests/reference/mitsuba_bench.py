#!/usr/bin/env python3
"""Time Mitsuba 3's path tracer against a reference, at growing sample counts.

The peer half of `lumiere bench --peer mitsuba`: loads a lumiere glTF scene
exactly as mitsuba_render.py does, renders it at each sample count of
--spp, times each render, and measures its error against a reference EXR
with lumiere's own definitions (src/metrics.rs):

    RMSE   = sqrt(1/3n sum (x - r)^2)
    relMSE = 1/3n sum (x - r)^2 / (r^2 + 1e-2)

    python tests/reference/mitsuba_bench.py SCENE.gltf --reference REF.exr \
        --width W --height H --max-depth 3 --spp 1,2,4,8,... --out OUT.csv \
        [--until-relmse 1e-3 --spp-limit 1024] [--variant llvm_ad_rgb] [--threads N] \
        [--brdf lambert|mirror|phong|glass] [--ior ETA] [--sphere-lights RADIUS] [--point-emitters]

(`--brdf`, `--sphere-lights` and `--point-emitters` are lumiere's `--brdf`,
`--lights area` and `--lights point`,
as in mitsuba_render.py.) Unlike mitsuba_render.py's references, the timed
renders use Russian roulette as lumiere does (`--rr-depth 4`): both end
deep paths the same way, which only matters past L2.

The CSV's header is `renderer,estimator,spp,seconds,rmse,relmse`, one row a
render (renderer `mitsuba`, estimator `path-llvm` or `path-scalar`); a short
table goes to standard output, with the CPU seconds of each render too (all
threads): on a shared machine the wall time depends on the other load, the
CPU time much less.

With --until-relmse, a curve whose last image is still above that relMSE
goes on with twice the samples, then twice again, while the count stays
within --spp-limit: lumiere's own rule for its curves (`extend_spp` in
src/bench/error_curve.rs), so that both renderers get a time to 10^-3
rather than a bound.

Timing: each row's seconds is the wall time of its renders (all passes) up
to the image as a NumPy array, so the kernels have really run; loading the
scene is not counted. Before the timed renders, one warm-up render at 1 spp
compiles the JIT kernels (llvm variants); it is not timed and not reported,
because compilation happens once per process (and Dr.Jit also caches kernels
on disk), not once per image, and later renders of any sample count reuse
the kernels. Every render uses fresh seeds. Large sample counts are split
into passes of --spp-per-pass samples (default 256 for llvm, bounding the
wavefront's memory), each with its own seed, and averaged, as
mitsuba_render.py does.
"""

import argparse
import csv
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mitsuba_render as mr  # noqa: E402  (the scene conversion, shared)

RELMSE_EPSILON = 1e-2  # lumiere's src/metrics.rs
# lumiere's Russian roulette starts after the fourth reflection (survival
# min(max throughput, 0.95)); Mitsuba's rr_depth 4 starts it at the same
# vertex with the same survival. It never touches max_depth <= 3 (L0-L2).
LUMIERE_RR_DEPTH = 4


def image_error(image, reference):
    """(RMSE, relMSE) of `image` against `reference`, as lumiere's metrics.rs:
    f32 pixels widened to f64, averaged over all pixels and the 3 channels."""
    x = np.asarray(image, dtype=np.float32)[:, :, :3].astype(np.float64)
    r = np.asarray(reference, dtype=np.float32)[:, :, :3].astype(np.float64)
    if x.shape != r.shape or x.size == 0:
        raise ValueError(f"image {x.shape} and reference {r.shape} differ in size")
    e2 = (x - r) ** 2
    return float(np.sqrt(e2.mean())), float((e2 / (r * r + RELMSE_EPSILON)).mean())


_READ_EXR = """
import sys, numpy as np, mitsuba as mi
mi.set_variant("scalar_rgb")
bmp = mi.Bitmap(sys.argv[1]).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, srgb_gamma=False)
np.save(sys.argv[2], np.array(bmp, dtype=np.float32))
"""


def read_exr(path):
    """A linear RGB EXR as float32 (height, width, 3), read by Mitsuba in a
    child process: in this one, once Dr.Jit's thread count is set to 1,
    reading an EXR never returns."""
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "image.npy")
        subprocess.run([sys.executable, "-c", _READ_EXR, path, out], check=True)
        return np.load(out)


def parse_spp(text):
    try:
        spps = [int(s) for s in text.split(",") if s.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a list of sample counts: {text!r}")
    if not spps or min(spps) < 1:
        raise argparse.ArgumentTypeError("sample counts must be positive")
    return spps


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene", help="lumiere glTF scene (.gltf or .glb)")
    ap.add_argument("--reference", required=True, help="reference EXR (linear RGB), same size")
    ap.add_argument("--width", type=int, required=True)
    ap.add_argument("--height", type=int, required=True)
    ap.add_argument("--max-depth", type=int, required=True,
                    help="maximum number of path segments (1 = L0, 2 = L0+L1, 3 = L0+L1+L2)")
    ap.add_argument("--spp", type=parse_spp, required=True, help="comma-separated sample counts, e.g. 1,2,4,8")
    ap.add_argument("--out", required=True, help="CSV to write")
    ap.add_argument("--until-relmse", type=float, default=None,
                    help="past the last count, double the samples while relMSE is above this")
    ap.add_argument("--spp-limit", type=int, default=0,
                    help="the most samples a doubled count may reach (with --until-relmse)")
    ap.add_argument("--variant", default="llvm_ad_rgb",
                    help="Mitsuba variant (default llvm_ad_rgb; scalar_rgb needs no LLVM)")
    ap.add_argument("--threads", type=int, default=None, help="worker threads (default: all cores)")
    ap.add_argument("--spp-per-pass", type=int, default=None,
                    help="most samples per render call (default 256 for llvm, unlimited for scalar)")
    ap.add_argument("--seed", type=int, default=1, help="seed of the first timed pass (the warm-up uses 0)")
    ap.add_argument("--rr-depth", type=int, default=LUMIERE_RR_DEPTH,
                    help="Russian roulette after this many interactions (default 4, as lumiere)")
    mr.add_override_arguments(ap)
    args = ap.parse_args(argv)

    llvm = args.variant.startswith("llvm")
    if llvm and not os.environ.get("DRJIT_LIBLLVM_PATH"):
        lib = mr.find_libllvm()
        if lib:
            os.environ["DRJIT_LIBLLVM_PATH"] = lib
    import drjit as dr
    if args.threads is not None:
        # before the variant starts its backend
        dr.set_thread_count(args.threads)
    import mitsuba as mi
    mi.set_variant(args.variant)
    if mi.variant() != args.variant:
        print(f"error: Mitsuba runs {mi.variant()}, not {args.variant}", file=sys.stderr)
        return 2
    mr.register_phong(mi)
    mr.register_textures(mi)
    mr.register_emitters(mi)
    threads = dr.thread_count() if hasattr(dr, "thread_count") else os.cpu_count()

    reference = read_exr(args.reference)
    if reference.shape[:2] != (args.height, args.width):
        print(f"error: the reference is {reference.shape[1]}x{reference.shape[0]}, "
              f"not {args.width}x{args.height}", file=sys.stderr)
        return 2

    g = mr.Gltf(args.scene)
    scene = mi.load_dict(mr.convert(mi, g, args.width, args.height, 1, args.max_depth, verbose=False,
                                          brdf=mr.brdf_override(args), sphere_radius=args.sphere_lights,
                                          rr_depth=args.rr_depth, given_camera=args.camera,
                                          point_emitters=args.point_emitters))

    per_pass = args.spp_per_pass or (256 if llvm else max(args.spp))
    seed = [args.seed]

    def render(spp, timed=True):
        """The image of `spp` samples per pixel: passes of at most per_pass,
        each with a fresh seed, averaged (weighted by their sample counts)."""
        acc, left = None, spp
        while left > 0:
            n = min(per_pass, left)
            s = seed[0] if timed else 0
            if timed:
                seed[0] += 1
            img = np.array(mi.render(scene, spp=n, seed=s), dtype=np.float64) * n
            acc = img if acc is None else acc + img
            left -= n
        return (acc / spp).astype(np.float32)

    # Warm-up: one untimed render at 1 spp compiles the kernels; renders of
    # other sample counts reuse them (the sample count and the seed are not
    # baked into the kernels: no recompilation shows in Dr.Jit's kernel history).
    t = time.perf_counter()
    render(1, timed=False)
    warm = time.perf_counter() - t

    estimator = "path-" + ("llvm" if llvm else args.variant.split("_")[0])
    rows = []

    def measure(spp):
        t0, c0 = time.perf_counter(), time.process_time()
        img = render(spp)
        seconds, cpu = time.perf_counter() - t0, time.process_time() - c0
        rmse, relmse = image_error(img, reference)
        rows.append(("mitsuba", estimator, spp, seconds, rmse, relmse, cpu))

    for spp in args.spp:
        measure(spp)
    if args.until_relmse is not None:
        # the same rule as lumiere's curves (next_extended_count)
        while rows[-1][5] > args.until_relmse and 2 * rows[-1][2] <= args.spp_limit:
            measure(2 * rows[-1][2])

    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    with open(args.out, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["renderer", "estimator", "spp", "seconds", "rmse", "relmse"])
        for r in rows:
            w.writerow([r[0], r[1], r[2], f"{r[3]:.6f}", f"{r[4]:.6e}", f"{r[5]:.6e}"])

    print(f"mitsuba {mi.__version__} {mi.variant()}, {threads} threads, {args.width}x{args.height}, "
          f"max_depth {args.max_depth}, passes of <= {per_pass} spp; warm-up (untimed) {warm:.2f} s")
    print(f"{'spp':>7} {'seconds':>9} {'spp/s':>9} {'cpu s':>9} {'rmse':>11} {'relmse':>11}")
    for _, _, spp, seconds, rmse, relmse, cpu in rows:
        print(f"{spp:>7} {seconds:>9.3f} {spp / seconds:>9.1f} {cpu:>9.3f} {rmse:>11.4e} {relmse:>11.4e}")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except mr.GltfError as e:
        print(f"error: {e}", file=sys.stderr)
        sys.exit(2)
