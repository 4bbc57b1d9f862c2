#!/usr/bin/env python3
"""Exact reference for waterline contours of the ball and flat end mills (no OCL, no Talas).

A cutter whose tip is at (x, y, z) touches the mesh without cutting it when the clearance

    g(x, y) = min over mesh points q of  |q - c|        (q at or below the ball centre c = (x, y, z + R))
                                          |q.xy - c.xy|  (q above it: the shank cylinder)

equals R (ball end mill, radius R), or when the horizontal distance from (x, y) to the part of
the mesh at or above z equals R (flat end mill). Each triangle is clipped once per level at the
plane that separates the two parts; the distances to the clipped pieces are the closed forms
(point to plane inside the triangle, else to its edges). A waterline contour point is exact when
its residual g - R is zero; a negative residual is a gouge, a positive one a missed contact.

Used by waterline_ocl.py (column "exact residual") and on its own:
    .venv/bin/python benches/waterline_exact.py tests/data/pocket-fillets.stl ball 6 15.0 X,Y [X,Y ...]
"""

import sys

import numpy as np


def clip_below(tris, zc, keep_below):
    """Fan triangles of the part of each triangle at or below (keep_below) or above the plane z = zc."""
    out = []
    for t in tris:
        poly = []
        for k in range(3):
            a, b = t[k], t[(k + 1) % 3]
            ina = a[2] <= zc if keep_below else a[2] >= zc
            inb = b[2] <= zc if keep_below else b[2] >= zc
            if ina:
                poly.append(a)
            if ina != inb and a[2] != b[2]:
                s = (zc - a[2]) / (b[2] - a[2])
                poly.append(a + s * (b - a))
        for k in range(1, len(poly) - 1):
            out.append((poly[0], poly[k], poly[k + 1]))
    return np.array(out, dtype=float).reshape(-1, 3, 3)


def _segment_distance(p, a, b):
    d = b - a
    dd = np.maximum((d * d).sum(-1), 1e-300)
    s = np.clip(((p - a) * d).sum(-1) / dd, 0.0, 1.0)
    q = a + s[..., None] * d
    return np.sqrt(((p - q) ** 2).sum(-1))


def point_triangle_distance(p, tris):
    """Distance from the point p (dim 2 or 3) to each triangle (n, 3, dim)."""
    if len(tris) == 0:
        return np.full(0, np.inf)
    a, b, c = tris[:, 0], tris[:, 1], tris[:, 2]
    edges = np.minimum(np.minimum(_segment_distance(p, a, b), _segment_distance(p, b, c)),
                       _segment_distance(p, c, a))
    v0, v1, v2 = b - a, c - a, p - a
    d00, d01, d11 = (v0 * v0).sum(-1), (v0 * v1).sum(-1), (v1 * v1).sum(-1)
    d20, d21 = (v2 * v0).sum(-1), (v2 * v1).sum(-1)
    den = d00 * d11 - d01 * d01
    ok = np.abs(den) > 1e-300
    den = np.where(ok, den, 1.0)
    v = (d11 * d20 - d01 * d21) / den
    w = (d00 * d21 - d01 * d20) / den
    inside = ok & (v >= 0) & (w >= 0) & (v + w <= 1)
    foot = a + v[:, None] * v0 + w[:, None] * v1
    plane = np.sqrt(((p - foot) ** 2).sum(-1))
    return np.where(inside, np.minimum(plane, edges), edges)


class ExactLevel:
    """Clearance of a ball (kind 'ball') or flat ('flat') cutter of radius R whose tip is at height z."""

    def __init__(self, tris, kind, radius, z):
        self.kind, self.r, self.z = kind, radius, z
        split = z + radius if kind == "ball" else z
        near = tris[tris[:, :, 2].max(1) >= z - 1e-12]
        self.low = clip_below(near, split, True) if kind == "ball" else np.zeros((0, 3, 3))
        self.high = clip_below(near, split, False)[:, :, :2]

    def clearance(self, xy):
        c = np.array([xy[0], xy[1], self.z + self.r])
        g = np.inf
        if len(self.low):
            g = min(g, point_triangle_distance(c, self.low).min())
        if len(self.high):
            g = min(g, point_triangle_distance(c[:2], self.high).min())
        return g

    def residuals(self, points):
        return np.array([self.clearance(p) - self.r for p in points])


def main():
    sys.path.insert(0, __file__.rsplit("/", 1)[0])
    from dropcutter_ocl import read_stl_triangles
    stl, kind, dia, z = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
    level = ExactLevel(read_stl_triangles(stl), kind, dia / 2, z)
    for arg in sys.argv[5:]:
        x, y = map(float, arg.split(","))
        print(f"{x} {y}: residual {level.clearance((x, y)) - dia / 2:+.3e} mm")


if __name__ == "__main__":
    main()
