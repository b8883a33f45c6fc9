"""Helmholtz-Hodge decomposition of a 2D vector field inside a curved
boundary, without a mesh of the domain (paper Sec. 6.6, Fig. 20): the field
X, given in closed form, and its curl-free, divergence-free and harmonic
parts, each coloured by its magnitude with arrows along it.

Run with pvbatch under xvfb (the GridFree plugin loads through
PV_PLUGIN_PATH, which `./gridfree env` prints):

    pvbatch helmholtz_decomposition.py --output Documentation/Images

Writes helmholtz_decomposition.png and prints the points, walks and seconds.
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
from vtkmodules.vtkFiltersCore import vtkThreshold

# A rotation, an expansion with a local sink, and a wavy uniform flow, mixed.
FIELD = ("(-y + 0.9*x + 0.6 + 0.4*sin(3*y))*iHat"
         " + (x + 0.9*y + 0.3*cos(2*x) - 1.5*exp(-6*((x-0.3)^2 + (y+0.2)^2)))*jHat")


def radius(theta):
    """The boundary r(theta): a rounded trefoil."""
    return 1.0 + 0.22 * math.cos(3.0 * theta)


def parse_arguments():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", default="output", help="folder for the picture")
    parser.add_argument("--resolution", type=int, default=80, help="probe points per side")
    parser.add_argument("--walks", type=int, default=256, help="walks per point and potential")
    return parser.parse_args()


def boundary_curve(sides=720):
    vertices = []
    for k in range(sides):
        theta = 2.0 * math.pi * k / sides
        vertices.append((radius(theta) * math.cos(theta), radius(theta) * math.sin(theta)))
    return closed_polyline(vertices)


def interior_probe(resolution):
    """The pixels of an image over the domain whose corners are all inside."""
    image = vtkImageData()
    image.SetDimensions(resolution, resolution, 1)
    spacing = 2.5 / (resolution - 1)
    image.SetOrigin(-1.25, -1.25, 0.0)
    image.SetSpacing(spacing, spacing, 1.0)
    inside = vtkDoubleArray()
    inside.SetName("Inside")
    for i in range(image.GetNumberOfPoints()):
        x, y, _ = image.GetPoint(i)
        margin = radius(math.atan2(y, x)) - math.hypot(x, y)
        inside.InsertNextValue(1.0 if margin > 0.01 else 0.0)
    image.GetPointData().AddArray(inside)
    threshold = vtkThreshold()
    threshold.SetInputData(image)
    threshold.SetInputArrayToProcess(0, 0, 0, 0, "Inside")
    threshold.SetLowerThreshold(0.5)
    threshold.SetUpperThreshold(1.5)
    threshold.AllScalarsOn()
    threshold.Update()
    return threshold.GetOutput()


def main():
    args = parse_arguments()
    if not hasattr(pvs, "WalkOnSpheresHelmholtzDecomposition"):
        sys.exit("GridFree plugin not loaded (PV_PLUGIN_PATH)")
    os.makedirs(args.output, exist_ok=True)
    curve = producer(boundary_curve())
    probe = producer(interior_probe(args.resolution))
    helmholtz = pvs.WalkOnSpheresHelmholtzDecomposition(Boundary=curve, Probe=probe)
    helmholtz.FieldExpression = FIELD
    helmholtz.WalksPerPoint = args.walks
    helmholtz.Seed = 1
    helmholtz.UpdatePipeline()
    data = servermanager.Fetch(helmholtz)
    walks = int(data.GetFieldData().GetArray("TotalWalks").GetValue(0))
    seconds = data.GetFieldData().GetArray("SolveSeconds").GetValue(0)
    points = data.GetNumberOfPoints()
    print(f"points {points}, walks {walks}, seconds {seconds:.1f}, "
          f"walks/s {walks / max(seconds, 1e-9):.0f}")
    largest = max(data.GetPointData().GetArray("X").GetRange(-1)[1], 1e-12)

    layout = pvs.CreateLayout("Helmholtz decomposition")
    layout.SetSize(1200, 1200)
    layout.SplitHorizontal(0, 0.5)
    layout.SplitVertical(1, 0.5)
    layout.SplitVertical(2, 0.5)
    panels = [("X", "X (the field)"), ("X_CurlFree", "curl-free part (grad u)"),
              ("X_DivergenceFree", "divergence-free part (J grad a)"),
              ("X_Harmonic", "harmonic part")]
    lut = pvs.GetColorTransferFunction("HelmholtzMagnitude")
    lut.ApplyPreset("Viridis (matplotlib)", True)
    lut.RescaleTransferFunction(0.0, largest)
    lut.AutomaticRescaleRangeMode = "Never"
    for cell, (name, label) in zip((3, 5, 4, 6), panels):
        view = pvs.CreateView("RenderView")
        layout.AssignView(cell, view)
        view.OrientationAxesVisibility = 0
        magnitude = pvs.Calculator(Input=helmholtz, ResultArrayName="HelmholtzMagnitude",
                                   Function=f"mag({name})")
        surface = pvs.Show(magnitude, view)
        pvs.ColorBy(surface, ("POINTS", "HelmholtzMagnitude"))
        surface.LookupTable = lut
        arrows = pvs.Glyph(Input=helmholtz, GlyphType="2D Glyph")
        arrows.GlyphType.GlyphType = "Arrow"
        arrows.OrientationArray = ["POINTS", name]
        arrows.ScaleArray = ["POINTS", name]
        arrows.ScaleFactor = 0.3 / largest
        arrows.GlyphMode = "Uniform Spatial Distribution (Bounds Based)"
        arrows.MaximumNumberOfSamplePoints = 120
        arrows.Seed = 7
        arrow_display = pvs.Show(arrows, view)
        arrow_display.ColorArrayName = ["POINTS", ""]
        arrow_display.AmbientColor = arrow_display.DiffuseColor = [1.0, 1.0, 1.0]
        outline = pvs.Show(curve, view)
        outline.ColorArrayName = ["POINTS", ""]
        outline.AmbientColor = outline.DiffuseColor = [0.9, 0.9, 0.9]
        outline.LineWidth = 2.0
        text = label if name == "X" else f"{label}\n{walks // 2:,} walks, {seconds / 2:.1f} s"
        title = pvs.Text(Text=text)
        title_display = pvs.Show(title, view)
        title_display.FontSize = 13
        title_display.WindowLocation = "Upper Center"
        view.CameraPosition = [0.0, 0.0, 6.0]
        view.CameraFocalPoint = [0.0, 0.0, 0.0]
        view.CameraViewUp = [0.0, 1.0, 0.0]
        view.ResetCamera(False)
    save(layout, os.path.join(args.output, "helmholtz_decomposition.png"), [1200, 1200])


if __name__ == "__main__":
    main()
