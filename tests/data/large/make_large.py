#!/usr/bin/env python3
"""Stand-ins for the parts of issue 36 "Import at scale", made with Open CASCADE
(cadquery-ocp-novtk), with Open CASCADE's own figures beside them.

    python3 tests/data/large/make_large.py [OUTDIR]

- `frame-1280.stp`: a 1.28 m frame of the kind of the 1 018-face Inventor part: a filleted base
  plate (cylinder and sphere blends), two flanges 1 148 mm apart with filleted roots, bosses with
  torus fillets, a variable-radius (B-spline) blend, and 400 tubes of radius 1.08 mm and
  1 148 mm long between the flanges (one solid each), in one part (a compound of solids).
- `assembly-5m-inch.stp`: a 5 m assembly of a few solids, written in inches (unit INCH).

Beside each STEP, `NAME.occ.json`: faces, solids, Open CASCADE's BRepMesh triangle count at
0.01 mm linear / 0.5 rad angular deflection and its mesh time (median of 3, read excluded), the
total area (BRepGProp) and each solid's volume, read back from the written file.
"""
import json
import math
import statistics
import sys
import time
from pathlib import Path

from OCP.BRep import BRep_Tool
from OCP.BRepAdaptor import BRepAdaptor_Curve
from OCP.BRepAlgoAPI import BRepAlgoAPI_Fuse
from OCP.BRepBuilderAPI import BRepBuilderAPI_Transform
from OCP.BRepFilletAPI import BRepFilletAPI_MakeFillet
from OCP.BRepGProp import BRepGProp
from OCP.BRepMesh import BRepMesh_IncrementalMesh
from OCP.BRepPrimAPI import (BRepPrimAPI_MakeBox, BRepPrimAPI_MakeCylinder,
                             BRepPrimAPI_MakeSphere, BRepPrimAPI_MakeTorus)
from OCP.BRep import BRep_Builder
from OCP.GProp import GProp_GProps
from OCP.IFSelect import IFSelect_RetDone
from OCP.Interface import Interface_Static
from OCP.STEPControl import STEPControl_AsIs, STEPControl_Reader, STEPControl_Writer
from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE, TopAbs_SOLID
from OCP.TopExp import TopExp_Explorer
from OCP.TopLoc import TopLoc_Location
from OCP.TopoDS import TopoDS, TopoDS_Compound
from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt, gp_Trsf, gp_Vec

LIN_DEFL = 0.01
ANG_DEFL = 0.5


def box(x0, y0, z0, x1, y1, z1):
    return BRepPrimAPI_MakeBox(gp_Pnt(x0, y0, z0), gp_Pnt(x1, y1, z1)).Shape()


def fuse(a, b):
    f = BRepAlgoAPI_Fuse(a, b)
    f.SimplifyResult()
    return f.Shape()


def edges(shape):
    ex = TopExp_Explorer(shape, TopAbs_EDGE)
    out = []
    while ex.More():
        out.append(TopoDS.Edge(ex.Current()))
        ex.Next()
    return out


def count(shape, kind):
    ex = TopExp_Explorer(shape, kind)
    n = 0
    while ex.More():
        n += 1
        ex.Next()
    return n


def edge_mid(e):
    c = BRepAdaptor_Curve(e)
    return c.Value(0.5 * (c.FirstParameter() + c.LastParameter()))


def fillet(shape, pick, radius):
    mk = BRepFilletAPI_MakeFillet(shape)
    n = 0
    for e in edges(shape):
        if pick(e):
            mk.Add(radius, e)
            n += 1
    if n == 0:
        return shape
    mk.Build()
    if not mk.IsDone():
        raise SystemExit("fillet failed")
    return mk.Shape()


def frame():
    """The 1.28 m frame (one solid) and the 400 tubes."""
    # Base plate 1280 x 200 x 10 with every edge rounded (cylinders and spheres at the corners).
    base = box(0, 0, 0, 1280, 200, 10)
    base = fillet(base, lambda e: True, 2.0)
    # Flanges whose inner faces are 1148 mm apart (x = 66 and x = 1214).
    for x0, x1 in ((50, 66), (1214, 1230)):
        base = fuse(base, box(x0, 5, 10, x1, 195, 130))
    # Round bosses on the plate (their root edges get torus fillets below).
    for i in range(6):
        cyl = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(200 + 160 * i, 100, 10), gp_Dir(0, 0, 1)), 12, 20).Shape()
        base = fuse(base, cyl)

    def root(e):
        p = edge_mid(e)
        # Circular roots of the bosses, straight roots of the flanges, at z = 10.
        if abs(p.Z() - 10) > 1e-6:
            return False
        boss = any(abs(p.X() - (200 + 160 * i)) < 13 for i in range(6)) and 80 < p.Y() < 120
        flange = abs(p.Y() - 100) < 1 and any(abs(p.X() - x) < 1e-6 for x in (50, 66, 1214, 1230))
        return boss or flange

    base = fillet(base, root, 3.0)
    # A variable-radius blend (a B-spline surface) along the top outer edge of the first flange.
    mk = BRepFilletAPI_MakeFillet(base)
    for e in edges(base):
        p = edge_mid(e)
        if abs(p.X() - 50) < 1e-6 and abs(p.Z() - 130) < 1e-6:
            mk.Add(2.0, 5.0, e)
    mk.Build()
    if mk.IsDone():
        base = mk.Shape()
    tubes = []
    r, length = 1.08, 1148.0
    for i in range(20):
        for j in range(20):
            y = 12 + 176 * i / 19
            z = 20 + 100 * j / 19
            tubes.append(BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(66, y, z), gp_Dir(1, 0, 0)), r, length).Shape())
    return [base] + tubes


def assembly_5m():
    """A 5 m assembly: a filleted beam, two shafts, a ring (torus), a ball, a plate."""
    beam = fillet(box(0, 0, 0, 5000, 300, 200), lambda e: True, 20.0)
    shaft1 = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, -200, 100), gp_Dir(1, 0, 0)), 60, 5000).Shape()
    shaft2 = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 500, 100), gp_Dir(1, 0, 0)), 25, 4800).Shape()
    ring = BRepPrimAPI_MakeTorus(gp_Ax2(gp_Pnt(2500, 150, 600), gp_Dir(1, 0, 0)), 400, 40).Shape()
    ball = BRepPrimAPI_MakeSphere(gp_Pnt(4500, 150, 700), 250).Shape()
    plate = fillet(box(100, -400, 300, 4900, 700, 340), lambda e: True, 10.0)
    return [beam, shaft1, shaft2, ring, ball, plate]


def compound(shapes):
    c = TopoDS_Compound()
    b = BRep_Builder()
    b.MakeCompound(c)
    for s in shapes:
        b.Add(c, s)
    return c


def write_step(shapes, path, unit, assembly):
    if assembly:
        from OCP.STEPCAFControl import STEPCAFControl_Writer
        from OCP.TCollection import TCollection_ExtendedString
        from OCP.TDocStd import TDocStd_Document
        from OCP.XCAFDoc import XCAFDoc_DocumentTool
        doc = TDocStd_Document(TCollection_ExtendedString("XmlXCAF"))
        tool = XCAFDoc_DocumentTool.ShapeTool_s(doc.Main())
        tool.AddShape(compound(shapes), True)
        Interface_Static.SetCVal_s("write.step.unit", unit)
        w = STEPCAFControl_Writer()
        w.Transfer(doc, STEPControl_AsIs)
        ok = w.Write(str(path))
    else:
        Interface_Static.SetCVal_s("write.step.unit", unit)
        w = STEPControl_Writer()
        w.Transfer(compound(shapes), STEPControl_AsIs)
        ok = w.Write(str(path))
    if ok != IFSelect_RetDone:
        raise SystemExit(f"{path}: write failed")


def read(path):
    r = STEPControl_Reader()
    if r.ReadFile(str(path)) != IFSelect_RetDone:
        raise SystemExit(f"{path}: OCCT could not read it")
    r.TransferRoots()
    return r.OneShape()


def triangles(shape):
    n = 0
    ex = TopExp_Explorer(shape, TopAbs_FACE)
    per_face = []
    while ex.More():
        f = TopoDS.Face(ex.Current())
        t = BRep_Tool.Triangulation_s(f, TopLoc_Location())
        k = t.NbTriangles() if t is not None else 0
        per_face.append(k)
        n += k
        ex.Next()
    return n, per_face


def figures(path):
    shape = read(path)
    times = []
    for _ in range(3):
        s = read(path)
        t0 = time.perf_counter()
        BRepMesh_IncrementalMesh(s, LIN_DEFL, False, ANG_DEFL, False)
        times.append(time.perf_counter() - t0)
    BRepMesh_IncrementalMesh(shape, LIN_DEFL, False, ANG_DEFL, False)
    tris, per_face = triangles(shape)
    props = GProp_GProps()
    BRepGProp.SurfaceProperties_s(shape, props)
    area = props.Mass()
    vols = []
    ex = TopExp_Explorer(shape, TopAbs_SOLID)
    while ex.More():
        p = GProp_GProps()
        BRepGProp.VolumeProperties_s(ex.Current(), p)
        vols.append(p.Mass())
        ex.Next()
    return {
        "file": path.name,
        "occt": "cadquery-ocp-novtk",
        "linear_deflection_mm": LIN_DEFL,
        "angular_deflection_rad": ANG_DEFL,
        "faces": count(shape, TopAbs_FACE),
        "solids": count(shape, TopAbs_SOLID),
        "triangles": tris,
        "triangles_max_face": max(per_face) if per_face else 0,
        "mesh_time_s_median_of_3": statistics.median(times),
        "area_mm2": area,
        "volume_mm3": sum(vols),
        "solid_volumes_mm3": vols,
    }


def main():
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).parent
    out.mkdir(parents=True, exist_ok=True)
    jobs = [
        ("frame-1280.stp", frame, "MM", False),
        ("assembly-5m-inch.stp", assembly_5m, "INCH", True),
    ]
    for name, make, unit, asm in jobs:
        t0 = time.perf_counter()
        shapes = make()
        path = out / name
        write_step(shapes, path, unit, asm)
        fig = figures(path)
        fig["unit_in_file"] = unit
        fig["made_in_s"] = time.perf_counter() - t0
        (out / (path.stem + ".occ.json")).write_text(json.dumps(fig, indent=1) + "\n")
        print(name, path.stat().st_size, "bytes", json.dumps({k: v for k, v in fig.items() if k != "solid_volumes_mm3"}))


if __name__ == "__main__":
    main()
