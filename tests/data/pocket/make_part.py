"""The 2.5D test part of issue 33, made with Open CASCADE (cadquery-ocp 8.0.1). Run from this
folder: `/work/venv-occ/bin/python make_part.py`; writes `pocket-part.stp` and `pocket-part.json`.

A block 120 x 80 x 30 mm (x 0..120, y 0..80, z 0..30) whose four vertical edges are rounded
R10 (the outer profile), with
- a step: x 100..120 lowered to z = 25 (open on three sides, the wall at x = 100);
- a closed pocket x 15..65, y 20..60 with R5 vertical corners, floor z = 20, and a round
  island of radius 8 at (40, 40) standing to the top (z = 30);
- an open slot x 80..90 across the whole part in y, floor z = 22.

The JSON holds the closed-form values (floor heights, depths, areas, corner radii, islands,
open sides; a smallest corner radius is that of a corner between two walls, none where the
region has no such corner); every area is also measured on the built solid by Open CASCADE (BRepGProp) and
the two must agree to 1e-6 mm^2, else the script fails.
"""
import json
import math

from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut, BRepAlgoAPI_Fuse
from OCP.BRepCheck import BRepCheck_Analyzer
from OCP.BRepFilletAPI import BRepFilletAPI_MakeFillet
from OCP.BRepGProp import BRepGProp
from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox, BRepPrimAPI_MakeCylinder
from OCP.BRepAdaptor import BRepAdaptor_Curve, BRepAdaptor_Surface
from OCP.GeomAbs import GeomAbs_Plane
from OCP.GProp import GProp_GProps
from OCP.IFSelect import IFSelect_RetDone
from OCP.Interface import Interface_Static
from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer
from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE, TopAbs_REVERSED
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS
from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt

TOP = 30.0
STEP_Z = 25.0
POCKET_Z = 20.0
SLOT_Z = 22.0
R_OUT = 10.0
R_POCKET = 5.0
R_ISLAND = 8.0


def cut(a, b):
    op = BRepAlgoAPI_Cut(a, b)
    op.Build()
    return op.Shape()


def fuse(a, b):
    op = BRepAlgoAPI_Fuse(a, b)
    op.Build()
    return op.Shape()


def round_vertical_edges(shape, r):
    fil = BRepFilletAPI_MakeFillet(shape)
    exp = TopExp_Explorer(shape, TopAbs_EDGE)
    while exp.More():
        e = TopoDS.Edge(exp.Current())
        ad = BRepAdaptor_Curve(e)
        p0 = ad.Value(ad.FirstParameter())
        p1 = ad.Value(ad.LastParameter())
        if abs(p0.X() - p1.X()) < 1e-9 and abs(p0.Y() - p1.Y()) < 1e-9:
            fil.Add(r, e)
        exp.Next()
    return fil.Shape()


def box(x0, y0, z0, x1, y1, z1):
    return BRepPrimAPI_MakeBox(gp_Pnt(x0, y0, z0), x1 - x0, y1 - y0, z1 - z0).Shape()


def build():
    part = round_vertical_edges(box(0, 0, 0, 120, 80, TOP), R_OUT)
    part = cut(part, box(100, -1, STEP_Z, 121, 81, TOP + 1))
    pocket = round_vertical_edges(box(15, 20, POCKET_Z, 65, 60, TOP + 1), R_POCKET)
    part = cut(part, pocket)
    island = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(40, 40, POCKET_Z - 1), gp_Dir(0, 0, 1)),
                                      R_ISLAND, TOP - POCKET_Z + 1).Shape()
    part = fuse(part, island)
    part = cut(part, box(80, -1, SLOT_Z, 90, 81, TOP + 1))
    assert BRepCheck_Analyzer(part).IsValid(), "invalid part"
    return part


def corner_loss(r):
    """Area a rectangle loses at one corner rounded to radius r."""
    return (1.0 - math.pi / 4.0) * r * r


def up_facing_planar_faces(part):
    """(z, area) of every planar face whose outward normal is +Z."""
    out = []
    exp = TopExp_Explorer(part, TopAbs_FACE)
    while exp.More():
        f = TopoDS.Face(exp.Current())
        ad = BRepAdaptor_Surface(f)
        if ad.GetType() == GeomAbs_Plane:
            pl = ad.Plane()
            n = pl.Axis().Direction()
            nz = n.Z() * (-1.0 if f.Orientation() == TopAbs_REVERSED else 1.0)
            if nz > 0.999999:
                g = GProp_GProps()
                BRepGProp.SurfaceProperties_s(f, g)
                out.append((pl.Location().Z(), g.Mass()))
        exp.Next()
    return out


def main():
    part = build()
    Interface_Static.SetCVal_s("write.step.schema", "AP214")
    w = STEPControl_Writer()
    w.Transfer(part, STEPControl_AsIs)
    assert w.Write("pocket-part.stp") == IFSelect_RetDone

    outline_area = 120 * 80 - 4 * corner_loss(R_OUT)
    step_area = 20 * 80 - 2 * corner_loss(R_OUT)
    pocket_area = 50 * 40 - 4 * corner_loss(R_POCKET) - math.pi * R_ISLAND ** 2
    slot_area = 10 * 80
    island_area = math.pi * R_ISLAND ** 2
    top_area = outline_area - step_area - slot_area - (50 * 40 - 4 * corner_loss(R_POCKET))
    regions = [
        {"kind": "closed_pocket", "floor_z_mm": POCKET_Z, "top_z_mm": TOP,
         "depth_mm": TOP - POCKET_Z, "floor_area_mm2": pocket_area,
         "min_corner_radius_mm": R_POCKET, "islands": 1, "open_sides": 0,
         "bbox_mm": [15, 20, 65, 60]},
        {"kind": "slot", "floor_z_mm": SLOT_Z, "top_z_mm": TOP, "depth_mm": TOP - SLOT_Z,
         "floor_area_mm2": slot_area, "min_corner_radius_mm": None, "islands": 0,
         "open_sides": 2, "width_mm": 10.0, "bbox_mm": [80, 0, 90, 80]},
        {"kind": "step", "floor_z_mm": STEP_Z, "top_z_mm": TOP, "depth_mm": TOP - STEP_Z,
         "floor_area_mm2": step_area, "min_corner_radius_mm": None, "islands": 0,
         "open_sides": 1, "bbox_mm": [100, 0, 120, 80]},
        {"kind": "outer_profile", "floor_z_mm": 0.0, "top_z_mm": TOP, "depth_mm": TOP,
         "floor_area_mm2": outline_area, "min_corner_radius_mm": None, "islands": 0,
         "open_sides": 0, "bbox_mm": [0, 0, 120, 80]},
    ]
    measured = sorted(up_facing_planar_faces(part))
    expected = sorted([(POCKET_Z, pocket_area), (SLOT_Z, slot_area), (STEP_Z, step_area),
                       (TOP, island_area), (TOP, top_area / 2), (TOP, top_area / 2)])
    # The top is split by the slot into two faces; compare totals per height instead.
    def per_z(items):
        d = {}
        for z, a in items:
            d[round(z, 9)] = d.get(round(z, 9), 0.0) + a
        return d
    m, e = per_z(measured), per_z(expected)
    assert m.keys() == e.keys(), (m, e)
    for z in m:
        assert abs(m[z] - e[z]) < 1e-6, (z, m[z], e[z])
    doc = {
        "part": "pocket-part.stp",
        "units": "mm",
        "top_z_mm": TOP,
        "bottom_z_mm": 0.0,
        "outline": {"x0": 0, "y0": 0, "x1": 120, "y1": 80, "corner_radius_mm": R_OUT},
        "island": {"x": 40, "y": 40, "radius_mm": R_ISLAND, "top_z_mm": TOP},
        "up_facing_area_by_z_mm2": {str(z): a for z, a in sorted(m.items())},
        "regions": regions,
    }
    with open("pocket-part.json", "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
    print(json.dumps(m))


main()
