"""The job test part: a 60 x 40 x 25 mm block (x -30..30, y -20..20, z 0..25) with features
on three sides, made with Open CASCADE (cadquery-ocp):
- top (+Z): a 30 x 16 x 5 mm pocket centred at (0, 0), and two 6 mm holes 8 mm deep at
  (+-22, 0);
- front (-Y): a 20 x 10 mm pocket 4 mm deep centred at (0, z = 12.5) with a 8 mm boss in it;
- right side (+X): a slot 6 mm wide, 3 mm deep along Y at z = 15.

Run: /work/venv-occ/bin/python tests/data/job/make_part.py tests/data/job/job-part.stp
Prints the volume (mm^3) and the face count Open CASCADE computes, which the tests compare
Talas's reading with.
"""
import sys

from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut, BRepAlgoAPI_Fuse
from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox, BRepPrimAPI_MakeCylinder
from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt
from OCP.GProp import GProp_GProps
from OCP.BRepGProp import BRepGProp
from OCP.STEPControl import STEPControl_Writer, STEPControl_AsIs
from OCP.TopExp import TopExp_Explorer
from OCP.TopAbs import TopAbs_FACE


def box(x0, y0, z0, x1, y1, z1):
    return BRepPrimAPI_MakeBox(gp_Pnt(x0, y0, z0), gp_Pnt(x1, y1, z1)).Shape()


def cyl(p, d, r, h):
    return BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(*p), gp_Dir(*d)), r, h).Shape()


def cut(a, b):
    return BRepAlgoAPI_Cut(a, b).Shape()


def fuse(a, b):
    return BRepAlgoAPI_Fuse(a, b).Shape()


part = box(-30, -20, 0, 30, 20, 25)
# Top: pocket and two holes.
part = cut(part, box(-15, -8, 20, 15, 8, 26))
for x in (-22.0, 22.0):
    part = cut(part, cyl((x, 0.0, 17.0), (0, 0, 1), 3.0, 9.0))
# Front: pocket 4 mm deep with a boss Ø8 standing 3 mm in it.
part = cut(part, box(-10, -21, 7.5, 10, -16, 17.5))
part = fuse(part, cyl((0.0, -16.0, 12.5), (0, -1, 0), 4.0, 3.0))
# Right side: a slot along Y.
part = cut(part, box(27, -21, 12, 31, 21, 18))

props = GProp_GProps()
BRepGProp.VolumeProperties_s(part, props)
faces = 0
e = TopExp_Explorer(part, TopAbs_FACE)
while e.More():
    faces += 1
    e.Next()
w = STEPControl_Writer()
w.Transfer(part, STEPControl_AsIs)
w.Write(sys.argv[1] if len(sys.argv) > 1 else "job-part.stp")
print(f"volume_mm3 {props.Mass():.6f} faces {faces}")
