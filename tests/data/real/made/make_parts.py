"""Small parts of the kinds real CAD systems send, made with Open CASCADE (cadquery-ocp-novtk
8.0.1) for Talas's tessellation tests. Run from this folder: `python make_parts.py`.

- drilled-block.stp: a block with blind drilled holes ending in 118° drill points (cones that
  close at their apex), one counterbored, one with a spherical end, filleted edges (tori).
- thin-tube.stp: a tube of outer radius 1.08 mm, inner 0.8 mm, 1148 mm long, as the many small
  tubes of a long shaft.
- fan.stp: a hub (surface of revolution from a B-spline meridian) with a cone nose, a torus
  fillet, blades lofted through B-spline sections (B-spline surfaces) and extruded B-spline
  profiles (surfaces of linear extrusion), and a sphere cap.
"""
import math

from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut, BRepAlgoAPI_Fuse
from OCP.BRepCheck import BRepCheck_Analyzer
from OCP.BRepBuilderAPI import (BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeFace,
                                BRepBuilderAPI_MakeWire, BRepBuilderAPI_Transform)
from OCP.BRepFilletAPI import BRepFilletAPI_MakeFillet
from OCP.BRepOffsetAPI import BRepOffsetAPI_ThruSections
from OCP.BRepPrimAPI import (BRepPrimAPI_MakeBox, BRepPrimAPI_MakeCone,
                             BRepPrimAPI_MakeCylinder, BRepPrimAPI_MakePrism,
                             BRepPrimAPI_MakeRevol, BRepPrimAPI_MakeSphere,
                             BRepPrimAPI_MakeTorus)
from OCP.GeomAPI import GeomAPI_PointsToBSpline
from OCP.gp import gp_Ax1, gp_Ax2, gp_Dir, gp_Pnt, gp_Trsf, gp_Vec
from OCP.IFSelect import IFSelect_RetDone
from OCP.Interface import Interface_Static
from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer
from OCP.collections import Array1_gp_Pnt as TColgp_Array1OfPnt
from OCP.TopAbs import TopAbs_EDGE
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS


def write(shape, name):
    Interface_Static.SetCVal_s("write.step.schema", "AP214")
    w = STEPControl_Writer()
    w.Transfer(shape, STEPControl_AsIs)
    assert w.Write(name) == IFSelect_RetDone, name


def fuse(a, b):
    op = BRepAlgoAPI_Fuse(a, b)
    op.Build()
    out = op.Shape()
    assert BRepCheck_Analyzer(out).IsValid(), "fuse gave an invalid shape"
    return out


def cut(a, b):
    op = BRepAlgoAPI_Cut(a, b)
    op.Build()
    return op.Shape()


def drill(x, y, top, r, depth):
    """A drill: cylinder from above the top down to `depth`, then a 118° point."""
    h_point = r / math.tan(math.radians(59.0))
    cyl = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(x, y, top - depth), gp_Dir(0, 0, 1)), r,
                                   depth + 1.0).Shape()
    cone = BRepPrimAPI_MakeCone(gp_Ax2(gp_Pnt(x, y, top - depth - h_point), gp_Dir(0, 0, 1)),
                                0.0, r, h_point).Shape()
    return fuse(cyl, cone)


def drilled_block():
    block = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 60.0, 40.0, 25.0).Shape()
    fil = BRepFilletAPI_MakeFillet(block)
    exp = TopExp_Explorer(block, TopAbs_EDGE)
    while exp.More():
        e = TopoDS.Edge(exp.Current())
        fil.Add(3.0, e)
        exp.Next()
    block = fil.Shape()
    block = cut(block, drill(12, 12, 25, 4.25, 14))
    block = cut(block, drill(30, 20, 25, 3.3, 18))
    # counterbore above a drilled hole
    block = cut(block, drill(48, 12, 25, 2.75, 16))
    block = cut(block, BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(48, 12, 20), gp_Dir(0, 0, 1)),
                                               4.5, 6).Shape())
    # ball-end hole
    ball = fuse(BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(48, 30, 15), gp_Dir(0, 0, 1)), 3.0,
                                         11).Shape(),
                BRepPrimAPI_MakeSphere(gp_Pnt(48, 30, 15), 3.0).Shape())
    block = cut(block, ball)
    return block


def thin_tube():
    outer = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(1, 0, 0)), 1.08,
                                     1148.0).Shape()
    inner = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(-1, 0, 0), gp_Dir(1, 0, 0)), 0.8,
                                     1150.0).Shape()
    return cut(outer, inner)


def spline(points):
    arr = TColgp_Array1OfPnt(1, len(points))
    for k, p in enumerate(points):
        arr.SetValue(k + 1, gp_Pnt(*p))
    return GeomAPI_PointsToBSpline(arr).Curve()


def closed_wire(points):
    """A wire of a B-spline through `points` closed by a line back to the first point."""
    c = spline(points)
    e1 = BRepBuilderAPI_MakeEdge(c).Edge()
    e2 = BRepBuilderAPI_MakeEdge(gp_Pnt(*points[-1]), gp_Pnt(*points[0])).Edge()
    return BRepBuilderAPI_MakeWire(e1, e2).Wire()


def fan():
    # Hub: a B-spline meridian in the xz plane revolved about z (surface of revolution).
    mer = [(0.0, 0, 0), (20.0, 0, 0), (22.0, 0, 8), (21.0, 0, 16), (18.0, 0, 24), (0.0, 0, 24)]
    c = spline(mer[1:5])
    edges = [BRepBuilderAPI_MakeEdge(gp_Pnt(*mer[0]), gp_Pnt(*mer[1])).Edge(),
             BRepBuilderAPI_MakeEdge(c).Edge(),
             BRepBuilderAPI_MakeEdge(gp_Pnt(*mer[4]), gp_Pnt(*mer[5])).Edge(),
             BRepBuilderAPI_MakeEdge(gp_Pnt(*mer[5]), gp_Pnt(*mer[0])).Edge()]
    wb = BRepBuilderAPI_MakeWire()
    for e in edges:
        wb.Add(e)
    prof = BRepBuilderAPI_MakeFace(wb.Wire(), True).Face()
    hub = BRepPrimAPI_MakeRevol(prof, gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1))).Shape()
    # Nose cone and a torus ring sitting on it, a sphere cap.
    nose = BRepPrimAPI_MakeCone(gp_Ax2(gp_Pnt(0, 0, 24), gp_Dir(0, 0, 1)), 12.0, 4.0,
                                10.0).Shape()
    hub = fuse(hub, nose)
    hub = fuse(hub, BRepPrimAPI_MakeSphere(gp_Pnt(0, 0, 34), 5.0).Shape())
    hub = fuse(hub, BRepPrimAPI_MakeTorus(gp_Ax2(gp_Pnt(0, 0, 3), gp_Dir(0, 0, 1)), 20.5,
                                          2.5).Shape())
    # Blades: lofted through three cambered sections of two B-splines each (B-spline surfaces).
    for k in range(3):
        loft = BRepOffsetAPI_ThruSections(True, False)
        for r, twist in ((17.0, 0.0), (40.0, 0.3), (65.0, 0.6)):
            up = [(r, 10.0 * s, 12.0 + 3.0 * (1 - s * s) + twist * 10.0 * s)
                  for s in (-1.0, -0.5, 0.0, 0.5, 1.0)]
            low = [(x, y, z - 2.0 * (1 - (y / 10.0) ** 2)) for (x, y, z) in up]
            e_up = BRepBuilderAPI_MakeEdge(spline(up)).Edge()
            e_low = BRepBuilderAPI_MakeEdge(spline(low[::-1])).Edge()
            loft.AddWire(BRepBuilderAPI_MakeWire(e_up, e_low).Wire())
        loft.Build()
        t = gp_Trsf()
        t.SetRotation(gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), 2 * math.pi * k / 3)
        hub = fuse(hub, BRepBuilderAPI_Transform(loft.Shape(), t).Shape())
    # Ribs: B-spline profiles extruded along z (surfaces of linear extrusion).
    for k in range(3):
        a = 2 * math.pi * (k + 0.5) / 3
        ca, sa = math.cos(a), math.sin(a)
        pts = []
        for s in (0.0, 0.25, 0.5, 0.75, 1.0):
            r = 18.0 + 14.0 * s
            w = 1.5 * math.sin(math.pi * s) + 0.5
            pts.append((r * ca - w * sa, r * sa + w * ca, 0.0))
        prof = BRepBuilderAPI_MakeFace(closed_wire(pts), True).Face()
        rib = BRepPrimAPI_MakePrism(prof, gp_Vec(0, 0, 6)).Shape()
        hub = fuse(hub, rib)
    return hub


write(drilled_block(), "drilled-block.stp")
write(thin_tube(), "thin-tube.stp")
write(fan(), "fan.stp")
