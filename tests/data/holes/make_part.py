"""The hole-making test part, made with Open CASCADE (cadquery-ocp-novtk 8.0.1).
Run from this folder: `/work/venv-occ/bin/python make_part.py`. Writes

- holes-part.stp: a 100 x 60 mm block, 30 mm high for x < 50 and 20 mm high for x > 50 (holes on
  two heights), with through holes, blind holes with 118° drill points, a flat-bottomed blind
  hole, a counterbore, a countersink and a through hole whose wall is split in two half faces;
- holes-part.json: the holes as they were made (the reference the recognition test compares to,
  all lengths mm, angles degrees) and the part's area and volume from BRepGProp.

Each hole is `{x, y, top, diameter, depth, bottom, point_angle, steps}`: the axis is +z (the
tool comes from +z), `top` the z of its entry face, `diameter` and `depth` those of the main
(smallest, deepest) bore measured from `top` to the end of its cylinder (through holes: to the
bottom face), `bottom` is `through`, `flat` or `point`; `steps` the wider parts above the main
bore from the top down: `{kind: "cylinder", diameter, depth}` (a counterbore: depth from top to
its floor) or `{kind: "cone", diameter, angle}` (a countersink: diameter at the top, included
angle).
"""
import json
import math

from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut, BRepAlgoAPI_Fuse
from OCP.BRepCheck import BRepCheck_Analyzer
from OCP.BRepGProp import BRepGProp
from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox, BRepPrimAPI_MakeCone, BRepPrimAPI_MakeCylinder
from OCP.GProp import GProp_GProps
from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt
from OCP.IFSelect import IFSelect_RetDone
from OCP.Interface import Interface_Static
from OCP.ShapeUpgrade import ShapeUpgrade_ShapeDivideClosed
from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer
from OCP.TopAbs import TopAbs_FACE
from OCP.TopExp import TopExp_Explorer

Z = gp_Dir(0, 0, 1)


def fuse(a, b):
    op = BRepAlgoAPI_Fuse(a, b)
    op.Build()
    return op.Shape()


def cut(a, b):
    op = BRepAlgoAPI_Cut(a, b)
    op.Build()
    out = op.Shape()
    assert BRepCheck_Analyzer(out).IsValid(), "cut gave an invalid shape"
    return out


def cylinder(x, y, z0, r, h):
    return BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(x, y, z0), Z), r, h).Shape()


HOLES = []


def hole(block, x, y, top, d, depth, bottom, steps=(), split=False):
    """Cut one hole and record it."""
    r = d / 2.0
    if bottom == "through":
        tool = cylinder(x, y, top - depth - 1.0, r, depth + 2.0)
    else:
        tool = cylinder(x, y, top - depth, r, depth + 1.0)
    if bottom == "point":
        h = r / math.tan(math.radians(59.0))
        tool = fuse(tool, BRepPrimAPI_MakeCone(gp_Ax2(gp_Pnt(x, y, top - depth - h), Z), 0.0, r,
                                               h).Shape())
    if split:
        div = ShapeUpgrade_ShapeDivideClosed(tool)
        div.SetNbSplitPoints(1)
        div.Perform()
        tool = div.Result()
    block = cut(block, tool)
    for s in steps:
        if s["kind"] == "cylinder":
            block = cut(block, cylinder(x, y, top - s["depth"], s["diameter"] / 2.0,
                                        s["depth"] + 1.0))
        else:
            rt = s["diameter"] / 2.0
            half = math.radians(s["angle"] / 2.0)
            # a cone from the axis (apex below) to 1 mm above the top
            h = (rt + math.tan(half)) / math.tan(half)
            apex = top - rt / math.tan(half)
            block = cut(block, BRepPrimAPI_MakeCone(gp_Ax2(gp_Pnt(x, y, apex), Z), 0.0,
                                                    rt + math.tan(half), h).Shape())
    HOLES.append({"x": x, "y": y, "top": top, "diameter": d, "depth": depth, "bottom": bottom,
                  "point_angle": 118.0 if bottom == "point" else None, "steps": list(steps),
                  "split": split})
    return block


def part():
    block = fuse(BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 50.0, 60.0, 30.0).Shape(),
                 BRepPrimAPI_MakeBox(gp_Pnt(50, 0, 0), 50.0, 60.0, 20.0).Shape())
    from OCP.ShapeUpgrade import ShapeUpgrade_UnifySameDomain
    u = ShapeUpgrade_UnifySameDomain(block, True, True, False)
    u.Build()
    block = u.Shape()
    # high level, z = 30
    block = hole(block, 10, 10, 30, 6.0, 30, "through")
    block = hole(block, 10, 50, 30, 6.0, 30, "through")
    block = hole(block, 25, 15, 30, 8.5, 15, "point")
    block = hole(block, 40, 30, 30, 10.0, 8, "flat")
    block = hole(block, 25, 45, 30, 6.6, 30, "through",
                 steps=[{"kind": "cylinder", "diameter": 11.0, "depth": 6.5}])
    # low level, z = 20
    block = hole(block, 70, 15, 20, 5.0, 10, "point")
    block = hole(block, 70, 45, 20, 5.5, 20, "through",
                 steps=[{"kind": "cone", "diameter": 10.0, "angle": 90.0}])
    block = hole(block, 88, 30, 20, 8.0, 20, "through", split=True)
    block = hole(block, 60, 30, 20, 4.2, 12, "point")
    return block


def main():
    shape = part()
    Interface_Static.SetCVal_s("write.step.schema", "AP214")
    w = STEPControl_Writer()
    w.Transfer(shape, STEPControl_AsIs)
    assert w.Write("holes-part.stp") == IFSelect_RetDone
    props = GProp_GProps()
    BRepGProp.SurfaceProperties_s(shape, props)
    area = props.Mass()
    vprops = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, vprops)
    n = 0
    exp = TopExp_Explorer(shape, TopAbs_FACE)
    while exp.More():
        n += 1
        exp.Next()
    with open("holes-part.json", "w", encoding="utf-8") as f:
        json.dump({"occ_area_mm2": area, "occ_volume_mm3": vprops.Mass(), "occ_faces": n,
                   "holes": HOLES}, f, indent=1)
        f.write("\n")
    print(f"area {area:.6f} mm², volume {vprops.Mass():.6f} mm³, {n} faces, {len(HOLES)} holes")


if __name__ == "__main__":
    main()
