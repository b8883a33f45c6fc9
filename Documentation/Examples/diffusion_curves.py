"""Diffusion curves and surfaces (paper Sec. 6.4, Figs. 16 and 18): colours
on the two sides of curves or of a surface, spread by walk on spheres.
Left: Bézier curves and a polyline with a colour on each side, plus a glow
from a source term, as an image of the whole plane. Middle: a small window
of the same image at the same resolution, computed on its own (no global
solve). Right: the CT head's skin with one colour on the air side and
another on the tissue side, evaluated on a slice through the head.

Run with pvbatch under xvfb (the GridFree plugin loads through
PV_PLUGIN_PATH, which `./gridfree env` prints):

    pvbatch diffusion_curves.py --output Documentation/Images

Writes diffusion_curves.png and prints the points, walks and seconds of each
panel.
"""
import argparse
import os
import sys

import paraview.simple as pvs
from example_pictures import producer, save
from paraview import servermanager
from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkIntArray, vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData

HERE = os.path.dirname(os.path.abspath(__file__))
SKIN = os.path.join(HERE, "..", "..", "Data", "headsq_skin_iso500_closed.vtp")

# Strokes: (control points, front colours at the curve end points, back
# colours, Bézier or straight). The front is the left side going along.
STROKES = [
    # An S across the picture: warm on its left, cool on its right.
    ([(-1.0, -0.7), (-0.5, 0.3), (0.1, -0.9), (0.35, 0.0), (0.6, 0.9), (0.9, 0.4),
      (1.0, 1.0)],
     [(1.0, 0.35, 0.1), (0.95, 0.8, 0.2), (0.9, 0.1, 0.3)],
     [(0.05, 0.2, 0.6), (0.1, 0.7, 0.8), (0.3, 0.1, 0.5)], True),
    # A closed loop of four curves, counter-clockwise: yellow inside
    # (its left), dark outside.
    ([(-0.35, 0.45), (-0.35, 0.65), (-0.55, 0.8), (-0.7, 0.8), (-0.85, 0.8), (-1.0, 0.65),
      (-1.0, 0.45), (-1.0, 0.25), (-0.85, 0.1), (-0.7, 0.1), (-0.55, 0.1), (-0.35, 0.25),
      (-0.35, 0.45)],
     [(1.0, 0.95, 0.4), (1.0, 0.85, 0.2), (1.0, 0.95, 0.4), (1.0, 0.85, 0.2), (1.0, 0.95, 0.4)],
     [(0.15, 0.05, 0.25), (0.3, 0.0, 0.2), (0.15, 0.05, 0.25), (0.3, 0.0, 0.2),
      (0.15, 0.05, 0.25)], True),
    # A straight polyline near the bottom: green above, white below.
    ([(-0.9, -0.85), (-0.2, -0.95), (0.5, -0.8)],
     [(0.2, 0.7, 0.3), (0.1, 0.5, 0.2), (0.3, 0.8, 0.4)],
     [(1.0, 1.0, 1.0), (0.9, 0.9, 0.85), (1.0, 1.0, 1.0)], False),
]
# A glow: Δu = f with f < 0 raises every channel around (0.55, -0.45).
GLOW = "-150*exp(-((x-0.55)^2+(y+0.45)^2)/0.008)"
WINDOW = (-1.1, 1.1, -1.1, 1.1)
ZOOM = (-1.05, -0.55, -1.0, -0.5)


def parse_arguments():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", default="output", help="folder for the picture")
    parser.add_argument("--resolution", type=int, default=240, help="pixels across each panel")
    parser.add_argument("--walks", type=int, default=128, help="walks per pixel")
    return parser.parse_args()


def curve_boundary():
    """The strokes as polylines of control points (BezierControlPoints marks
    the Bézier ones), with FrontColor and BackColor at every point (the
    handles' values are not used)."""
    points = vtkPoints()
    lines = vtkCellArray()
    front, back = vtkDoubleArray(), vtkDoubleArray()
    for array, name in ((front, "FrontColor"), (back, "BackColor")):
        array.SetName(name)
        array.SetNumberOfComponents(3)
    bezier = vtkIntArray()
    bezier.SetName("BezierControlPoints")
    for control, fronts, backs, is_bezier in STROKES:
        first = points.GetNumberOfPoints()
        step = 3 if is_bezier else 1
        for k, (x, y) in enumerate(control):
            points.InsertNextPoint(x, y, 0.0)
            end = k // step if k % step == 0 else None
            front.InsertNextTuple3(*(fronts[end] if end is not None else (0.0, 0.0, 0.0)))
            back.InsertNextTuple3(*(backs[end] if end is not None else (0.0, 0.0, 0.0)))
        lines.InsertNextCell(len(control))
        for k in range(len(control)):
            lines.InsertCellPoint(first + k)
        bezier.InsertNextValue(1 if is_bezier else 0)
    curves = vtkPolyData()
    curves.SetPoints(points)
    curves.SetLines(lines)
    curves.GetPointData().AddArray(front)
    curves.GetPointData().AddArray(back)
    curves.GetCellData().AddArray(bezier)
    return curves


def drawn_strokes(samples=40):
    """The strokes as fine polylines, to draw them (Bézier curves evaluated)."""
    points = vtkPoints()
    lines = vtkCellArray()
    for control, _, _, is_bezier in STROKES:
        shape = []
        if is_bezier:
            for c in range(0, len(control) - 1, 3):
                p0, p1, p2, p3 = control[c:c + 4]
                for s in range(samples + 1):
                    t = s / samples
                    a, b, c2, d = (1 - t) ** 3, 3 * t * (1 - t) ** 2, 3 * t * t * (1 - t), t ** 3
                    shape.append((a * p0[0] + b * p1[0] + c2 * p2[0] + d * p3[0],
                                  a * p0[1] + b * p1[1] + c2 * p2[1] + d * p3[1]))
        else:
            shape = control
        first = points.GetNumberOfPoints()
        for x, y in shape:
            points.InsertNextPoint(x, y, 0.001)
        lines.InsertNextCell(len(shape))
        for k in range(len(shape)):
            lines.InsertCellPoint(first + k)
    drawn = vtkPolyData()
    drawn.SetPoints(points)
    drawn.SetLines(lines)
    return drawn


def skin_colours(skin):
    """Two-sided colours on the skin: blue-green by height on the air side
    (front: the mesh is wound outward), warm and varying around the head on
    the tissue side (back)."""
    colours = pvs.Calculator(Input=skin, ResultArrayName="FrontColor")
    colours.Function = "0.1*iHat + (0.3+0.6*(coordsZ+2)/142)*jHat + 0.85*kHat"
    colours = pvs.Calculator(Input=colours, ResultArrayName="BackColor")
    colours.Function = ("0.95*iHat + (0.45+0.35*sin(atan2(coordsY-94,coordsX-99)*2))*jHat"
                        " + (0.25+0.25*cos(atan2(coordsY-94,coordsX-99)))*kHat")
    return colours


def report(name, proxy):
    data = servermanager.Fetch(proxy)
    walks = int(data.GetFieldData().GetArray("TotalWalks").GetValue(0))
    seconds = data.GetFieldData().GetArray("SolveSeconds").GetValue(0)
    print(f"{name}: points {data.GetNumberOfPoints()}, walks {walks}, seconds {seconds:.1f}, "
          f"walks/s {walks / max(seconds, 1e-9):.0f}")
    return walks, seconds


def main():
    args = parse_arguments()
    if not hasattr(pvs, "WalkOnSpheresDiffusionCurves"):
        sys.exit("GridFree plugin not loaded (PV_PLUGIN_PATH)")
    os.makedirs(args.output, exist_ok=True)
    curves = producer(curve_boundary())
    strokes = producer(drawn_strokes())

    images = []
    for window in (WINDOW, ZOOM):
        image = pvs.WalkOnSpheresDiffusionCurves(Boundary=curves)
        image.FrontColor = ["POINTS", "FrontColor"]
        image.BackColor = ["POINTS", "BackColor"]
        image.SourceExpression = GLOW
        image.ImageWindow = list(window)
        image.ImageResolution = [args.resolution, args.resolution]
        image.WalksPerPoint = args.walks
        image.UpdatePipeline()
        images.append(image)
    plane_stats = [report(name, image) for name, image in zip(("plane", "zoom"), images)]

    reader = pvs.XMLPolyDataReader(FileName=[SKIN])
    skin = skin_colours(reader)
    slice_plane = pvs.Plane(Origin=[0.0, -5.0, 70.0], Point1=[200.0, -5.0, 70.0],
                            Point2=[0.0, 195.0, 70.0])
    slice_plane.XResolution = slice_plane.YResolution = max(2, args.resolution * 2 // 3)
    ct = pvs.WalkOnSpheresDiffusionCurves(Boundary=skin, Probe=slice_plane)
    ct.FrontColor = ["POINTS", "FrontColor"]
    ct.BackColor = ["POINTS", "BackColor"]
    ct.WalksPerPoint = max(2, args.walks // 2)
    ct.UpdatePipeline()
    ct_stats = report("CT slice", ct)

    layout = pvs.CreateLayout("Diffusion curves and surfaces")
    layout.SetSize(1500, 520)
    layout.SplitHorizontal(0, 1.0 / 3.0)
    layout.SplitHorizontal(2, 0.5)
    labels = [f"diffusion curves, two-sided colours and a glow\n"
              f"{plane_stats[0][0]:,} walks, {plane_stats[0][1]:.1f} s",
              f"the window [{ZOOM[0]}, {ZOOM[1]}] x [{ZOOM[2]}, {ZOOM[3]}] alone\n"
              f"{plane_stats[1][0]:,} walks, {plane_stats[1][1]:.1f} s",
              f"CT skin: air side blue-green, tissue side warm\n"
              f"slice z = 70: {ct_stats[0]:,} walks, {ct_stats[1]:.1f} s"]
    for cell, label in zip((1, 5, 6), labels):
        view = pvs.CreateView("RenderView")
        layout.AssignView(cell, view)
        view.OrientationAxesVisibility = 0
        view.UseColorPaletteForBackground = 0
        view.Background = [0.0, 0.0, 0.0]
        if cell in (1, 5):
            window = WINDOW if cell == 1 else ZOOM
            image = images[0 if cell == 1 else 1]
            display = pvs.Show(image, view)
            pvs.ColorBy(display, ("POINTS", "FrontColor_RGB"))
            display.MapScalars = 0
            drawn = pvs.Show(strokes, view)
            drawn.ColorArrayName = ["POINTS", ""]
            drawn.AmbientColor = drawn.DiffuseColor = [0.0, 0.0, 0.0]
            drawn.LineWidth = 1.5
            cx, cy = 0.5 * (window[0] + window[1]), 0.5 * (window[2] + window[3])
            view.CameraPosition = [cx, cy, 10.0]
            view.CameraFocalPoint = [cx, cy, 0.0]
            view.CameraViewUp = [0.0, 1.0, 0.0]
            view.CameraParallelProjection = 1
            view.CameraParallelScale = 0.5 * (window[3] - window[2]) * 1.12
        else:
            display = pvs.Show(ct, view)
            pvs.ColorBy(display, ("POINTS", "FrontColor_RGB"))
            display.MapScalars = 0
            surface = pvs.Show(skin, view)
            pvs.ColorBy(surface, ("POINTS", "FrontColor"))
            surface.MapScalars = 0
            surface.Opacity = 0.2
            view.CameraPosition = [99.0, -260.0, 330.0]
            view.CameraFocalPoint = [99.0, 94.0, 60.0]
            view.CameraViewUp = [0.0, 0.6, 0.8]
        title = pvs.Text(Text=label)
        title_display = pvs.Show(title, view)
        title_display.FontSize = 11
        title_display.WindowLocation = "Upper Center"
        title_display.Color = [1.0, 1.0, 1.0]
    save(layout, os.path.join(args.output, "diffusion_curves.png"), [1500, 520])


if __name__ == "__main__":
    main()
