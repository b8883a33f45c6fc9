#!/usr/bin/env python3
"""Writes seed inputs for FuzzBoundaryWalks derived from the bundled CT skin
mesh (Data/headsq_skin_iso500_closed.vtp), in the byte layout documented in
FuzzBoundaryWalks.h.

    make_seed_corpus.py OUTPUT_DIR [--data Data/headsq_skin_iso500_closed.vtp]

Needs Debian's /usr/bin/python3 with the `vtkmodules` package (python3-vtk9
or python3-paraview). Seeds: the whole head decimated to <= 255 triangles
(closed, probes inside and outside), a local patch of the full-resolution
mesh, the same patch scaled to 1e300 and 1e-300 and shifted to 1e18, a
z-slice of the head as a 2D polyline, and raw variants of them.
"""
import argparse
import math
import os
import struct
import sys

from vtkmodules.vtkCommonDataModel import vtkPlane
from vtkmodules.vtkFiltersCore import (vtkCutter, vtkQuadricDecimation, vtkStripper,
                                       vtkTriangleFilter)
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

MAX = 255


def number(v):
    """A double, exactly: selector 0xf0 and its 8 bytes."""
    return b"\xf0" + struct.pack("<d", v)


def encode(dim, vertices, cells, values, probes, raw=False, cell_values=False,
           equation=0, roulette=False, epsilon=0):
    flags = (1 if dim == 2 else 0) | (2 if raw else 0) | (4 if cell_values else 0)
    flags |= (equation & 3) << 4 | (64 if roulette else 0)
    out = bytearray([flags, len(vertices), len(cells), len(probes) & 15, epsilon])
    for v in vertices:
        for k in range(dim):
            out += number(v[k])
    for c in cells:
        out += bytes(c)
    for g in values:
        out += number(g)
    for p in probes:
        for k in range(3):
            out += number(p[k] if k < len(p) else 0.0)
    return bytes(out)


def read_mesh(path):
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(path)
    tri = vtkTriangleFilter()
    tri.SetInputConnection(reader.GetOutputPort())
    tri.Update()
    return tri.GetOutput()


def triangles(poly):
    pts = [poly.GetPoint(i) for i in range(poly.GetNumberOfPoints())]
    cells = []
    polys = poly.GetPolys()
    ids = polys.GetConnectivityArray()
    offsets = polys.GetOffsetsArray()
    for c in range(polys.GetNumberOfCells()):
        a, b = int(offsets.GetValue(c)), int(offsets.GetValue(c + 1))
        if b - a == 3:
            cells.append(tuple(int(ids.GetValue(i)) for i in range(a, b)))
    return pts, cells


def compact(pts, cells):
    """Renumbers the used vertices 0..n-1."""
    index = {}
    out_pts, out_cells = [], []
    for c in cells:
        for i in c:
            if i not in index:
                index[i] = len(out_pts)
                out_pts.append(pts[i])
        out_cells.append(tuple(index[i] for i in c))
    return out_pts, out_cells


def center(pts):
    n = len(pts)
    return [sum(p[k] for p in pts) / n for k in range(3)]


def main():
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("output")
    parser.add_argument("--data", default=os.path.join(root, "Data", "headsq_skin_iso500_closed.vtp"))
    args = parser.parse_args()
    os.makedirs(args.output, exist_ok=True)
    mesh = read_mesh(args.data)
    seeds = {}

    # 1. The whole head, decimated to a closed surface of <= 255 triangles.
    decimate = vtkQuadricDecimation()
    decimate.SetInputData(mesh)
    decimate.SetTargetReduction(1.0 - 240.0 / mesh.GetNumberOfCells())
    decimate.Update()
    pts, cells = compact(*triangles(decimate.GetOutput()))
    cells = cells[:MAX]
    pts, cells = compact(pts, cells)
    assert len(pts) <= MAX, len(pts)
    c = center(pts)
    lo = [min(p[k] for p in pts) for k in range(3)]
    hi = [max(p[k] for p in pts) for k in range(3)]
    probes = [c, [c[0] + 5, c[1], c[2]], [c[0], c[1] - 10, c[2] + 3],
              [hi[0] + 20, c[1], c[2]], [lo[0], lo[1], lo[2]], list(pts[0])]
    temperature = [p[0] / 100.0 for p in pts]  # smooth point values
    seeds["head_decimated"] = encode(3, pts, cells, temperature, probes)
    seeds["head_decimated_cells_screened"] = encode(
        3, pts, cells, [i % 7 for i in range(len(cells))], probes, cell_values=True, equation=3)
    seeds["head_decimated_biharmonic"] = encode(
        3, pts, cells, [v for t in temperature for v in (t, -t)], probes, equation=2)
    seeds["head_decimated_roulette_exact"] = encode(
        3, pts, cells, temperature, probes, equation=1, roulette=True, epsilon=1)

    # 2. A patch of the full-resolution mesh around one vertex.
    full_pts, full_cells = triangles(mesh)
    anchor = full_pts[full_cells[len(full_cells) // 3][0]]
    near = sorted(full_cells, key=lambda t: sum((full_pts[t[0]][k] - anchor[k]) ** 2 for k in range(3)))
    pts, cells = compact(full_pts, near[:120])
    c = center(pts)
    probes = [c, [c[0] + 1, c[1] + 1, c[2] + 1], list(pts[1]), [c[0] - 0.5, c[1], c[2] + 0.25]]
    values = [math.sin(p[0]) + p[2] for p in pts]
    seeds["patch"] = encode(3, pts, cells, values, probes)
    for name, scale, shift in (("patch_1e300", 1e298, 0.0), ("patch_1e-300", 1e-302, 0.0),
                               ("patch_shift_1e18", 1.0, 1e18), ("patch_subnormal", 1e-322, 0.0)):
        sp = [[x * scale + shift for x in p] for p in pts]
        spr = [[x * scale + shift for x in p] for p in probes]
        seeds[name] = encode(3, sp, cells, values, spr)
    # Raw: the same patch with a duplicate, a repeated-index and an
    # out-of-range cell, a NaN vertex and a NaN value.
    bad_pts = pts + [[float("nan"), 0.0, 0.0]]
    bad_cells = cells[:100] + [cells[0], (0, 0, 1), (0, 1, len(bad_pts) - 1), (0, 1, 251 % 256)]
    bad_values = values + [float("nan")]
    seeds["patch_raw_soup"] = encode(3, bad_pts, bad_cells, bad_values, probes, raw=True)

    # 3. A 2D slice of the head: the z = middle contour as segments.
    bounds = mesh.GetBounds()
    plane = vtkPlane()
    plane.SetOrigin(0, 0, 0.5 * (bounds[4] + bounds[5]))
    plane.SetNormal(0, 0, 1)
    cutter = vtkCutter()
    cutter.SetInputData(mesh)
    cutter.SetCutFunction(plane)
    stripper = vtkStripper()
    stripper.SetInputConnection(cutter.GetOutputPort())
    stripper.Update()
    contour = stripper.GetOutput()
    lines = contour.GetLines()
    ids = lines.GetConnectivityArray()
    offsets = lines.GetOffsetsArray()
    longest = max(range(lines.GetNumberOfCells()),
                  key=lambda c: offsets.GetValue(c + 1) - offsets.GetValue(c))
    a, b = int(offsets.GetValue(longest)), int(offsets.GetValue(longest + 1))
    loop = [int(ids.GetValue(i)) for i in range(a, b)]
    step = max(1, (len(loop) + 199) // 200)
    loop = loop[::step]
    pts2 = [contour.GetPoint(i)[:2] for i in loop]
    segs = [(i, (i + 1) % len(pts2)) for i in range(len(pts2))]
    c2 = [sum(p[k] for p in pts2) / len(pts2) for k in range(2)]
    probes2 = [c2 + [0.0], [c2[0] + 7, c2[1] - 4, 0.0], [c2[0] + 500, c2[1], 0.0], list(pts2[3]) + [0.0]]
    seeds["slice2d"] = encode(2, pts2, segs, [p[1] / 50.0 for p in pts2], probes2)
    seeds["slice2d_cells_biharmonic"] = encode(
        2, pts2, segs, [v for i in range(len(segs)) for v in (i % 3, 1.0)], probes2,
        cell_values=True, equation=2)
    seeds["slice2d_1e-300"] = encode(
        2, [[x * 1e-300 for x in p] for p in pts2], segs, [1.0] * len(pts2),
        [[x * 1e-300 for x in p] for p in probes2])

    for name, data in seeds.items():
        with open(os.path.join(args.output, name), "wb") as f:
            f.write(data)
    print("wrote %d seeds (%d..%d bytes) to %s" % (len(seeds), min(map(len, seeds.values())),
                                                   max(map(len, seeds.values())), args.output))


if __name__ == "__main__":
    sys.exit(main())
