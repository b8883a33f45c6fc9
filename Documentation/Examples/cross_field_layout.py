"""Cross fields and quad layouts without a mesh (paper Sec. 6.5, Fig. 19):
for three domains, the boundary-aligned cross field drawn as crosses, its
singularities (coloured by index: +1 three-armed, -1 five-armed) and the
separatrices traced from them.

Run with pvbatch under xvfb (the GridFree plugin loads through
PV_PLUGIN_PATH, which `./gridfree env` prints):

    pvbatch cross_field_layout.py --output Documentation/Images

Writes cross_field_layout.png and prints, per domain, the singularities,
separatrices, walks and seconds.
"""
import argparse
import math
import os
import sys

import paraview.simple as pvs
from example_pictures import closed_polyline, producer, save
from paraview import servermanager
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkPolyData


def trefoil(t):
    r = 1.0 + 0.22 * math.cos(3.0 * t)
    return (r * math.cos(t), r * math.sin(t))


def regular(sides):
    return [(math.cos(2 * math.pi * k / sides + math.pi / 2),
             math.sin(2 * math.pi * k / sides + math.pi / 2)) for k in range(sides)]


# Name, vertices of the closed boundary, walks per search estimate (a smooth
# boundary's singularities are weaker and need more).
DOMAINS = [
    ("triangle", regular(3), 1024),
    ("pentagon", regular(5), 1024),
    ("trefoil", [trefoil(2 * math.pi * k / 512) for k in range(512)], 2048),
]


def parse_arguments():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", default="output", help="folder for the picture")
    parser.add_argument("--crosses", type=int, default=22, help="crosses per side of the box")
    parser.add_argument("--walks", type=int, default=256, help="walks per cross")
    parser.add_argument("--search-scale", type=float, default=1.0,
                        help="factor on the walks per search estimate")
    return parser.parse_args()


def inside(vertices, x, y):
    """Even-odd rule."""
    result = False
    for (x0, y0), (x1, y1) in zip(vertices, vertices[1:] + vertices[:1]):
        if (y0 > y) != (y1 > y) and x0 + (y - y0) / (y1 - y0) * (x1 - x0) > x:
            result = not result
    return result


def interior_points(vertices, count):
    """A lattice of points inside the boundary, away from it."""
    xs = [v[0] for v in vertices]
    ys = [v[1] for v in vertices]
    points = vtkPoints()
    for j in range(count):
        for i in range(count):
            x = min(xs) + (max(xs) - min(xs)) * (i + 0.5) / count
            y = min(ys) + (max(ys) - min(ys)) * (j + 0.5) / count
            near = any(inside(vertices, x + dx, y + dy) is False
                       for dx, dy in ((0.04, 0), (-0.04, 0), (0, 0.04), (0, -0.04)))
            if inside(vertices, x, y) and not near:
                points.InsertNextPoint(x, y, 0.0)
    cloud = vtkPolyData()
    cloud.SetPoints(points)
    return cloud


def main():
    args = parse_arguments()
    if not hasattr(pvs, "WalkOnSpheresCrossField"):
        sys.exit("GridFree plugin not loaded (PV_PLUGIN_PATH)")
    os.makedirs(args.output, exist_ok=True)
    layout = pvs.CreateLayout("Cross fields")
    layout.SetSize(1500, 540)
    layout.SplitHorizontal(0, 1.0 / 3.0)
    layout.SplitHorizontal(2, 0.5)
    for cell, (name, vertices, search_walks) in zip((1, 5, 6), DOMAINS):
        curve = producer(closed_polyline(vertices))
        probe = producer(interior_points(vertices, args.crosses))
        field = pvs.WalkOnSpheresCrossField(Boundary=curve, Probe=probe)
        field.WalksPerPoint = args.walks
        field.SearchWalksPerPoint = max(2, int(search_walks * args.search_scale))
        field.Seed = 3
        field.UpdatePipeline()
        crosses = servermanager.Fetch(field, idx=0)
        found = servermanager.Fetch(field, idx=1)
        lines = servermanager.Fetch(field, idx=2)
        walks = int(crosses.GetFieldData().GetArray("TotalWalks").GetValue(0))
        seconds = crosses.GetFieldData().GetArray("SolveSeconds").GetValue(0)
        indices = [found.GetPointData().GetArray("Index").GetValue(i)
                   for i in range(found.GetNumberOfPoints())]
        print(f"{name}: singularities {indices} (sum {sum(indices)}), "
              f"separatrices {lines.GetNumberOfCells()}, walks {walks}, seconds {seconds:.1f}")

        view = pvs.CreateView("RenderView")
        layout.AssignView(cell, view)
        view.OrientationAxesVisibility = 0
        view.Background = [1.0, 1.0, 1.0]
        view.UseColorPaletteForBackground = 0
        glyphs = pvs.Glyph(Input=OutputPort(field, 0), GlyphType="2D Glyph")
        glyphs.GlyphType.GlyphType = "Cross"
        glyphs.OrientationArray = ["POINTS", "CrossDirection1"]
        glyphs.ScaleArray = ["POINTS", "No scale array"]
        glyphs.ScaleFactor = 1.6 / args.crosses
        glyphs.GlyphMode = "All Points"
        glyph_display = pvs.Show(glyphs, view)
        glyph_display.ColorArrayName = ["POINTS", ""]
        glyph_display.AmbientColor = glyph_display.DiffuseColor = [0.45, 0.45, 0.5]
        separatrices = pvs.Show(OutputPort(field, 2), view)
        separatrices.ColorArrayName = ["POINTS", ""]
        separatrices.AmbientColor = separatrices.DiffuseColor = [0.85, 0.15, 0.1]
        separatrices.LineWidth = 4.0
        # Singularities in fixed colours by the sign of their index: blue
        # for positive (three-armed), green for negative (five-armed).
        for lower, upper, colour in ((0.5, 1e9, [0.15, 0.2, 0.75]),
                                     (-1e9, -0.5, [0.1, 0.6, 0.2])):
            kept = pvs.Threshold(Input=OutputPort(field, 1), Scalars=["POINTS", "Index"],
                                 LowerThreshold=lower, UpperThreshold=upper)
            # Lifted towards the camera so the separatrices do not cover them.
            lifted = pvs.Transform(Input=kept)
            lifted.Transform.Translate = [0.0, 0.0, 0.01]
            points = pvs.Show(lifted, view)
            points.SetRepresentationType("Points")
            points.ColorArrayName = ["POINTS", ""]
            points.AmbientColor = points.DiffuseColor = colour
            points.PointSize = 16.0
            points.RenderPointsAsSpheres = 1
        outline = pvs.Show(curve, view)
        outline.ColorArrayName = ["POINTS", ""]
        outline.AmbientColor = outline.DiffuseColor = [0.1, 0.1, 0.1]
        outline.LineWidth = 3.0
        title = pvs.Text(Text=f"{name}: indices {', '.join('%+d' % i for i in indices)}\n"
                         f"{walks:,} walks, {seconds:.1f} s")
        title_display = pvs.Show(title, view)
        title_display.FontSize = 11
        title_display.Color = [0.0, 0.0, 0.0]
        title_display.WindowLocation = "Upper Center"
        view.CameraPosition = [0.0, -0.05, 6.0]
        view.CameraFocalPoint = [0.0, -0.05, 0.0]
        view.CameraViewUp = [0.0, 1.0, 0.0]
        view.CameraParallelProjection = 1
        view.CameraParallelScale = 1.45
    save(layout, os.path.join(args.output, "cross_field_layout.png"), [1500, 540])


OutputPort = pvs.OutputPort

if __name__ == "__main__":
    main()
