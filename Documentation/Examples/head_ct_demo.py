"""GridFree demo: a steady temperature inside a CT-scanned head, solved on a
slice by walk on spheres, with no volume mesh.

Run with pvbatch (the GridFree plugin loads through PV_PLUGIN_PATH, which
`./gridfree demo` sets):

    pvbatch head_ct_demo.py --data Data/headsq_skin_iso500_closed.vtp --output output

The skin surface extracted from the classic VTK "headsq" CT scan carries a
smooth boundary temperature T(x, y, z). The Walk On Spheres Solver estimates
the harmonic temperature inside at every point of a horizontal slice through
the head (points outside the skin solve the exterior problem, which decays
to 0 far away). Writes into the output folder:
  head_slice.vtp        the slice with T, T_Variance, WalkSteps, EscapedFraction
  head_slice.png        the solution and its variance side by side
and prints points, walks, seconds and walks per second.
"""
import argparse
import os
import sys

import paraview.simple as pvs
from paraview.simple import (
    Calculator, ColorBy, CreateLayout, CreateView, GetColorTransferFunction,
    GetScalarBar, Plane, SaveData, SaveScreenshot, Show, Slice, XMLPolyDataReader)

# Boundary temperature in degrees, a smooth function of position (mm).
TEMPERATURE = "20 + 10*sin(0.04*coordsX)*cos(0.03*coordsY) + 0.1*coordsZ"


def parse_arguments():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", required=True, help="skin surface (.vtp)")
    parser.add_argument("--output", default="output", help="folder for the results")
    parser.add_argument("--walks", type=int, default=64, help="walks per point")
    parser.add_argument("--resolution", type=int, default=200,
                        help="slice points along each side")
    parser.add_argument("--seed", type=int, default=0)
    return parser.parse_args()


def temperature_and_slice(data, resolution):
    """The skin surface, the skin carrying TEMPERATURE as the point array T,
    a horizontal slice through the middle of the head, a little larger than
    it, with `resolution` points along each side, and the skin's bounds
    (also used by ct_slice_gallery.py)."""
    skin = XMLPolyDataReader(FileName=[data])
    boundary = Calculator(Input=skin, ResultArrayName="T", Function=TEMPERATURE)
    boundary.UpdatePipeline()
    (xmin, xmax, ymin, ymax, zmin, zmax) = boundary.GetDataInformation().GetBounds()
    margin = 0.05 * (xmax - xmin)
    zmid = 0.5 * (zmin + zmax)
    probe = Plane(Origin=[xmin - margin, ymin - margin, zmid],
                  Point1=[xmax + margin, ymin - margin, zmid],
                  Point2=[xmin - margin, ymax + margin, zmid],
                  XResolution=resolution - 1, YResolution=resolution - 1)
    return skin, boundary, probe, (xmin, xmax, ymin, ymax, zmin, zmax)


def main():
    args = parse_arguments()
    os.makedirs(args.output, exist_ok=True)

    skin, boundary, probe, bounds = temperature_and_slice(args.data, args.resolution)
    (xmin, xmax, ymin, ymax, zmin, zmax) = bounds
    zmid = 0.5 * (zmin + zmax)

    if not hasattr(pvs, "WalkOnSpheresSolver"):
        sys.exit("The GridFree plugin is not loaded: set PV_PLUGIN_PATH to its folder "
                 "(`./gridfree env` prints it).")
    solver = pvs.WalkOnSpheresSolver(Boundary=boundary, Probe=probe)
    solver.BoundaryValues = ["POINTS", "T"]
    solver.WalksPerPoint = args.walks
    solver.Seed = args.seed
    solver.UpdatePipeline()

    # The solver's run summary travels with the data as field arrays.
    points = solver.GetDataInformation().GetNumberOfPoints()
    walks = int(solver.FieldData["TotalWalks"].GetRange()[0])
    seconds = solver.FieldData["SolveSeconds"].GetRange()[0]
    escaped = int(solver.FieldData["EscapedWalks"].GetRange()[0])
    print(f"points: {points}")
    print(f"walks: {walks} ({args.walks} per point; {escaped} left the head, exterior problem)")
    print(f"seconds: {seconds:.2f}")
    print(f"walks per second: {walks / seconds:.0f}")
    sys.stdout.flush()

    # Inline (base64) binary rather than VTK's default appended raw data: Debian
    # 12's patched expat makes ParaView 5.11 reject appended raw data on reading.
    SaveData(os.path.join(args.output, "head_slice.vtp"), proxy=solver,
             DataMode="Binary", CompressorType="ZLib")

    # Solution and variance side by side, each with the skin's cross-section.
    contour = Slice(Input=skin)
    contour.SliceType = "Plane"
    contour.SliceType.Origin = [0.5 * (xmin + xmax), 0.5 * (ymin + ymax), zmid]
    contour.SliceType.Normal = [0.0, 0.0, 1.0]
    layout = CreateLayout("GridFree demo")
    layout.SplitHorizontal(0, 0.5)
    center = [0.5 * (xmin + xmax), 0.5 * (ymin + ymax), zmid]
    panels = [("T", "Inferno (matplotlib)", "T"),
              ("T_Variance", "Viridis (matplotlib)", "Var[T]")]
    for cell, (array, preset, title) in zip((1, 2), panels):
        view = CreateView("RenderView")
        layout.AssignView(cell, view)
        view.OrientationAxesVisibility = 0
        slice_display = Show(solver, view)
        ColorBy(slice_display, ("POINTS", array))
        lut = GetColorTransferFunction(array)
        lut.ApplyPreset(preset, True)
        slice_display.RescaleTransferFunctionToDataRange(False, True)
        slice_display.SetScalarBarVisibility(view, True)
        bar = GetScalarBar(lut, view)
        bar.WindowLocation = "Any Location"
        bar.Position = [0.78, 0.1]
        bar.ScalarBarLength = 0.8
        bar.Title = title
        bar.HorizontalTitle = 1
        bar.ComponentTitle = ""
        bar.AutomaticLabelFormat = 0
        bar.LabelFormat = "%-#.3g"
        bar.RangeLabelFormat = "%-#.3g"
        outline = Show(contour, view)
        outline.AmbientColor = outline.DiffuseColor = [1.0, 1.0, 1.0]
        outline.LineWidth = 2.0
        view.CameraFocalPoint = center
        view.CameraPosition = [center[0], center[1], zmax + 4.0 * (zmax - zmin)]
        view.CameraViewUp = [0.0, 1.0, 0.0]
        view.ResetCamera(False)
        view.CameraPosition = [center[0] + 0.12 * (xmax - xmin), center[1],
                               view.CameraPosition[2]]
        view.CameraFocalPoint = [center[0] + 0.12 * (xmax - xmin), center[1], zmid]

    picture = os.path.join(args.output, "head_slice.png")
    # An X server that is slow to come up under load can lose the first
    # render: try again once, and fail loudly rather than leave no picture.
    for _ in range(2):
        if SaveScreenshot(picture, layout, ImageResolution=[1280, 600]) and \
                os.path.isfile(picture) and os.path.getsize(picture) > 0:
            break
    else:
        sys.exit(f"could not write {picture}")
    print(f"wrote {os.path.join(args.output, 'head_slice.vtp')} and {picture}")


if __name__ == "__main__":
    main()
