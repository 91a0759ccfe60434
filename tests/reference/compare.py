#!/usr/bin/env python3
"""Compare two linear RGB EXR images, A against the reference B.

    python tests/reference/compare.py A.exr B.exr [--block 8] [--eps 1e-3]
        [--max-mean-rel X] [--max-block-p99 X]

Prints the mean of each image (per channel and overall), the relative
difference of the means (A - B) / B, and, over blocks of 8x8 pixels, the
maximum and the 99th percentile of the relative difference of the block
means |A - B| / |B|, per channel and pooled over the channels. Blocks
where both images are about 0 (below eps = 1e-3 times B's overall mean) are
skipped. With --max-mean-rel / --max-block-p99 it exits with status 1
when the overall mean's or the pooled 99th percentile's relative
difference exceeds the bound.
"""

import argparse
import sys

import numpy as np


def read_exr(path):
    try:
        import mitsuba as mi
        if mi.variant() is None:
            mi.set_variant("scalar_rgb")
        img = np.array(mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32,
                                               srgb_gamma=False), dtype=np.float64)
    except ImportError:
        import imageio.v3 as iio
        img = np.asarray(iio.imread(path), dtype=np.float64)
    if img.ndim == 2:
        img = img[:, :, None].repeat(3, axis=2)
    return img[:, :, :3]


def block_means(img, b):
    h, w, c = img.shape
    hb, wb = -(-h // b), -(-w // b)
    sums = np.zeros((hb, wb, c))
    counts = np.zeros((hb, wb, 1))
    ys, xs = np.arange(h) // b, np.arange(w) // b
    np.add.at(sums, (ys[:, None], xs[None, :]), img)
    np.add.at(counts, (ys[:, None], xs[None, :]), 1.0)
    return sums / counts


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("a", help="image to check (EXR)")
    ap.add_argument("b", help="reference image (EXR)")
    ap.add_argument("--block", type=int, default=8, help="block size in pixels (default 8)")
    ap.add_argument("--eps", type=float, default=1e-3,
                    help="skip blocks where both values are below eps x the reference's mean (default 1e-3)")
    ap.add_argument("--max-mean-rel", type=float, help="fail if |relative difference of the means| exceeds this")
    ap.add_argument("--max-block-p99", type=float, help="fail if the pooled 99th percentile exceeds this")
    args = ap.parse_args(argv)

    a, b = read_exr(args.a), read_exr(args.b)
    if a.shape != b.shape:
        print(f"error: sizes differ: {a.shape} vs {b.shape}", file=sys.stderr)
        return 2
    for name, img in (("A", a), ("B", b)):
        if not np.all(np.isfinite(img)):
            print(f"warning: {name} has {np.count_nonzero(~np.isfinite(img))} non-finite values", file=sys.stderr)

    ma, mb = a.reshape(-1, 3).mean(axis=0), b.reshape(-1, 3).mean(axis=0)
    print(f"A {args.a}: {a.shape[1]}x{a.shape[0]}")
    print(f"B {args.b}: {b.shape[1]}x{b.shape[0]}")
    print(f"mean A   R {ma[0]:.6g}  G {ma[1]:.6g}  B {ma[2]:.6g}  overall {ma.mean():.6g}")
    print(f"mean B   R {mb[0]:.6g}  G {mb[1]:.6g}  B {mb[2]:.6g}  overall {mb.mean():.6g}")
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.where(ma == mb, 0.0, (ma - mb) / mb)  # 0 when both are 0
        rel_all = 0.0 if ma.mean() == mb.mean() else (ma.mean() - mb.mean()) / mb.mean()
    print(f"rel diff of means (A-B)/B   R {rel[0]:+.4%}  G {rel[1]:+.4%}  B {rel[2]:+.4%}  overall {rel_all:+.4%}")

    ba, bb = block_means(a, args.block), block_means(b, args.block)
    thresh = args.eps * max(mb.mean(), 1e-30)
    keep = ~((np.abs(ba) < thresh) & (np.abs(bb) < thresh))
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.abs(ba - bb) / np.abs(bb)
    r = np.where(keep, r, np.nan)
    nblocks = ba.shape[0] * ba.shape[1]
    print(f"{args.block}x{args.block} blocks: {nblocks} per channel; "
          f"|A-B|/|B| of block means (blocks with both < {thresh:.3g} skipped)")
    pooled = r[~np.isnan(r)]
    for i, ch in enumerate("RGB"):
        v = r[:, :, i]
        v = v[~np.isnan(v)]
        if v.size:
            print(f"  {ch}: max {np.max(v):.4%}  p99 {np.percentile(v, 99):.4%}  "
                  f"({v.size} blocks, {nblocks - v.size} skipped)")
        else:
            print(f"  {ch}: all blocks skipped")
    if pooled.size:
        p99 = float(np.percentile(pooled, 99))
        print(f"  all: max {np.max(pooled):.4%}  p99 {p99:.4%}")
    else:
        p99 = 0.0
        print("  all: all blocks skipped")

    ok = True
    if args.max_mean_rel is not None and not abs(rel_all) <= args.max_mean_rel:
        print(f"FAIL: relative difference of the means {rel_all:+.4%} exceeds {args.max_mean_rel:.4%}")
        ok = False
    if args.max_block_p99 is not None and not p99 <= args.max_block_p99:
        print(f"FAIL: block p99 {p99:.4%} exceeds {args.max_block_p99:.4%}")
        ok = False
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
