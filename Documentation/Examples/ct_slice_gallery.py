"""The output-sensitive gallery: the demo's CT slice solved four ways (a
high-walk reference, a raw low-walk solve, adaptive samples + moving least
squares, the raw solve denoised), then streamlines and gradient glyphs on the
CT head. Renders PNGs and prints the walks, seconds and error of each.

Run with pvbatch under xvfb (the GridFree plugin loads through
PV_PLUGIN_PATH, which `./gridfree env` prints):

    pvbatch ct_slice_gallery.py --data Data/headsq_skin_iso500_closed.vtp \
        --output Documentation/Images

Writes gallery_ct_slice.png, gallery_ct_streamlines.png and
gallery_ct_slice.md (the table) into the output folder. The error of each
result is its RMS difference from the reference over the slice, with the
reference's own noise (its mean variance) subtracted. "Dense walks for equal
error" extrapolates the raw solves' error by the Monte Carlo law
error² ∝ 1/walks.
"""
import argparse
import math
import os
import sys

import paraview.simple as pvs
from paraview import servermanager
from paraview.simple import (
    ColorBy, CreateLayout, CreateView, GetColorTransferFunction, GetScalarBar, Glyph,
    PointSource, Show, Slice, Text)
from vtkmodules.util.numpy_support import vtk_to_numpy

from example_pictures import save
from head_ct_demo import temperature_and_slice  # the demo's boundary and slice


def parse_arguments():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", required=True, help="skin surface (.vtp)")
    parser.add_argument("--output", default="output", help="folder for the pictures and table")
    parser.add_argument("--resolution", type=int, default=128, help="slice points per side")
    parser.add_argument("--reference-walks", type=int, default=1024)
    parser.add_argument("--walks", type=int, default=16, help="walks per pixel of the raw solve")
    parser.add_argument("--ladder-walks", type=int, default=64,
                        help="walks per pixel of a second raw solve, for the error law")
    parser.add_argument("--initial-samples", type=int, default=256)
    parser.add_argument("--samples", type=int, default=1024, help="adaptive sampling budget")
    parser.add_argument("--sample-walks", type=int, default=256, help="walks per adaptive sample")
    parser.add_argument("--seeds", type=int, default=24, help="streamline seeds")
    parser.add_argument("--line-walks", type=int, default=256, help="walks per streamline estimate")
    return parser.parse_args()


def fetch(proxy):
    proxy.UpdatePipeline()
    return servermanager.Fetch(proxy)


def array(data, name):
    return vtk_to_numpy(data.GetPointData().GetArray(name)).astype(float)


def field(data, name):
    return data.GetFieldData().GetArray(name).GetValue(0)


class Result:
    """A slice result: its pipeline proxy, fetched data, walks and seconds."""

    def __init__(self, label, proxy, data, walks, seconds):
        self.label, self.proxy, self.data = label, proxy, data
        self.walks, self.seconds = walks, seconds


def main():
    args = parse_arguments()
    os.makedirs(args.output, exist_ok=True)
    if not hasattr(pvs, "WalkOnSpheresSolver"):
        sys.exit("The GridFree plugin is not loaded: set PV_PLUGIN_PATH to its folder.")

    n = args.resolution
    skin, boundary, probe, bounds = temperature_and_slice(args.data, n)
    (xmin, xmax, ymin, ymax, zmin, zmax) = bounds

    def dense(walks):
        solver = pvs.WalkOnSpheresSolver(Boundary=boundary, Probe=probe)
        solver.BoundaryValues = ["POINTS", "T"]
        solver.WalksPerPoint = walks
        solver.ControlVariates = 0  # values only: the fastest dense solve
        data = fetch(solver)
        return Result(f"raw, {walks} walks per pixel", solver, data,
                              int(field(data, "TotalWalks")), field(data, "SolveSeconds"))

    print(f"reference: {n * n} pixels x {args.reference_walks} walks ...")
    sys.stdout.flush()
    reference = dense(args.reference_walks)
    reference.label = f"reference, {args.reference_walks} walks per pixel"
    exact = array(reference.data, "T")
    reference_noise = float(array(reference.data, "T_Variance").mean())

    def error(result):
        squared = float(((array(result.data, "T") - exact) ** 2).mean())
        return math.sqrt(max(squared - reference_noise, 0.0))

    raw = dense(args.walks)
    ladder = dense(args.ladder_walks)

    sampler = pvs.WalkOnSpheresAdaptiveSampler(Boundary=boundary, Domain=probe)
    sampler.BoundaryValues = ["POINTS", "T"]
    sampler.InitialSamples = args.initial_samples
    sampler.MaximumSamples = args.samples
    sampler.WalksPerPoint = args.sample_walks
    samples = fetch(sampler)
    mls = pvs.MovingLeastSquaresInterpolator(Input=probe, Source=sampler, Boundary=boundary)
    mls.Values = ["POINTS", "T"]
    interpolated = fetch(mls)
    adaptive = Result(f"adaptive ({samples.GetNumberOfPoints()} samples) + MLS", mls, interpolated,
                      int(field(samples, "TotalWalks")),
                      field(samples, "SamplingSeconds") + field(interpolated, "InterpolationSeconds"))

    denoiser = pvs.WalkOnSpheresDenoiser(Input=raw.proxy)
    denoiser.Values = ["POINTS", "T"]
    denoised_data = fetch(denoiser)
    denoised = Result(f"raw {args.walks} walks, denoised", denoiser, denoised_data, raw.walks,
                      raw.seconds + field(denoised_data, "DenoiseSeconds"))

    # The Monte Carlo law error² = c / walks, c from the two raw solves.
    c = 0.5 * (error(raw) ** 2 * args.walks + error(ladder) ** 2 * args.ladder_walks)
    rows = [reference, raw, ladder, adaptive, denoised]
    lines = ["| result | walks | seconds | RMS error (°C) | dense walks for equal error | walks saved |",
             "|---|---:|---:|---:|---:|---:|"]
    for r in rows:
        e = error(r) if r is not reference else math.sqrt(reference_noise)
        equal = c / (e * e) * n * n if e > 0 else float("inf")
        equal_text = "" if r is reference else f"{equal:.3g}"
        saved = f"{equal / r.walks:.1f}x" if r in (adaptive, denoised) else ""
        lines.append(f"| {r.label} | {r.walks} | {r.seconds:.2f} | {e:.3f} | "
                     f"{equal_text} | {saved} |")
    table = "\n".join(lines)
    print(table)
    with open(os.path.join(args.output, "gallery_ct_slice.md"), "w") as out:
        out.write(table + "\n")

    render_slices(args, boundary, skin, [reference, raw, adaptive, denoised], exact,
                  (xmin, xmax, ymin, ymax, zmin, zmax), error)
    render_streamlines(args, boundary, skin, sampler, mls, (xmin, xmax, ymin, ymax, zmin, zmax))


def render_slices(args, boundary, skin, results, exact, bounds, error):
    (xmin, xmax, ymin, ymax, zmin, zmax) = bounds
    zmid = 0.5 * (zmin + zmax)
    center = [0.5 * (xmin + xmax), 0.5 * (ymin + ymax), zmid]
    contour = Slice(Input=skin)
    contour.SliceType = "Plane"
    contour.SliceType.Origin = center
    contour.SliceType.Normal = [0.0, 0.0, 1.0]
    layout = CreateLayout("CT slice gallery")
    layout.SetSize(1200, 1200)
    layout.SplitHorizontal(0, 0.5)
    layout.SplitVertical(1, 0.5)
    layout.SplitVertical(2, 0.5)
    lut = GetColorTransferFunction("T")
    lut.ApplyPreset("Inferno (matplotlib)", True)
    lut.RescaleTransferFunction(float(exact.min()), float(exact.max()))
    lut.AutomaticRescaleRangeMode = "Never"
    # Reference and raw on top, adaptive + MLS and denoised below.
    for cell, result in zip((3, 5, 4, 6), results):
        view = CreateView("RenderView")
        layout.AssignView(cell, view)
        view.OrientationAxesVisibility = 0
        display = Show(result.proxy, view)
        ColorBy(display, ("POINTS", "T"))
        outline = Show(contour, view)
        outline.AmbientColor = outline.DiffuseColor = [1.0, 1.0, 1.0]
        outline.LineWidth = 2.0
        title = Text(Text=f"{result.label}\n{result.walks:,} walks, {result.seconds:.1f} s"
                     + ("" if result is results[0] else f", error {error(result):.2f} °C"))
        title_display = Show(title, view)
        title_display.FontSize = 13
        title_display.WindowLocation = "Upper Center"
        view.CameraFocalPoint = center
        view.CameraPosition = [center[0], center[1], zmax + 4.0 * (zmax - zmin)]
        view.CameraViewUp = [0.0, 1.0, 0.0]
        view.ResetCamera(False)
    save(layout, os.path.join(args.output, "gallery_ct_slice.png"), [1200, 1200])


def render_streamlines(args, boundary, skin, sampler, mls, bounds):
    (xmin, xmax, ymin, ymax, zmin, zmax) = bounds
    center = [0.5 * (xmin + xmax), 0.5 * (ymin + ymax), 0.5 * (zmin + zmax)]
    seeds = PointSource(Center=center, Radius=0.25 * (xmax - xmin),
                        NumberOfPoints=args.seeds)
    tracer = pvs.WalkOnSpheresStreamTracer(Boundary=boundary, Seeds=seeds)
    tracer.BoundaryValues = ["POINTS", "T"]
    tracer.WalksPerPoint = args.line_walks
    tracer.IntegrationDirection = 2  # both
    tracer.StepLength = 0.01
    tracer.MaximumSteps = 150
    lines = fetch(tracer)
    print(f"streamlines: {lines.GetNumberOfCells()} lines, {lines.GetNumberOfPoints()} points")
    # Arrows of the adaptive samples' gradients, on the interpolated slice.
    arrows = Glyph(Input=sampler, GlyphType="Arrow")
    arrows.OrientationArray = ["POINTS", "T_Gradient"]
    arrows.ScaleArray = ["POINTS", "No scale array"]
    arrows.ScaleFactor = 0.04 * (xmax - xmin)
    arrows.GlyphMode = "Every Nth Point"
    arrows.Stride = max(1, args.samples // 256)

    layout = CreateLayout("CT streamlines")
    layout.SetSize(1000, 800)  # fonts at their size, not scaled up
    view = CreateView("RenderView")
    layout.AssignView(0, view)
    view.OrientationAxesVisibility = 0
    surface = Show(skin, view)
    surface.Opacity = 0.15
    surface.AmbientColor = surface.DiffuseColor = [0.85, 0.8, 0.75]
    slice_display = Show(mls, view)
    ColorBy(slice_display, ("POINTS", "T"))
    slice_display.Opacity = 0.55
    line_display = Show(tracer, view)
    ColorBy(line_display, ("POINTS", "T"))
    line_display.LineWidth = 3.0
    line_display.RenderLinesAsTubes = 1
    arrow_display = Show(arrows, view)
    arrow_display.AmbientColor = arrow_display.DiffuseColor = [1.0, 1.0, 1.0]
    ColorBy(arrow_display, None)
    lut = GetColorTransferFunction("T")
    bar = GetScalarBar(lut, view)
    bar.Title = "T (°C)"
    bar.ComponentTitle = ""
    bar.WindowLocation = "Any Location"
    bar.Position = [0.88, 0.15]
    bar.ScalarBarLength = 0.6
    bar.TitleFontSize = 7
    bar.LabelFontSize = 6
    bar.ScalarBarThickness = 8
    bar.AutomaticLabelFormat = 0
    bar.LabelFormat = "%-#.3g"
    bar.RangeLabelFormat = "%-#.3g"
    line_display.SetScalarBarVisibility(view, True)
    title = Text(Text="Walk On Spheres Stream Tracer: lines of grad T from seeds inside the head\n"
                 f"({lines.GetNumberOfCells()} lines, {args.line_walks} walks per estimate); "
                 "arrows: grad T at the adaptive samples")
    title_display = Show(title, view)
    title_display.FontSize = 6  # a single large view scales text up
    title_display.WindowLocation = "Upper Center"
    view.CameraFocalPoint = center
    view.CameraPosition = [center[0] + 1.2 * (xmax - xmin), center[1] - 1.8 * (ymax - ymin),
                           center[2] + 1.6 * (zmax - zmin)]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    view.ResetCamera(False)
    save(layout, os.path.join(args.output, "gallery_ct_streamlines.png"), [1000, 800])


if __name__ == "__main__":
    main()
