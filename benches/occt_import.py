#!/usr/bin/env python3
"""Open CASCADE's STEP import time for a file, for comparison with `cargo bench --bench kernel`
(`step_import/pocket-fillets read_step`). Run on the same machine in the same session:

    python3 -m venv .venv && .venv/bin/pip install cadquery-ocp-novtk
    .venv/bin/python benches/occt_import.py tests/data/pocket-fillets.stp

Prints the median of N runs of ReadFile + TransferRoots + OneShape (what Talas's read_step does:
parse + B-rep), and of that plus BRepMesh at 0.01 mm (Talas's read + tessellate).
"""
import statistics
import sys
import time

from OCP.BRepMesh import BRepMesh_IncrementalMesh
from OCP.IFSelect import IFSelect_RetDone
from OCP.STEPControl import STEPControl_Reader


def read(path):
    r = STEPControl_Reader()
    if r.ReadFile(path) != IFSelect_RetDone:
        raise SystemExit(f"{path}: OCCT could not read it")
    r.TransferRoots()
    return r.OneShape()


def median_time(fn, n):
    times = []
    for _ in range(n):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main():
    path = sys.argv[1] if len(sys.argv) > 1 else "tests/data/pocket-fillets.stp"
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 20
    read(path)  # warm up
    t_read = median_time(lambda: read(path), n)
    t_mesh = median_time(lambda: BRepMesh_IncrementalMesh(read(path), 0.01, False, 0.25, False), n)
    print(f"occt read_step median: {t_read * 1e3:.3f} ms")
    print(f"occt read_step + mesh 0.01 mm median: {t_mesh * 1e3:.3f} ms")


if __name__ == "__main__":
    main()
