"""Open CASCADE reference for Talas's tessellation tests (cadquery-ocp-novtk 8.0.1).

usage: occ_reference.py FILE.stp [DEFLECTION_MM]

Prints CSV on stdout: one `face` row per face as TopExp_Explorer visits them (surface kind, area
in mm² from BRepGProp.SurfaceProperties, centre of mass in mm), one `solid` row per solid (volume
in mm³ from BRepGProp.VolumeProperties, centre), and a `mesh` row with BRepMesh_IncrementalMesh's
triangle count at the deflection (default 0.01 mm, angular 0.5 rad, OCCT's default); read and
mesh wall times on stderr.
"""
import sys
import time

from OCP.BRep import BRep_Tool
from OCP.BRepAdaptor import BRepAdaptor_Surface
from OCP.BRepGProp import BRepGProp
from OCP.BRepMesh import BRepMesh_IncrementalMesh
from OCP.GProp import GProp_GProps
from OCP.IFSelect import IFSelect_RetDone
from OCP.STEPControl import STEPControl_Reader
from OCP.TopAbs import TopAbs_FACE, TopAbs_SOLID
from OCP.TopExp import TopExp_Explorer
from OCP.TopLoc import TopLoc_Location
from OCP.TopoDS import TopoDS

KINDS = {0: "plane", 1: "cylinder", 2: "cone", 3: "sphere", 4: "torus", 5: "bezier",
         6: "bspline", 7: "revolution", 8: "extrusion", 9: "offset", 10: "other"}


def main():
    path = sys.argv[1]
    defl = float(sys.argv[2]) if len(sys.argv) > 2 else 0.01
    t0 = time.perf_counter()
    reader = STEPControl_Reader()
    if reader.ReadFile(path) != IFSelect_RetDone:
        sys.exit(f"{path}: not read")
    reader.TransferRoots()
    shape = reader.OneShape()
    t_read = time.perf_counter() - t0
    print("row,kind,value,cx,cy,cz")
    exp = TopExp_Explorer(shape, TopAbs_FACE)
    while exp.More():
        f = TopoDS.Face(exp.Current())
        props = GProp_GProps()
        BRepGProp.SurfaceProperties_s(f, props)
        kind = KINDS.get(int(BRepAdaptor_Surface(f).GetType()), "other")
        c = props.CentreOfMass()
        print(f"face,{kind},{props.Mass():.9f},{c.X():.6f},{c.Y():.6f},{c.Z():.6f}")
        exp.Next()
    exp = TopExp_Explorer(shape, TopAbs_SOLID)
    k = 0
    while exp.More():
        props = GProp_GProps()
        BRepGProp.VolumeProperties_s(exp.Current(), props)
        c = props.CentreOfMass()
        print(f"solid,solid,{props.Mass():.6f},{c.X():.6f},{c.Y():.6f},{c.Z():.6f}")
        k += 1
        exp.Next()
    t1 = time.perf_counter()
    BRepMesh_IncrementalMesh(shape, defl, False, 0.5, False)
    t_mesh = time.perf_counter() - t1
    n = 0
    exp = TopExp_Explorer(shape, TopAbs_FACE)
    while exp.More():
        loc = TopLoc_Location()
        tri = BRep_Tool.Triangulation_s(TopoDS.Face(exp.Current()), loc)
        if tri is not None:
            n += tri.NbTriangles()
        exp.Next()
    print(f"mesh,triangles,{n},{defl},0,0")
    print(f"time,read_s,{t_read:.3f},mesh_s,{t_mesh:.3f}", file=sys.stderr)


main()
