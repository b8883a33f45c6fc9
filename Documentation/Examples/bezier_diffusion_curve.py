"""GridFree example: a diffusion-curve picture, the colours on a few cubic
Bézier curves spread smoothly over the plane by walk on spheres.

Run with the Python that sees VTK, with the `gridfree` module on PYTHONPATH
(`./gridfree env` prints it):

    python3 bezier_diffusion_curve.py --resolution 200 --walks 128 \
        --output diffusion_curve.vti

The boundary is a 2D vtkPolyData (all points in z = 0) made of polylines of
Bézier control points, marked by the cell array "BezierControlPoints" = 1:
  - a closed outline of four cubic curves (a rounded, slightly lopsided
    blob), a colour at each of its four curve end points;
  - an open S-shaped stroke of two curves inside it, one colour along it;
  - a straight polyline (BezierControlPoints = 0) across the lower part,
    to show that plain segments and curves mix.
Colours are RGB point data ("Color", 3 components) given at the curve end
points; the inner control points (handles) are off the curve, so their
values are never used (they are set to 0 here). Along a curve the colour is
interpolated linearly in the curve parameter t between its two end points.

The vtkWalkOnSpheresSolver estimates the harmonic interpolant (Laplace
equation, every colour channel from the same walks) at the points of a
vtkImageData plane around the outline. Points outside the outline solve the
exterior problem (bounded at infinity in 2D). Writes the image with "Color",
"Color_Variance" and the walk statistics as a .vti, and prints points, walks
and seconds.
"""
import argparse
import time

import gridfree
from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkIntArray, vtkPoints
from vtkmodules.vtkCommonDataModel import (
    vtkCellArray, vtkDataObject, vtkImageData, vtkPolyData)
from vtkmodules.vtkIOXML import vtkXMLImageDataWriter

# Outline: end points E0..E3 and two handles per curve, counter-clockwise.
OUTLINE = [
    (1.0, 0.0), (1.0, 0.7), (0.6, 1.1),       # E0, handles
    (0.0, 1.0), (-0.7, 0.9), (-1.1, 0.5),     # E1, handles
    (-1.0, 0.0), (-0.9, -0.6), (-0.5, -1.0),  # E2, handles
    (0.0, -1.0), (0.6, -1.0), (1.0, -0.6),    # E3, handles; closes at E0
]
OUTLINE_COLORS = [(0.9, 0.2, 0.1), (0.95, 0.8, 0.1), (0.1, 0.5, 0.9), (0.2, 0.8, 0.3)]
# Inner S stroke: two curves, 7 control points (end points at 0, 3, 6).
STROKE = [(-0.5, 0.3), (-0.3, 0.7), (0.0, 0.0), (0.1, 0.3), (0.2, 0.6), (0.5, -0.1), (0.6, 0.3)]
STROKE_COLOR = (1.0, 1.0, 1.0)
# A straight polyline (ordinary segments).
SEGMENT = [(-0.6, -0.5), (0.0, -0.6), (0.5, -0.5)]
SEGMENT_COLOR = (0.1, 0.1, 0.1)


def parse_arguments():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", default="diffusion_curve.vti", help="image to write (.vti)")
    parser.add_argument("--resolution", type=int, default=200, help="pixels along each side")
    parser.add_argument("--walks", type=int, default=128, help="walks per pixel")
    parser.add_argument("--seed", type=int, default=0)
    return parser.parse_args()


def diffusion_curve_boundary():
    """The outline, the stroke and the segment as one 2D vtkPolyData."""
    points = vtkPoints()
    points.SetDataTypeToDouble()
    lines = vtkCellArray()
    bezier = vtkIntArray()
    bezier.SetName("BezierControlPoints")
    color = vtkDoubleArray()
    color.SetName("Color")
    color.SetNumberOfComponents(3)

    def add_polyline(coordinates, colors, is_bezier, closed=False):
        first = points.GetNumberOfPoints()
        for (x, y), rgb in zip(coordinates, colors):
            points.InsertNextPoint(x, y, 0.0)
            color.InsertNextTuple3(*rgb)
        ids = list(range(first, first + len(coordinates)))
        if closed:
            ids.append(first)  # the last curve ends where the first starts
        lines.InsertNextCell(len(ids))
        for i in ids:
            lines.InsertCellPoint(i)
        bezier.InsertNextValue(1 if is_bezier else 0)

    handle = (0.0, 0.0, 0.0)  # never used: handles are not on the curve
    outline_colors = []
    for k in range(len(OUTLINE)):
        outline_colors.append(OUTLINE_COLORS[k // 3] if k % 3 == 0 else handle)
    add_polyline(OUTLINE, outline_colors, True, closed=True)
    add_polyline(STROKE, [STROKE_COLOR if k % 3 == 0 else handle for k in range(len(STROKE))],
                 True)
    add_polyline(SEGMENT, [SEGMENT_COLOR] * len(SEGMENT), False)

    boundary = vtkPolyData()
    boundary.SetPoints(points)
    boundary.SetLines(lines)
    boundary.GetCellData().AddArray(bezier)
    boundary.GetPointData().AddArray(color)
    return boundary


def image_plane(resolution, margin=0.15):
    """A resolution × resolution image in z = 0 around the outline."""
    low, high = -1.1 - margin, 1.1 + margin
    image = vtkImageData()
    image.SetDimensions(resolution, resolution, 1)
    image.SetOrigin(low, low, 0.0)
    spacing = (high - low) / (resolution - 1)
    image.SetSpacing(spacing, spacing, 1.0)
    return image


def main():
    args = parse_arguments()
    solver = gridfree.vtkWalkOnSpheresSolver()
    solver.SetBoundaryData(diffusion_curve_boundary())
    solver.SetProbeData(image_plane(args.resolution))
    solver.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS, "Color")
    solver.SetWalksPerPoint(args.walks)
    solver.SetSeed(args.seed)
    start = time.perf_counter()
    solver.Update()
    seconds = time.perf_counter() - start

    writer = vtkXMLImageDataWriter()
    writer.SetFileName(args.output)
    writer.SetInputData(solver.GetOutput())
    writer.Write()
    print(f"points: {solver.GetOutput().GetNumberOfPoints()}")
    print(f"walks: {solver.GetLastNumberOfWalks()}")
    print(f"seconds: {seconds:.2f}")
    print(f"wrote: {args.output}")


if __name__ == "__main__":
    main()
