#!/usr/bin/env python3
"""Waterline: Talas's contours against OpenCAMLib's Waterline on the shared STLs.

For each mesh (tests/data/bicubic-hills.stl, tests/data/pocket-fillets.stl) and each cutter
(ball d=6, flat d=10, bull-nose d=10 r=2, cone d=10 45 deg) both programs compute the
cutter's contours at the same levels (tool-tip heights spread over the part's height) with
fibres the same distance apart. Reported: the two-way distance between the contours (each
Talas contour point to the nearest segment of OCL's closed loops at that level, and each OCL
point to Talas's loops; max and 99.9 % quantile), the number of loops of each, and both
planning times in the same run: Talas's is the BVH build plus all levels (timed inside
`talas contours`, all cores), OCL's is STLSurf construction plus Waterline.run() for all
levels (OpenMP, all cores).

Usage (from the repository root):
    python3 -m venv .venv && .venv/bin/pip install opencamlib numpy
    cargo build --release --no-default-features
    .venv/bin/python benches/waterline_ocl.py [--sampling 0.02] [--levels 5] [--only ball]
"""

import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np
from opencamlib import ocl

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from dropcutter_ocl import read_stl_triangles  # noqa: E402
from waterline_exact import ExactLevel  # noqa: E402

MESHES = ["tests/data/bicubic-hills.stl", "tests/data/pocket-fillets.stl"]
CUTTERS = [
    ("ball:d=6", lambda: ocl.BallCutter(6.0, 30.0)),
    ("flat:d=10", lambda: ocl.CylCutter(10.0, 30.0)),
    ("bull:d=10,r=2", lambda: ocl.BullCutter(10.0, 2.0, 30.0)),
    ("cone:d=10,angle=45", lambda: ocl.ConeCutter(10.0, 0.25 * 3.141592653589793, 30.0)),
]


def seg_distance(points, loops):
    """Distance from each point (n, 2) to the nearest segment of the closed loops."""
    if not loops or len(points) == 0:
        return np.full(len(points), np.inf)
    a = np.concatenate([lp for lp in loops])
    b = np.concatenate([np.roll(lp, -1, axis=0) for lp in loops])
    out = np.empty(len(points))
    d = b - a
    dd = np.maximum((d * d).sum(1), 1e-300)
    for k in range(0, len(points), 256):
        p = points[k:k + 256, None, :]
        t = np.clip(((p - a) * d).sum(2) / dd, 0.0, 1.0)
        q = a + t[..., None] * d
        out[k:k + 256] = np.sqrt(((p - q) ** 2).sum(2)).min(1)
    return out


def run_ocl(tris, make_cutter, levels, sampling):
    t0 = time.perf_counter()
    surf = ocl.STLSurf()
    for t in tris:
        surf.addTriangle(ocl.Triangle(*(ocl.Point(*map(float, v)) for v in t)))
    cutter = make_cutter()
    out = []
    for z in levels:
        # One Waterline object per level: reset() and a second run() crash this OCL build.
        wl = ocl.Waterline()
        wl.setSTL(surf)
        wl.setCutter(cutter)
        wl.setSampling(sampling)
        wl.setZ(z)
        wl.run()
        out.append([np.array([[p.x, p.y] for p in lp]) for lp in wl.getLoops() if len(lp) >= 3])
    return out, time.perf_counter() - t0


def run_talas(binary, stl, spec, levels, sampling):
    res = subprocess.run([binary, "contours", stl, "--tool", spec, "--levels", ",".join(map(str, levels)),
                          "--sampling", str(sampling), "--json"], check=True, capture_output=True, text=True)
    doc = json.loads(res.stdout)
    out = [[np.array(lp, dtype=float) for lp in lv["loops"] if len(lp) >= 3] for lv in doc["levels"]]
    return out, doc["time_s"]


def spread_levels(tris, n):
    """n tip heights spread over the part's height, each moved off the heights of horizontal
    triangles: a level on a horizontal face is degenerate (the cutter's tip touches the whole
    face, so every point over it is a contact and the contour is not a curve)."""
    zmin, zmax = tris[:, :, 2].min(), tris[:, :, 2].max()
    flat = tris[np.ptp(tris[:, :, 2], axis=1) < 1e-9][:, 0, 2]
    out = []
    for k in range(n):
        z = zmin + (zmax - zmin) * (k + 0.5) / n
        while np.any(np.abs(flat - z) < 1e-3):
            z += 0.137 * (zmax - zmin) / n
        out.append(float(z))
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--talas", default="target/release/talas")
    ap.add_argument("--sampling", type=float, default=0.02)
    ap.add_argument("--levels", type=int, default=5)
    ap.add_argument("--only", default="")
    ap.add_argument("--mesh", default="", help="only meshes whose name contains this")
    ap.add_argument("--z", default="", help="comma-separated tip heights instead of --levels")
    args = ap.parse_args()
    binary = args.talas
    print(f"sampling {args.sampling} mm, {args.levels} levels per part, {os.cpu_count()} cores")
    print("mesh | tool | loops talas/ocl | talas->ocl max, q99.9 (mm) | ocl->talas max, q99.9 (mm)"
          " | exact residual talas, ocl (mm) | talas s | ocl s | ocl/talas")
    for mesh in MESHES:
        if args.mesh not in mesh:
            continue
        tris = read_stl_triangles(mesh)
        levels = [float(z) for z in args.z.split(",")] if args.z else spread_levels(tris, args.levels)
        for spec, make in CUTTERS:
            if args.only and args.only not in spec:
                continue
            ocl_loops, t_ocl = run_ocl(tris, make, levels, args.sampling)
            tal_loops, t_tal = run_talas(binary, mesh, spec, levels, args.sampling)
            d1, d2, e1, e2 = [], [], [0.0], [0.0]
            nl = [0, 0]
            kind = spec.split(":")[0]
            for z, tl, ol in zip(levels, tal_loops, ocl_loops):
                nl[0] += len(tl)
                nl[1] += len(ol)
                tp = np.concatenate(tl) if tl else np.zeros((0, 2))
                op = np.concatenate(ol) if ol else np.zeros((0, 2))
                d1.append(seg_distance(tp, ol))
                d2.append(seg_distance(op, tl))
                if kind in ("ball", "flat"):
                    exact = ExactLevel(tris, kind, float(spec.split("d=")[1].split(",")[0]) / 2, z)
                    e1.append(np.abs(exact.residuals(tp)).max(initial=0.0))
                    e2.append(np.abs(exact.residuals(op)).max(initial=0.0))
            d1, d2 = np.concatenate(d1), np.concatenate(d2)
            exact_col = f"{max(e1):.1e}, {max(e2):.1e}" if kind in ("ball", "flat") else "-"
            print(f"{os.path.basename(mesh)} | {spec} | {nl[0]}/{nl[1]} | {d1.max():.2e}, {np.quantile(d1, 0.999):.2e}"
                  f" | {d2.max():.2e}, {np.quantile(d2, 0.999):.2e} | {exact_col} | {t_tal:.3f} | {t_ocl:.3f} | {t_ocl / t_tal:.2f}",
                  flush=True)


if __name__ == "__main__":
    main()
