"""2D shape deformation by a biharmonic map, without a mesh (paper Sec. 6.7,
Fig. 22): a checkerboard image inside a bar is carried along when the bar's
outline is bent into an arc. Left: the source outline and the image; right:
the target outline and the image warped through the map.

Run with pvbatch under xvfb (the GridFree plugin loads through
PV_PLUGIN_PATH, which `./gridfree env` prints):

    pvbatch shape_deformation.py --output Documentation/Images

Writes shape_deformation.png and prints the points, walks and seconds.
"""
import argparse
import math
import os
import sys

import paraview.simple as pvs
from example_pictures import closed_polyline, producer, save
from paraview import servermanager
from vtkmodules.vtkCommonCore import vtkDoubleArray
from vtkmodules.vtkCommonDataModel import vtkImageData

HALF_LENGTH, HALF_WIDTH, BEND_RADIUS = 1.5, 0.45, 1.6


def bend(x, y):
    """The target: the bar bent around a circle (x along it, y across)."""
    angle = x / BEND_RADIUS
    r = BEND_RADIUS + y
    return (r * math.sin(angle), r * math.cos(angle) - BEND_RADIUS)


def parse_arguments():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", default="output", help="folder for the picture")
    parser.add_argument("--resolution", type=int, default=30, help="image points across the bar")
    parser.add_argument("--walks", type=int, default=4096, help="walks per image point")
    return parser.parse_args()


def outline(step=0.05):
    """The bar's boundary, counter-clockwise, about `step` apart."""
    corners = [(-HALF_LENGTH, -HALF_WIDTH), (HALF_LENGTH, -HALF_WIDTH),
               (HALF_LENGTH, HALF_WIDTH), (-HALF_LENGTH, HALF_WIDTH)]
    vertices = []
    for k in range(4):
        (x0, y0), (x1, y1) = corners[k], corners[(k + 1) % 4]
        pieces = max(1, round(math.hypot(x1 - x0, y1 - y0) / step))
        vertices += [(x0 + (x1 - x0) * s / pieces, y0 + (y1 - y0) * s / pieces)
                     for s in range(pieces)]
    return vertices


def checkerboard(resolution):
    """An image filling the bar, with a checkerboard of squares 0.15 wide."""
    image = vtkImageData()
    across = resolution
    along = round(resolution * HALF_LENGTH / HALF_WIDTH)
    image.SetDimensions(along, across, 1)
    image.SetOrigin(-HALF_LENGTH, -HALF_WIDTH, 0.0)
    image.SetSpacing(2 * HALF_LENGTH / (along - 1), 2 * HALF_WIDTH / (across - 1), 1.0)
    checker = vtkDoubleArray()
    checker.SetName("Checker")
    for i in range(image.GetNumberOfPoints()):
        x, y, _ = image.GetPoint(i)
        checker.InsertNextValue((math.floor(x / 0.15) + math.floor(y / 0.15)) % 2)
    image.GetPointData().SetScalars(checker)
    return image


def main():
    args = parse_arguments()
    if not hasattr(pvs, "WalkOnSpheresDeformation"):
        sys.exit("GridFree plugin not loaded (PV_PLUGIN_PATH)")
    os.makedirs(args.output, exist_ok=True)
    vertices = outline()
    source = producer(closed_polyline(vertices))
    target = producer(closed_polyline([bend(x, y) for x, y in vertices]))
    image = producer(checkerboard(args.resolution))
    warp = pvs.WalkOnSpheresDeformation(Source=source, Probe=image, Target=target)
    warp.WalksPerPoint = args.walks
    warp.Seed = 1
    warp.UpdatePipeline()
    data = servermanager.Fetch(warp)
    walks = int(data.GetFieldData().GetArray("TotalWalks").GetValue(0))
    seconds = data.GetFieldData().GetArray("SolveSeconds").GetValue(0)
    print(f"points {data.GetNumberOfPoints()}, walks {walks}, seconds {seconds:.1f}, "
          f"walks/s {walks / max(seconds, 1e-9):.0f}")

    layout = pvs.CreateLayout("Shape deformation")
    layout.SetSize(1400, 560)
    layout.SplitHorizontal(0, 0.5)
    lut = pvs.GetColorTransferFunction("Checker")
    lut.ApplyPreset("Blue Orange (divergent)", True)
    lut.RescaleTransferFunction(0.0, 1.0)
    lut.AutomaticRescaleRangeMode = "Never"
    panels = [(1, image, source, "source: the bar and its image"),
              (2, warp, target, f"target: the bar bent, the image warped\n"
                                f"{walks:,} walks, {seconds:.1f} s")]
    for cell, data_proxy, curve, label in panels:
        view = pvs.CreateView("RenderView")
        layout.AssignView(cell, view)
        view.OrientationAxesVisibility = 0
        display = pvs.Show(data_proxy, view)
        pvs.ColorBy(display, ("POINTS", "Checker"))
        display.LookupTable = lut
        line = pvs.Show(curve, view)
        line.ColorArrayName = ["POINTS", ""]
        line.AmbientColor = line.DiffuseColor = [1.0, 1.0, 1.0]
        line.LineWidth = 3.0
        title = pvs.Text(Text=label)
        title_display = pvs.Show(title, view)
        title_display.FontSize = 12
        title_display.WindowLocation = "Upper Center"
        view.CameraPosition = [0.0, -0.2, 6.0]
        view.CameraFocalPoint = [0.0, -0.2, 0.0]
        view.CameraViewUp = [0.0, 1.0, 0.0]
        view.CameraParallelProjection = 1
        view.CameraParallelScale = 1.25
    save(layout, os.path.join(args.output, "shape_deformation.png"), [1400, 560])


if __name__ == "__main__":
    main()
