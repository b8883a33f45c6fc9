"""GridFree example: the temperature gradient and Hessian inside a CT-scanned
head, estimated by walk on spheres and drawn with plain VTK.

Run with the Python that sees VTK, with the `gridfree` module on PYTHONPATH
(`./gridfree env` prints it), under a display or xvfb-run:

    xvfb-run -a python3 ct_gradient_streamlines.py --walks 512 --resolution 160 \
        --output ct_gradient_streamlines.png

The skin surface of the classic VTK "headsq" CT scan carries the same smooth
boundary temperature T(x, y, z) as the pvbatch demo (head_ct_demo.py), and the
slice is the demo's: horizontal, through the middle of the head and a little
larger than it (points outside the skin solve the exterior problem). The
vtkWalkOnSpheresSolver estimates T, its gradient T_Gradient and its Hessian
T_Hessian at every slice point from the same walks. Inside the skin
(vtkSelectEnclosedPoints and vtkThreshold pick that part of the slice)
  - vtkStreamTracer follows T_Gradient within the slice (surface
    streamlines, both directions from a grid of seeds): lines of steepest
    ascent of the temperature within the slice;
  - vtkGlyph3D puts arrows, oriented and scaled by T_Gradient, on a
    subsample (vtkMaskPoints, spatially stratified with a fixed seed);
  - vtkTensorGlyph puts ellipsoids with the axes and eigenvalues of
    T_Hessian on a coarser subsample, coloured by the signed eigenvalue of
    largest magnitude (green: T curves upwards along that axis, blue:
    downwards).
The whole slice is coloured by T, and the skin above it is a faint,
translucent dome for context. Glyph sizes are relative to the slice and to
the data's percentiles.

Writes one PNG and prints points, walks and seconds. --slice FILE saves the
solved slice, and draws from FILE without solving when it exists (handy to
try other looks). The picture is the same on every run for a given --seed:
the solver's random streams depend only on the seed and the point, whatever
the number of threads, and the subsamples use fixed seeds.
"""
import argparse
import math
import os
import sys
import time

import numpy as np

import gridfree
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkLookupTable
from vtkmodules.vtkCommonDataModel import vtkDataObject, vtkPlane, vtkPolyData
from vtkmodules.vtkFiltersCore import (
    vtkArrayCalculator, vtkClipPolyData, vtkCutter, vtkGlyph3D, vtkMaskPoints, vtkTensorGlyph,
    vtkThreshold, vtkTriangleFilter)
from vtkmodules.vtkFiltersFlowPaths import vtkStreamTracer
from vtkmodules.vtkFiltersModeling import vtkSelectEnclosedPoints
from vtkmodules.vtkFiltersVerdict import vtkCellSizeFilter
from vtkmodules.vtkFiltersSources import vtkArrowSource, vtkPlaneSource, vtkSphereSource
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLPolyDataWriter
from vtkmodules.vtkRenderingAnnotation import vtkScalarBarActor
from vtkmodules.vtkRenderingCore import (
    vtkActor, vtkColorTransferFunction, vtkPolyDataMapper, vtkRenderWindow, vtkRenderer,
    vtkTextActor, vtkWindowToImageFilter)
import vtkmodules.vtkInteractionStyle  # noqa: F401  (default interactor style)
import vtkmodules.vtkRenderingFreeType  # noqa: F401  (text of the scalar bars)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (the render window)

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_DATA = os.path.join(HERE, "..", "..", "Data", "headsq_skin_iso500_closed.vtp")

# Glyph and streamline counts, and the camera (offset from the slice centre in
# slice sizes, and zoom).
STREAMLINE_SEEDS = 18
ARROWS = 320
ELLIPSOIDS = 70
CAMERA = (0.0, 1.0, 1.9)
ZOOM = 1.42
# How much of the skin above the slice to show, as a fraction of its height.
DOME_HEIGHT = 0.6

# Boundary temperature in degrees, a smooth function of position (mm): the demo's.
TEMPERATURE = "20 + 10*sin(0.04*coordsX)*cos(0.03*coordsY) + 0.1*coordsZ"


def parse_arguments():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", default=DEFAULT_DATA, help="skin surface (.vtp)")
    parser.add_argument("--output", default=os.path.join("output", "ct_gradient_streamlines.png"),
                        help="PNG to write")
    parser.add_argument("--walks", type=int, default=256, help="walks per point")
    parser.add_argument("--resolution", type=int, default=120,
                        help="slice points along each side")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--slice", help="a .vtp file for the solved slice: written after "
                        "solving, or, if it exists, read instead of solving")
    parser.add_argument("--size", type=int, nargs=2, default=(1400, 1050),
                        metavar=("WIDTH", "HEIGHT"), help="picture size in pixels")
    return parser.parse_args()


def boundary_temperature(skin_port):
    # Only the skin's triangles: the file also holds a few stray lines and vertices.
    triangles = vtkTriangleFilter()
    triangles.SetInputConnection(skin_port)
    triangles.PassVertsOff()
    triangles.PassLinesOff()
    calculator = vtkArrayCalculator()
    calculator.SetInputConnection(triangles.GetOutputPort())
    calculator.SetAttributeTypeToPointData()
    for axis, name in enumerate(("coordsX", "coordsY", "coordsZ")):
        calculator.AddCoordinateScalarVariable(name, axis)
    calculator.SetFunction(TEMPERATURE)
    calculator.SetResultArrayName("T")
    calculator.Update()
    return calculator


def percentile_or(values, q, fallback):
    values = values[np.isfinite(values)]
    return float(np.percentile(values, q)) if values.size else fallback


def dominant_eigenvalue(hessians):
    """Signed eigenvalue of largest magnitude of each symmetric 3x3 matrix."""
    matrices = hessians.reshape(-1, 3, 3)
    matrices = 0.5 * (matrices + matrices.transpose(0, 2, 1))
    eigenvalues = np.linalg.eigvalsh(matrices)
    index = np.argmax(np.abs(eigenvalues), axis=1)
    return eigenvalues[np.arange(len(index)), index]


def actor_for(source, scalars=None, lut=None, scalar_range=None, color=None, point_data=False):
    mapper = vtkPolyDataMapper()
    if isinstance(source, vtkPolyData):
        mapper.SetInputData(source)
    else:
        mapper.SetInputConnection(source)
    if scalars is not None:
        if point_data:
            mapper.SetScalarModeToUsePointData()
        else:
            mapper.SetScalarModeToUsePointFieldData()
        mapper.SelectColorArray(scalars)
        mapper.SetLookupTable(lut)
        mapper.SetScalarRange(*scalar_range)
        mapper.ScalarVisibilityOn()
    else:
        mapper.ScalarVisibilityOff()
    actor = vtkActor()
    actor.SetMapper(mapper)
    if color is not None:
        actor.GetProperty().SetColor(*color)
    return actor


def inferno_lut(low, high):
    # Approximate samples of matplotlib's "inferno" colour map.
    samples = [(0.0, 0.001, 0.000, 0.014), (0.1, 0.087, 0.044, 0.225),
               (0.2, 0.258, 0.039, 0.406), (0.3, 0.416, 0.090, 0.433),
               (0.4, 0.578, 0.148, 0.404), (0.5, 0.735, 0.216, 0.330),
               (0.6, 0.865, 0.317, 0.226), (0.7, 0.955, 0.455, 0.117),
               (0.8, 0.988, 0.622, 0.048), (0.9, 0.969, 0.812, 0.227),
               (1.0, 0.988, 0.998, 0.645)]
    # The palest tenth is left out so white streamlines show everywhere.
    samples = [(t / 0.9, r, g, b) for t, r, g, b in samples if t <= 0.9]
    ctf = vtkColorTransferFunction()
    for t, r, g, b in samples:
        ctf.AddRGBPoint(low + t * (high - low), r, g, b)
    lut = vtkLookupTable()
    lut.SetNumberOfTableValues(256)
    lut.SetRange(low, high)
    for i in range(256):
        lut.SetTableValue(i, *ctf.GetColor(low + (high - low) * i / 255.0), 1.0)
    lut.Build()
    return lut


def diverging_lut(limit):
    # Blue (negative) to green (positive) through white: both stand out on
    # the slice's warm colours.
    ctf = vtkColorTransferFunction()
    ctf.SetColorSpaceToLab()
    ctf.AddRGBPoint(-limit, 0.13, 0.30, 0.80)
    ctf.AddRGBPoint(0.0, 0.95, 0.95, 0.95)
    ctf.AddRGBPoint(limit, 0.05, 0.60, 0.25)
    lut = vtkLookupTable()
    lut.SetNumberOfTableValues(256)
    lut.SetRange(-limit, limit)
    for i in range(256):
        lut.SetTableValue(i, *ctf.GetColor(-limit + 2.0 * limit * i / 255.0), 1.0)
    lut.Build()
    return lut


def scalar_bar(lut, title, x, labels_format="%-#.3g", font_scale=1.0):
    bar = vtkScalarBarActor()
    bar.SetLookupTable(lut)
    bar.SetTitle(title)
    bar.SetNumberOfLabels(5)
    bar.SetLabelFormat(labels_format)
    bar.SetOrientationToVertical()
    bar.GetPositionCoordinate().SetCoordinateSystemToNormalizedViewport()
    bar.GetPositionCoordinate().SetValue(x, 0.12)
    bar.SetWidth(0.08)
    bar.SetHeight(0.76)
    bar.SetBarRatio(0.35)
    bar.UnconstrainedFontSizeOn()
    for text in (bar.GetTitleTextProperty(), bar.GetLabelTextProperty()):
        text.SetColor(0.1, 0.1, 0.1)
        text.ShadowOff()
        text.ItalicOff()
        text.BoldOff()
        text.SetFontFamilyToArial()
    bar.GetTitleTextProperty().SetFontSize(round(20 * font_scale))
    bar.GetLabelTextProperty().SetFontSize(round(17 * font_scale))
    return bar


def main():
    args = parse_arguments()
    if not os.path.isfile(args.data):
        sys.exit(f"no skin surface at {args.data} (use --data)")
    if os.path.dirname(args.output):
        os.makedirs(os.path.dirname(args.output), exist_ok=True)

    reader = vtkXMLPolyDataReader()
    reader.SetFileName(args.data)
    boundary = boundary_temperature(reader.GetOutputPort())
    (xmin, xmax, ymin, ymax, zmin, zmax) = boundary.GetOutput().GetBounds()

    # The demo's slice: horizontal, through the middle, a little larger than the head.
    margin = 0.05 * (xmax - xmin)
    zmid = 0.5 * (zmin + zmax)
    x0, x1, y0, y1 = xmin - margin, xmax + margin, ymin - margin, ymax + margin
    size = max(x1 - x0, y1 - y0)

    if args.slice and os.path.isfile(args.slice):
        # A slice solved and saved before: only draw it again.
        slice_reader = vtkXMLPolyDataReader()
        slice_reader.SetFileName(args.slice)
        slice_reader.Update()
        result = slice_reader.GetOutput()
        print(f"points: {result.GetNumberOfPoints()} (read from {args.slice})")
    else:
        probe = vtkPlaneSource()
        probe.SetOrigin(x0, y0, zmid)
        probe.SetPoint1(x1, y0, zmid)
        probe.SetPoint2(x0, y1, zmid)
        probe.SetResolution(args.resolution - 1, args.resolution - 1)

        solver = gridfree.vtkWalkOnSpheresSolver()
        solver.SetBoundaryConnection(boundary.GetOutputPort())
        solver.SetProbeConnection(probe.GetOutputPort())
        solver.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS, "T")
        solver.SetWalksPerPoint(args.walks)
        solver.SetSeed(args.seed)
        solver.ComputeGradientOn()
        solver.ComputeHessianOn()
        start = time.perf_counter()
        solver.Update()
        seconds = time.perf_counter() - start
        result = solver.GetOutput()
        print(f"points: {result.GetNumberOfPoints()}")
        # Points whose error bar could not be trusted after args.walks walk on
        # (Walk On Where Unreliable): they add a few walks to the total.
        walked_on = result.GetFieldData().GetArray("PointsWalkedOnForReliability")
        walked_on = int(walked_on.GetValue(0)) if walked_on else 0
        print(f"walks: {solver.GetLastNumberOfWalks()} ({args.walks} per point, "
              f"more at {walked_on} points with unreliable error bars)")
        print(f"seconds: {seconds:.2f}")
        sys.stdout.flush()
        if args.slice:
            writer = vtkXMLPolyDataWriter()
            writer.SetFileName(args.slice)
            writer.SetInputData(result)
            writer.SetDataModeToBinary()
            writer.SetCompressorTypeToZLib()
            writer.Write()

    spacing = (x1 - x0) / (round(math.sqrt(result.GetNumberOfPoints())) - 1)

    # Which slice points lie inside the skin: the glyphs and streamlines are
    # drawn there (outside is the exterior problem, shown only by its colour).
    enclosed = vtkSelectEnclosedPoints()
    enclosed.SetInputData(result)
    enclosed.SetSurfaceConnection(boundary.GetOutputPort())
    enclosed.SetTolerance(1e-6)
    enclosed.Update()
    inside = vtkThreshold()
    inside.SetInputConnection(enclosed.GetOutputPort())
    inside.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS,
                                  "SelectedPoints")
    inside.SetLowerThreshold(0.5)
    inside.SetUpperThreshold(1.5)
    inside.SetThresholdFunction(vtkThreshold.THRESHOLD_BETWEEN)
    inside.AllScalarsOn()
    inside.Update()
    interior = inside.GetOutput()
    if interior.GetNumberOfCells() == 0:
        sys.exit("no slice cell lies inside the skin: is the surface closed?")
    interior.GetPointData().SetActiveVectors("T_Gradient")
    interior.GetPointData().SetActiveTensors("T_Hessian")

    data = interior.GetPointData()
    temperature = vtk_to_numpy(result.GetPointData().GetArray("T"))
    speed = np.linalg.norm(vtk_to_numpy(data.GetArray("T_Gradient")), axis=1)
    dominant = dominant_eigenvalue(vtk_to_numpy(data.GetArray("T_Hessian")))
    dominant_array = numpy_to_vtk(np.ascontiguousarray(dominant), deep=True)
    dominant_array.SetName("T_Hessian_Dominant")
    data.AddArray(dominant_array)
    t_low, t_high = float(temperature.min()), float(temperature.max())
    speed_scale = percentile_or(speed, 95, 1.0)
    # Near the skin the Hessian is far larger than inside: its 75th percentile
    # gets the full radius (larger ones are clamped), so the interior shows.
    hessian_scale = percentile_or(np.abs(dominant), 75, 1.0)

    # Streamlines of the gradient from a grid of seeds (a quarter cell off the
    # slice's points), kept in the slice and inside the skin.
    seeds = vtkPlaneSource()
    seeds.SetOrigin(x0, y0, zmid)
    seeds.SetPoint1(x1, y0, zmid)
    seeds.SetPoint2(x0, y1, zmid)
    seeds.SetResolution(STREAMLINE_SEEDS, STREAMLINE_SEEDS)
    seeds.SetCenter(0.5 * (x0 + x1) + 0.25 * spacing, 0.5 * (y0 + y1) + 0.25 * spacing, zmid)
    tracer = vtkStreamTracer()
    tracer.SetInputData(interior)
    tracer.SetSourceConnection(seeds.GetOutputPort())
    tracer.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS, "T_Gradient")
    tracer.SurfaceStreamlinesOn()
    tracer.SetIntegrationDirectionToBoth()
    tracer.SetIntegratorTypeToRungeKutta45()
    tracer.SetIntegrationStepUnit(vtkStreamTracer.CELL_LENGTH_UNIT)
    tracer.SetInitialIntegrationStep(0.5)
    tracer.SetMinimumIntegrationStep(0.2)
    tracer.SetMaximumIntegrationStep(1.0)
    tracer.SetMaximumPropagation(size)
    tracer.SetMaximumNumberOfSteps(2000)
    tracer.SetTerminalSpeed(1e-3 * speed_scale)
    tracer.SetComputeVorticity(False)
    tracer.Update()

    # Arrows on a spatially stratified subsample, oriented and scaled by the
    # gradient; the 95th-percentile gradient gets the length of the spacing.
    arrow_points = stratified_subsample(interior, ARROWS, seed=1)
    arrow_length = 1.3 * math.sqrt(slice_area(interior) / ARROWS)
    arrow = vtkArrowSource()
    arrow.SetTipResolution(16)
    arrow.SetShaftResolution(12)
    arrow.SetTipLength(0.35)
    arrow.SetTipRadius(0.13)
    arrow.SetShaftRadius(0.05)
    arrows = vtkGlyph3D()
    arrows.SetInputConnection(arrow_points.GetOutputPort())
    arrows.SetSourceConnection(arrow.GetOutputPort())
    arrows.SetInputArrayToProcess(1, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS, "T_Gradient")
    arrows.SetVectorModeToUseVector()
    arrows.SetScaleModeToScaleByVector()
    arrows.OrientOn()
    arrows.ClampingOn()
    arrows.SetRange(0.0, speed_scale)
    arrows.SetScaleFactor(arrow_length)

    # Hessian ellipsoids on a coarser subsample: axes along the eigenvectors,
    # radii proportional to |eigenvalue|, colour the dominant eigenvalue.
    tensor_points = stratified_subsample(interior, ELLIPSOIDS, seed=2)
    ellipsoid_radius = 0.4 * math.sqrt(slice_area(interior) / ELLIPSOIDS)
    sphere = vtkSphereSource()
    sphere.SetThetaResolution(24)
    sphere.SetPhiResolution(16)
    ellipsoids = vtkTensorGlyph()
    ellipsoids.SetInputConnection(tensor_points.GetOutputPort())
    ellipsoids.SetSourceConnection(sphere.GetOutputPort())
    ellipsoids.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS, "T_Hessian")
    ellipsoids.SetInputArrayToProcess(1, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS,
                                      "T_Hessian_Dominant")
    ellipsoids.ExtractEigenvaluesOn()
    ellipsoids.ColorGlyphsOn()
    ellipsoids.SetColorModeToScalars()
    # The unit-diameter sphere is scaled by eigenvalue * factor.
    ellipsoids.SetScaleFactor(2.0 * ellipsoid_radius / hessian_scale)
    ellipsoids.ClampScalingOn()
    ellipsoids.SetMaxScaleFactor(2.0 * ellipsoid_radius)

    # Context: the skin above the slice as a translucent dome, and its cross-section.
    cut_plane = vtkPlane()
    cut_plane.SetOrigin(0.0, 0.0, zmid)
    cut_plane.SetNormal(0.0, 0.0, 1.0)
    dome = vtkClipPolyData()
    dome.SetInputConnection(boundary.GetOutputPort())
    dome.SetClipFunction(cut_plane)
    dome_top = vtkPlane()
    dome_top.SetOrigin(0.0, 0.0, zmid + DOME_HEIGHT * (zmax - zmid))
    dome_top.SetNormal(0.0, 0.0, -1.0)
    dome_band = vtkClipPolyData()
    dome_band.SetInputConnection(dome.GetOutputPort())
    dome_band.SetClipFunction(dome_top)
    outline = vtkCutter()
    outline.SetInputConnection(boundary.GetOutputPort())
    outline.SetCutFunction(cut_plane)

    t_lut = inferno_lut(t_low, t_high)
    h_lut = diverging_lut(hessian_scale)

    slice_actor = actor_for(result, "T", t_lut, (t_low, t_high))
    slice_actor.GetProperty().SetAmbient(0.3)
    slice_actor.GetProperty().SetDiffuse(0.7)
    stream_actor = actor_for(tracer.GetOutputPort(), color=(0.97, 0.98, 1.0))
    stream_actor.GetProperty().SetLineWidth(2.0)
    stream_actor.GetProperty().RenderLinesAsTubesOn()
    arrow_actor = actor_for(arrows.GetOutputPort(), color=(0.05, 0.05, 0.08))
    arrow_actor.GetProperty().SetSpecular(0.3)
    ellipsoid_actor = actor_for(ellipsoids.GetOutputPort(), "T_Hessian_Dominant", h_lut,
                                (-hessian_scale, hessian_scale), point_data=True)
    ellipsoid_actor.GetProperty().SetSpecular(0.4)
    ellipsoid_actor.GetProperty().SetSpecularPower(30)
    dome_actor = actor_for(dome_band.GetOutputPort(), color=(0.80, 0.70, 0.62))
    dome_actor.GetProperty().SetOpacity(0.18)
    outline_actor = actor_for(outline.GetOutputPort(), color=(0.75, 0.95, 0.80))
    outline_actor.GetProperty().SetLineWidth(3.0)
    outline_actor.GetProperty().RenderLinesAsTubesOn()

    # The scene, the colour bars on the right, a title above and a key below.
    renderer = vtkRenderer()
    renderer.SetBackground(1.0, 1.0, 1.0)
    renderer.SetViewport(0.0, 0.1, 0.84, 0.95)
    for actor in (slice_actor, stream_actor, arrow_actor, ellipsoid_actor, outline_actor,
                  dome_actor):
        renderer.AddActor(actor)
    renderer.SetUseDepthPeeling(1)
    renderer.SetMaximumNumberOfPeels(6)
    renderer.SetOcclusionRatio(0.0)

    bars = vtkRenderer()
    bars.SetViewport(0.84, 0.0, 1.0, 0.95)
    bars.SetBackground(1.0, 1.0, 1.0)
    # Text sizes are set for a 1400 pixel wide picture and follow the width.
    font_scale = args.size[0] / 1400.0
    bars.AddViewProp(scalar_bar(t_lut, "T", 0.04, font_scale=font_scale))
    bars.AddViewProp(scalar_bar(h_lut, "Hessian\neigenvalue", 0.5, "%-#.2g", font_scale))

    title = text_renderer(
        (0.0, 0.95, 1.0, 1.0), round(21 * font_scale), (0.1, 0.1, 0.1),
        f"Temperature T inside a CT-scanned head ({args.walks} walks per point): "
        "streamlines and arrows of grad T, ellipsoids of its Hessian")
    key = text_renderer(
        (0.0, 0.0, 0.84, 0.1), round(16 * font_scale), (0.3, 0.3, 0.3),
        "white lines: streamlines of grad T within the slice;  black arrows: grad T\n"
        "ellipsoids: Hessian of T (axes along its eigenvectors, radii ~ |eigenvalue|, "
        "colour: the eigenvalue of largest magnitude)\n"
        "translucent: the skin above the slice;  green line: its cross-section")

    # Look down at the slice from above and in front, tilted so the dome shows.
    center = (0.5 * (x0 + x1), 0.5 * (y0 + y1), zmid)
    camera = renderer.GetActiveCamera()
    camera.SetFocalPoint(*center)
    camera.SetPosition(center[0] + CAMERA[0] * size, center[1] + CAMERA[1] * size,
                       zmid + CAMERA[2] * size)
    camera.SetViewUp(0.0, 0.0, 1.0)
    camera.SetViewAngle(30.0)
    renderer.ResetCamera(x0, x1, y0, y1, zmid, zmid)
    camera.Dolly(ZOOM)
    renderer.ResetCameraClippingRange()

    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(*args.size)
    window.SetAlphaBitPlanes(1)
    window.SetMultiSamples(0)
    window.AddRenderer(renderer)
    window.AddRenderer(bars)
    window.AddRenderer(title)
    window.AddRenderer(key)
    window.Render()

    capture = vtkWindowToImageFilter()
    capture.SetInput(window)
    capture.SetInputBufferTypeToRGB()
    capture.ReadFrontBufferOff()
    capture.ShouldRerenderOff()
    capture.Update()
    writer = vtkPNGWriter()
    writer.SetFileName(args.output)
    writer.SetInputConnection(capture.GetOutputPort())
    writer.Write()
    print(f"streamlines: {tracer.GetOutput().GetNumberOfLines()}; "
          f"arrows: {arrow_points.GetOutput().GetNumberOfPoints()}; "
          f"ellipsoids: {tensor_points.GetOutput().GetNumberOfPoints()}")
    print(f"wrote {args.output}")


def text_renderer(viewport, font_size, color, text):
    """A renderer of its own for a block of text in the top left of viewport."""
    actor = vtkTextActor()
    actor.SetInput(text)
    actor.GetTextProperty().SetFontSize(font_size)
    actor.GetTextProperty().SetColor(*color)
    actor.GetTextProperty().SetVerticalJustificationToTop()
    actor.GetPositionCoordinate().SetCoordinateSystemToNormalizedViewport()
    actor.GetPositionCoordinate().SetValue(0.012, 0.9)
    renderer = vtkRenderer()
    renderer.SetViewport(*viewport)
    renderer.SetBackground(1.0, 1.0, 1.0)
    renderer.AddViewProp(actor)
    return renderer


def slice_area(dataset):
    """Area of the 2D cells of dataset."""
    sizes = vtkCellSizeFilter()
    sizes.SetInputData(dataset)
    sizes.ComputeVertexCountOff()
    sizes.ComputeLengthOff()
    sizes.ComputeVolumeOff()
    sizes.ComputeSumOn()
    sizes.Update()
    return sizes.GetOutput().GetFieldData().GetArray("Area").GetTuple1(0)


def stratified_subsample(dataset, count, seed):
    """About count points of dataset, spread evenly in space (vtkMaskPoints'
    spatially stratified random sampling, repeatable through its seed)."""
    mask = vtkMaskPoints()
    mask.SetInputData(dataset)
    mask.RandomModeOn()
    mask.SetRandomModeType(2)
    mask.SetRandomSeed(seed)
    mask.SetMaximumNumberOfPoints(count)
    mask.GenerateVerticesOn()
    mask.SingleVertexPerCellOn()
    mask.Update()
    return mask


if __name__ == "__main__":
    main()
