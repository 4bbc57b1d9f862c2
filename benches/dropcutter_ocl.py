#!/usr/bin/env python3
"""Drop-cutter: Talas against OpenCAMLib's BatchDropCutter on the shared STLs.

For each mesh (tests/data/bicubic-hills.stl, tests/data/pocket-fillets.stl) and each cutter
(ball d=6, flat/cylindrical d=10, bull-nose d=10 r=2, cone d=10 45°) both programs drop the
cutter at the same grid of >= 100 000 XY points. Reported: max |dz| over the points where both find the mesh, the
number of such points, both wall times and the ratio OpenCAMLib / Talas.

Talas's time is the whole `talas dropcutter --json` process (STL read, BVH build, drop, JSON
written and parsed back here); OpenCAMLib's is STLSurf construction plus BatchDropCutter.run(),
with the same number of threads (all cores).

Usage (from the repository root):
    python3 -m venv .venv && .venv/bin/pip install opencamlib numpy
    cargo build --release --no-default-features
    .venv/bin/python benches/dropcutter_ocl.py [--n 320] [--talas target/release/talas]
"""

import argparse
import json
import os
import struct
import subprocess
import tempfile
import time

import numpy as np
from opencamlib import ocl

MESHES = ["tests/data/bicubic-hills.stl", "tests/data/pocket-fillets.stl"]
CUTTERS = [
    ("ball:d=6", lambda: ocl.BallCutter(6.0, 30.0)),
    ("flat:d=10", lambda: ocl.CylCutter(10.0, 30.0)),
    ("bull:d=10,r=2", lambda: ocl.BullCutter(10.0, 2.0, 30.0)),
    # OCL's ConeCutter takes the half-angle in radians, as Talas's `angle` (in degrees).
    ("cone:d=10,angle=45", lambda: ocl.ConeCutter(10.0, 0.25 * 3.141592653589793, 30.0)),
]


def read_stl_triangles(path):
    """Triangles of a binary or ASCII STL as an (n, 3, 3) float64 array."""
    data = open(path, "rb").read()
    if len(data) >= 84:
        (n,) = struct.unpack_from("<I", data, 80)
        if 84 + 50 * n == len(data):
            rec = np.frombuffer(data, dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]),
                                count=n, offset=84)
            return rec["v"].astype(np.float64)
    verts = [list(map(float, line.split()[1:4])) for line in data.decode().splitlines()
             if line.strip().startswith("vertex")]
    return np.array(verts, dtype=np.float64).reshape(-1, 3, 3)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=320, help="grid points per side (n*n points)")
    ap.add_argument("--talas", default="target/release/talas")
    ap.add_argument("--only", default="", help="run only the tools whose spec contains this text")
    args = ap.parse_args()
    threads = os.cpu_count() or 1
    print(f"# {args.n * args.n} points per run, {threads} threads, opencamlib {ocl.version()}")
    print("mesh | tool | compared | max |dz| mm | talas s | ocl s | ocl/talas")
    worst = 0.0
    for mesh in MESHES:
        tris = read_stl_triangles(mesh)
        lo = tris.reshape(-1, 3).min(axis=0)
        hi = tris.reshape(-1, 3).max(axis=0)
        xs = np.linspace(lo[0], hi[0], args.n)
        ys = np.linspace(lo[1], hi[1], args.n)
        pts = [(x, y) for y in ys for x in xs]
        with tempfile.NamedTemporaryFile("w", suffix=".csv", delete=False) as f:
            f.write("x,y\n")
            f.writelines(f"{float(x)!r},{float(y)!r}\n" for x, y in pts)
            csv = f.name
        z0 = lo[2] - 100.0
        for spec, make in CUTTERS:
            if args.only not in spec:
                continue
            t = time.perf_counter()
            out = subprocess.run([args.talas, "dropcutter", mesh, "--tool", spec, "--points", csv, "--json"],
                                 check=True, capture_output=True, text=True).stdout
            doc = json.loads(out)
            t_talas = time.perf_counter() - t

            t = time.perf_counter()
            surf = ocl.STLSurf()
            for tri in tris:
                surf.addTriangle(ocl.Triangle(*(ocl.Point(*map(float, v)) for v in tri)))
            bdc = ocl.BatchDropCutter()
            bdc.setThreads(threads)
            bdc.setSTL(surf)
            cutter = make()  # keep a reference: OCL stores a raw pointer to it
            bdc.setCutter(cutter)
            for x, y in pts:
                bdc.appendPoint(ocl.CLPoint(float(x), float(y), z0))
            bdc.run()
            cls = bdc.getCLPoints()
            t_ocl = time.perf_counter() - t

            # OCL returns its points in input order; z stays at z0 where the cutter misses.
            dz = []
            for cl_t, cl_o in zip(doc["cl"], cls):
                if cl_t is None or cl_o.z <= z0 + 1e-9:
                    continue
                dz.append(abs(cl_t[2] - cl_o.z))
            dmax = max(dz) if dz else float("nan")
            worst = max(worst, dmax)
            print(f"{os.path.basename(mesh)} | {spec} | {len(dz)} | {dmax:.3e} | {t_talas:.3f} | {t_ocl:.3f} | "
                  f"{t_ocl / t_talas:.2f}")
        os.unlink(csv)
    print(f"# worst max |dz| = {worst:.3e} mm (target 1e-5)")


if __name__ == "__main__":
    main()
