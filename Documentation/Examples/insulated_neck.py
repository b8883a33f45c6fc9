"""GridFree demo: a CT-scanned head whose neck cut is insulated, solved by
walk on stars (mixed Dirichlet and Neumann conditions), with no volume mesh.

Run with pvbatch (the GridFree plugin loads through PV_PLUGIN_PATH, which
`./gridfree demo` sets):

    pvbatch insulated_neck.py --data Data/headsq_skin_iso500_closed.vtp --output output

The skin of the classic VTK "headsq" CT scan is closed at the bottom by a
flat cap where the scan was cut. Giving that cap a temperature, as the
Dirichlet demo does, invents a boundary that is not there. Here the cap is
insulated instead (no heat flows through it, the Neumann condition
dT/dn = 0), and the skin keeps its temperature T(x, y, z): a point
Calculator marks the cap's points (bc = 1, Neumann) and the rest of the
skin (bc = 0, Dirichlet), and the Walk On Spheres Solver's Mixed Boundary
Conditions use that array. Both problems are solved on the same vertical
slice through the head, with the gradient (a first ball clear of the whole
boundary, then walk on stars), at the slice's points inside the head only
(outside it, both problems would be answered too: by the exterior problem,
which says nothing about the head).
Writes into the output folder:
  neck_slice.vtp   the slice with T (insulated neck), T_Variance, T_Gradient
                   and T_Dirichlet (the whole skin at T, for comparison)
  neck_slice.png   both solutions side by side with their isotherms, and on
                   the insulated one ParaView's streamlines and arrows of
                   T_Gradient: with the neck insulated, isotherms meet the
                   cut at right angles and heat flows along it, not through
and prints points, walks, seconds, how much the neck's temperature moved
and the gradient across the cut just above it in both problems.
"""
import argparse
import math
import os
import sys

import paraview.simple as pvs
from paraview import servermanager
from vtkmodules.vtkFiltersCore import vtkThreshold
from vtkmodules.vtkFiltersModeling import vtkSelectEnclosedPoints
from paraview.simple import (
    Calculator, ColorBy, Contour, CreateLayout, CreateView, GetColorTransferFunction,
    GetScalarBar, Plane, SaveData, SaveScreenshot, Show, Slice, XMLPolyDataReader)

# Boundary temperature in degrees, a smooth function of position (mm): the
# same as head_ct_demo.py's.
TEMPERATURE = "20 + 10*sin(0.04*coordsX)*cos(0.03*coordsY) + 0.1*coordsZ"
# The cap closing the scan lies in the plane z = zmin; its points are within
# this distance of it (mm), the skin's are not.
CAP_THICKNESS = 0.5


def parse_arguments():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", required=True, help="closed skin surface (.vtp)")
    parser.add_argument("--output", default="output", help="folder for the results")
    parser.add_argument("--walks", type=int, default=256, help="walks per point")
    parser.add_argument("--resolution", type=int, default=100,
                        help="slice points along its longer side")
    parser.add_argument("--seed", type=int, default=0)
    return parser.parse_args()


def field_value(proxy, name):
    return proxy.FieldData[name].GetRange()[0]


def cells_inside(plane, skin):
    """The plane's cells whose points all lie inside the closed skin, as a
    pipeline source: the probe. (Points outside would get the exterior
    problem's answers, as walk on spheres gives them.) VTK's
    vtkSelectEnclosedPoints in this process, so pvbatch runs it (a
    Programmable Filter would import numpy's max, sum, ... into the script)."""
    select = vtkSelectEnclosedPoints()
    select.SetInputData(servermanager.Fetch(plane))
    select.SetSurfaceData(servermanager.Fetch(skin))
    inside = vtkThreshold()
    inside.SetInputConnection(select.GetOutputPort())
    inside.SetInputArrayToProcess(0, 0, 0, 0, "SelectedPoints")
    inside.SetLowerThreshold(0.5)
    inside.SetUpperThreshold(1.5)
    inside.AllScalarsOn()
    inside.Update()
    probe = pvs.TrivialProducer(registrationName="SliceInsideHead")
    probe.GetClientSideObject().SetOutput(inside.GetOutput())
    probe.UpdatePipeline()
    return probe


def main():
    args = parse_arguments()
    os.makedirs(args.output, exist_ok=True)
    if not hasattr(pvs, "WalkOnSpheresSolver"):
        sys.exit("The GridFree plugin is not loaded: set PV_PLUGIN_PATH to its folder "
                 "(`./gridfree env` prints it).")

    skin = XMLPolyDataReader(FileName=[args.data])
    skin.UpdatePipeline()
    (xmin, xmax, ymin, ymax, zmin, zmax) = skin.GetDataInformation().GetBounds()
    temperature = Calculator(Input=skin, ResultArrayName="T", Function=TEMPERATURE)
    # 1 (Neumann) on the cap's points, 0 (Dirichlet) elsewhere: a triangle is
    # Neumann where all its points are.
    boundary = Calculator(Input=temperature, ResultArrayName="bc",
                          Function=f"(coordsZ < {zmin + CAP_THICKNESS})")

    # A vertical (sagittal) slice through the middle of the head, a little
    # larger than it.
    xmid = 0.5 * (xmin + xmax)
    margin = 0.04 * (zmax - zmin)
    width, height = (ymax - ymin) + 2 * margin, (zmax - zmin) + 2 * margin
    steps = args.resolution - 1
    plane = Plane(Origin=[xmid, ymin - margin, zmin - margin],
                  Point1=[xmid, ymax + margin, zmin - margin],
                  Point2=[xmid, ymin - margin, zmax + margin],
                  XResolution=steps, YResolution=max(1, round(steps * height / width)))
    probe = cells_inside(plane, skin)

    insulated = pvs.WalkOnSpheresSolver(Boundary=boundary, Probe=probe)
    insulated.BoundaryValues = ["POINTS", "T"]
    insulated.MixedBoundaryConditions = 1
    insulated.BoundaryConditionArray = ["POINTS", "bc"]
    # No flux (insulated) and no Robin cells: said explicitly, for from a
    # script the array properties default to the active source's scalars.
    insulated.NeumannFluxArray = ["POINTS", "None"]
    insulated.RobinCoefficientArray = ["POINTS", "None"]
    insulated.ComputeGradient = 1
    insulated.WalksPerPoint = args.walks
    insulated.Seed = args.seed
    insulated.UpdatePipeline()

    dirichlet = pvs.WalkOnSpheresSolver(Boundary=temperature, Probe=probe)
    dirichlet.BoundaryValues = ["POINTS", "T"]
    dirichlet.ComputeGradient = 1
    dirichlet.WalksPerPoint = args.walks
    dirichlet.Seed = args.seed
    dirichlet.UpdatePipeline()

    points = int(field_value(insulated, "ProbePoints"))
    walks = int(field_value(insulated, "TotalWalks"))
    seconds = field_value(insulated, "SolveSeconds")
    print(f"points inside the head: {points}")
    print(f"walks: {walks}, {seconds:.2f} s, "
          f"{walks / max(seconds, 1e-9):.0f} walks per second")
    print(f"walks that met the neck from outside: {int(field_value(insulated, 'BackFaceHits'))}")

    # One dataset with both solutions, and what insulation changed near the
    # neck (the lowest fifth of the head) and above it.
    data = servermanager.Fetch(insulated)
    reference = servermanager.Fetch(dirichlet)
    t_ins = data.GetPointData().GetArray("T")
    t_dir = reference.GetPointData().GetArray("T")
    near, far = [], []
    for i in range(data.GetNumberOfPoints()):
        a, b = t_ins.GetValue(i), t_dir.GetValue(i)
        if math.isnan(a) or math.isnan(b):
            continue
        z = data.GetPoint(i)[2]
        (near if z < zmin + 0.2 * (zmax - zmin) else far).append(abs(a - b))
    if near and far:
        print(f"mean |T_insulated - T_dirichlet|: {sum(near) / len(near):.3f} degrees near the "
              f"neck, {sum(far) / len(far):.3f} above it")
    # dT/dz just above the cut (a band 1 to 4 mm above it): heat crossing
    # it. Insulated, it falls towards 0 at the cut; at a fixed temperature,
    # it does not. (Points with no gradient, outside the head, have
    # T_Gradient 0 and a NaN variance.)
    for name, solved in (("insulated", data), ("Dirichlet", reference)):
        gradient = solved.GetPointData().GetArray("T_Gradient")
        variance = solved.GetPointData().GetArray("T_Gradient_Variance")
        band = [i for i in range(solved.GetNumberOfPoints())
                if zmin + 1.0 <= solved.GetPoint(i)[2] <= zmin + 4.0
                and not math.isnan(variance.GetComponent(i, 2))]
        if band:
            mean = sum(gradient.GetComponent(i, 2) for i in band) / len(band)
            error = math.sqrt(sum(variance.GetComponent(i, 2) for i in band)) / len(band)
            print(f"dT/dz 1-4 mm above the cut, {name}: {mean:+.4f} +- {error:.4f} degrees/mm "
                  f"(mean of {len(band)} points)")
    sys.stdout.flush()

    renamed = pvs.Calculator(Input=dirichlet, ResultArrayName="T_Dirichlet", Function="T")
    output = pvs.AppendAttributes(Input=[insulated, pvs.PassArrays(
        Input=renamed, PointDataArrays=["T_Dirichlet"])])
    # Inline (base64) binary: Debian 12's patched expat makes ParaView 5.11
    # reject appended raw data on reading.
    # (The probe's cells came through a threshold: back to polygons.)
    SaveData(os.path.join(args.output, "neck_slice.vtp"), proxy=pvs.ExtractSurface(Input=output),
             DataMode="Binary", CompressorType="ZLib")

    # Both solutions side by side inside the head, with isotherms, the skin's
    # outline (white) and the insulated cap (green).
    inside = pvs.Threshold(Input=output, Scalars=["POINTS", "T"],
                           LowerThreshold=-1e30, UpperThreshold=1e30)
    # The insulated problem's heat flow: lines of T_Gradient within the
    # slice (ParaView's own tracer, both directions) from every 80th point
    # inside, and arrows of one length on every 15th, as in the CT workflow.
    seeds = pvs.MaskPoints(Input=inside, OnRatio=80, MaximumNumberofPoints=100000,
                           GenerateVertices=1, SingleVertexPerCell=1)
    streamlines = pvs.StreamTracerWithCustomSource(Input=inside, SeedSource=seeds)
    streamlines.Vectors = ["POINTS", "T_Gradient"]
    streamlines.SurfaceStreamlines = 1
    streamlines.IntegrationDirection = "BOTH"
    streamlines.MaximumStreamlineLength = zmax - zmin
    # Arrows of the gradient's part in the slice (its x part points out of
    # the picture).
    in_slice = pvs.Calculator(Input=inside, ResultArrayName="T_Gradient_InSlice",
                              Function="T_Gradient_Y*jHat + T_Gradient_Z*kHat")
    arrows = pvs.Glyph(Input=in_slice, GlyphType="Arrow")
    arrows.OrientationArray = ["POINTS", "T_Gradient_InSlice"]
    arrows.ScaleArray = ["POINTS", "No scale array"]
    arrows.ScaleFactor = 3.0 * width / max(1, steps)
    arrows.GlyphMode = "Every Nth Point"
    arrows.Stride = 15
    cut = [xmid, 0.5 * (ymin + ymax), 0.5 * (zmin + zmax)]
    outlines = []
    for source, colour in ((skin, [1.0, 1.0, 1.0]),
                           (pvs.Threshold(Input=boundary, Scalars=["POINTS", "bc"],
                                          LowerThreshold=0.5, UpperThreshold=1.5,
                                          AllScalars=1), [0.2, 1.0, 0.3])):
        section = Slice(Input=source)
        section.SliceType = "Plane"
        section.SliceType.Origin = cut
        section.SliceType.Normal = [1.0, 0.0, 0.0]
        outlines.append((section, colour))
    layout = CreateLayout("Insulated neck")
    layout.SplitHorizontal(0, 0.5)
    ranges = [s.PointData["T"].GetRange() for s in (insulated, dirichlet)]
    low, high = min(r[0] for r in ranges), max(r[1] for r in ranges)
    panels = [("T_Dirichlet", "T: the whole skin at T (Dirichlet)"),
              ("T", "T: the neck's cut insulated (Neumann)")]
    for cell, (array, title) in zip((1, 2), panels):
        view = CreateView("RenderView")
        layout.AssignView(cell, view)
        view.OrientationAxesVisibility = 0
        display = Show(inside, view)
        ColorBy(display, ("POINTS", array))
        lut = GetColorTransferFunction(array)
        lut.ApplyPreset("Inferno (matplotlib)", True)
        lut.RescaleTransferFunction(low, high)
        display.SetScalarBarVisibility(view, True)
        bar = GetScalarBar(lut, view)
        bar.Title = title
        bar.ComponentTitle = ""
        bar.WindowLocation = "Upper Center"
        bar.Orientation = "Horizontal"
        bar.LabelFormat = "%-#.3g"
        bar.RangeLabelFormat = "%-#.3g"
        isotherms = Contour(Input=inside, ContourBy=["POINTS", array],
                            Isosurfaces=[14.0 + 2.0 * k for k in range(14)])
        lines = Show(isotherms, view)
        lines.ColorArrayName = ["POINTS", ""]
        lines.AmbientColor = lines.DiffuseColor = [0.3, 0.8, 1.0]
        lines.LineWidth = 1.5
        if array == "T":
            for flow, colour in ((streamlines, [0.9, 0.9, 0.9]), (arrows, [0.6, 1.0, 0.6])):
                shown = Show(flow, view)
                shown.ColorArrayName = ["POINTS", ""]
                shown.AmbientColor = shown.DiffuseColor = colour
        for section, colour in outlines:
            outline = Show(section, view)
            outline.ColorArrayName = ["POINTS", ""]
            outline.AmbientColor = outline.DiffuseColor = colour
            outline.LineWidth = 3.0
        view.CameraFocalPoint = cut
        view.CameraPosition = [xmax + 4.0 * (xmax - xmin), cut[1], cut[2]]
        view.CameraViewUp = [0.0, 0.0, 1.0]
        view.ResetCamera(False)

    picture = os.path.join(args.output, "neck_slice.png")
    for _ in range(2):
        if SaveScreenshot(picture, layout, ImageResolution=[1280, 640]) and \
                os.path.isfile(picture) and os.path.getsize(picture) > 0:
            break
    else:
        sys.exit(f"could not write {picture}")
    print(f"wrote {os.path.join(args.output, 'neck_slice.vtp')} and {picture}")


if __name__ == "__main__":
    main()
