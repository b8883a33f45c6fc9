"""GridFree CT workflow: from a CT volume to a temperature field on a slice,
its streamlines and gradient glyphs, all in ParaView with no volume mesh.

    CT volume (.mhd) -> Resample To Image (pad) -> Contour (skin) -> Calculator (T on the skin)
                     -> Calculator (heat source f)                 -> Walk On Spheres Solver
                     -> Slice (the probe) --------------------------^     |
                                   Threshold (inside the head) <---------+
                                   -> Stream Tracer and Glyph of T_Gradient

The skin of the classic VTK "headsq" CT scan carries the boundary temperature
of the demo (head_ct_demo.py) and the CT values themselves heat the tissue:
the solver solves the Poisson equation  ΔT = f  with f = -HEATING * CT value
(a source where tissue is dense: the solver's sign convention is Δu = f), on
the points of a Slice through the volume, with T's gradient from the same
walks. ParaView's own Stream Tracer and Glyph then draw T_Gradient inside
the head. Padding the volume by one voxel of zeros closes the skin where the
scan was cut, so the skin encloses the head. The solver's Polynomial Control
Variate (degree 6) fits a polynomial to the skin's temperature and the heating
before any walk and lets the walks estimate only what it misses: about a
fifth of their spread, so a target error takes about a fifth of the walks.
Points outside the head are NaN (it solves the head's interior).

Three ways to run it:
  - headless (pvbatch or pvpython), writing data and a picture:
        pvbatch ct_workflow.py --output output
    prints points, walks, seconds and walks per second. `./gridfree demo`
    runs it after the head-slice demo with the sphere cache, to 0.5 degrees
    at every point inside the head:
        pvbatch ct_workflow.py --output output --estimator sphere --target 0.5 --walks 4096
  - in the ParaView GUI, at start-up:
        ./gridfree paraview --script=Documentation/Examples/ct_workflow.py
  - in the ParaView GUI as a macro: Macros > Import new macro..., pick this
    file, then click "ct_workflow" in the Macros menu.
In the GUI the pipeline appears in the Pipeline Browser with the Slice
selected: drag its plane in the view (or type an origin and normal), press
Apply, and the solver, the streamlines and the glyphs follow the new slice.
The data folder is found in the GRIDFREE_DATA environment variable
(`./gridfree paraview` sets it, `./gridfree env` prints it), next to this
file (../../Data), or above a folder of PV_PLUGIN_PATH (a build in the
source tree); otherwise the script stops with a message saying so.

Each filter is created after its inputs have been updated: ParaView's panel
builds its array lists when a filter is created, and an array chosen by a
script that was not in the list then shows blank, and the first Apply would
clear it (the solver's Boundary Values, the Stream Tracer's Vectors).
"""
import argparse
import os
import sys

import paraview.simple as pvs
from paraview import servermanager

# Boundary temperature in degrees, a smooth function of position (mm): the
# same as head_ct_demo.py's.
TEMPERATURE = "20 + 10*sin(0.04*coordsX)*cos(0.03*coordsY) + 0.1*coordsZ"
# Heating per CT unit (degrees per mm^2): soft tissue (about 1000 units)
# warms the middle of the head by a few degrees over the boundary's values.
HEATING = 2e-5
# CT values above this are tissue: the skin's iso-value.
SKIN_ISO_VALUE = 500.0


VOLUME_NAME = "headsq_headCT.mhd"


def data_folder():
    """The folder holding the CT volume. Under `paraview --script` or as a
    macro there is no __file__: the plugin's folder leads to a build in the
    source tree."""
    candidates = []
    if os.environ.get("GRIDFREE_DATA"):
        candidates.append(os.environ["GRIDFREE_DATA"])
    if "__file__" in globals():
        candidates.append(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                       "Data"))
    for plugin_folder in os.environ.get("PV_PLUGIN_PATH", "").split(os.pathsep):
        folder = os.path.abspath(plugin_folder) if plugin_folder else ""
        for _ in range(6):
            if not folder or folder == os.path.dirname(folder):
                break
            folder = os.path.dirname(folder)
            candidates.append(os.path.join(folder, "Data"))
    for candidate in candidates:
        if os.path.isfile(os.path.join(candidate, VOLUME_NAME)):
            return candidate
    # An exception, not sys.exit: the GUI shows its message in the Output
    # Messages window and stays open, where sys.exit would end ParaView
    # silently.
    raise RuntimeError("Cannot find the CT volume %s: set GRIDFREE_DATA to the project's Data "
                       "folder (`./gridfree env` prints it) and run the script again."
                       % VOLUME_NAME)


def parse_arguments(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--volume", default=None,
                        help="CT volume (.mhd); default: headsq_headCT.mhd of the Data folder")
    parser.add_argument("--output", default=None,
                        help="folder for the data files and the picture (headless runs)")
    parser.add_argument("--walks", type=int, default=128, help="walks per slice point")
    parser.add_argument("--slice-z", type=float, default=70.0, help="height of the slice (mm)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--estimator", choices=("pointwise", "sphere"), default="pointwise",
                        help="pointwise walks at every slice point, or the sphere cache that "
                             "moved slices share")
    parser.add_argument("--target", type=float, default=0.0,
                        help="target standard error in degrees (0: a fixed count of walks)")
    parser.add_argument("--walks-per-sphere", type=int, default=128,
                        help="walks of each sphere of the sphere cache when it is made")
    parser.add_argument("--polynomial", type=int, default=6,
                        help="degree of the polynomial control variate (0: none)")
    return parser.parse_args(argv)


def build_pipeline(volume_file, walks=128, slice_z=70.0, seed=0, estimator="pointwise",
                   target=0.0, walks_per_sphere=128, polynomial=6):
    """Creates the workflow's proxies and returns them by name. The volume is
    read (for its grid) and the solver runs once (the arrows are scaled to
    its gradient); a view or UpdatePipeline runs the rest. With the sphere
    cache (estimator "sphere") a moved slice reuses the walks of the spheres
    it meets again. With the polynomial control variate (degree `polynomial`,
    0 for none) the walks estimate T minus a polynomial fitted to the skin's
    temperature and the heating, which takes most of their spread away;
    either way points outside the head are NaN (both solve inside)."""
    if not hasattr(pvs, "WalkOnSpheresSolver"):
        sys.exit("The GridFree plugin is not loaded: set PV_PLUGIN_PATH to its folder "
                 "(`./gridfree env` prints it) or load it in Tools > Manage Plugins.")
    p = {}
    p["volume"] = pvs.OpenDataFile(volume_file)
    pvs.RenameSource("CT volume", p["volume"])
    p["volume"].UpdatePipeline()
    (x0, x1, y0, y1, z0, z1) = p["volume"].GetDataInformation().GetBounds()
    dims = p["volume"].GetDataInformation().GetExtent()
    spacing = [(x1 - x0) / max(dims[1] - dims[0], 1), (y1 - y0) / max(dims[3] - dims[2], 1),
               (z1 - z0) / max(dims[5] - dims[4], 1)]
    array = p["volume"].PointData.keys()[0]

    # One voxel of zeros around the scan, on the scan's own grid: where the
    # scan cut through the body, the contour closes.
    p["padded"] = pvs.ResampleToImage(Input=p["volume"])
    pvs.RenameSource("Padded volume", p["padded"])
    p["padded"].UseInputBounds = 0
    p["padded"].SamplingBounds = [x0 - spacing[0], x1 + spacing[0], y0 - spacing[1],
                                  y1 + spacing[1], z0 - spacing[2], z1 + spacing[2]]
    p["padded"].SamplingDimensions = [dims[1] - dims[0] + 3, dims[3] - dims[2] + 3,
                                      dims[5] - dims[4] + 3]

    p["skin"] = pvs.Contour(Input=p["padded"], ContourBy=["POINTS", array],
                            Isosurfaces=[SKIN_ISO_VALUE])
    pvs.RenameSource("Skin (boundary)", p["skin"])
    p["boundary"] = pvs.Calculator(Input=p["skin"], ResultArrayName="T", Function=TEMPERATURE)
    pvs.RenameSource("Skin temperature", p["boundary"])
    p["heat"] = pvs.Calculator(Input=p["padded"], ResultArrayName="f",
                               Function="-%g*%s" % (HEATING, array))
    pvs.RenameSource("Heat source", p["heat"])
    # The solver's array lists (T, f) are built when it is created.
    p["boundary"].UpdatePipeline()
    p["heat"].UpdatePipeline()

    # The probe: a Slice of the volume, so its points carry the CT values too.
    p["slice"] = pvs.Slice(Input=p["padded"])
    p["slice"].SliceType = "Plane"
    p["slice"].SliceType.Origin = [0.5 * (x0 + x1), 0.5 * (y0 + y1), slice_z]
    p["slice"].SliceType.Normal = [0.0, 0.0, 1.0]
    pvs.RenameSource("Slice (the probe)", p["slice"])
    p["slice"].UpdatePipeline()

    solver = pvs.WalkOnSpheresSolver(Boundary=p["boundary"], Probe=p["slice"], Source=p["heat"])
    solver.BoundaryValues = ["POINTS", "T"]
    solver.Equation = "Poisson"
    solver.SourceArray = ["POINTS", "f"]
    solver.ComputeGradient = 1
    solver.WalksPerPoint = walks
    solver.Seed = seed
    if estimator == "sphere":
        solver.Estimator = "Sphere Cache"
        solver.WalksPerSphere = walks_per_sphere
    solver.TargetStandardError = target
    solver.PolynomialControlVariate = polynomial
    p["solver"] = solver
    pvs.RenameSource("Walk On Spheres Solver", solver)
    # The Threshold's and the tracer's array lists (MetaImage, T_Gradient).
    solver.UpdatePipeline()

    # Inside the head: slice points whose CT value is tissue.
    p["inside"] = pvs.Threshold(Input=solver, Scalars=["POINTS", array],
                                LowerThreshold=SKIN_ISO_VALUE, UpperThreshold=1e9,
                                AllScalars=1)
    pvs.RenameSource("Inside the head", p["inside"])
    p["inside"].UpdatePipeline()
    # Lines of steepest ascent and descent of T within the slice (surface
    # streamlines, both directions) from every 30th point inside.
    p["seeds"] = pvs.MaskPoints(Input=p["inside"], OnRatio=30, MaximumNumberofPoints=100000,
                                GenerateVertices=1, SingleVertexPerCell=1)
    pvs.RenameSource("Streamline seeds", p["seeds"])
    p["streamlines"] = pvs.StreamTracerWithCustomSource(Input=p["inside"],
                                                       SeedSource=p["seeds"])
    pvs.RenameSource("Streamlines of T_Gradient", p["streamlines"])
    p["streamlines"].Vectors = ["POINTS", "T_Gradient"]
    p["streamlines"].SurfaceStreamlines = 1
    p["streamlines"].IntegrationDirection = "BOTH"
    p["streamlines"].MaximumStreamlineLength = x1 - x0
    # Arrows along T_Gradient, their length proportional to its magnitude:
    # 4 voxels at the 90th percentile inside (a robust scale: the estimates
    # nearest the skin are the noisiest), on every 11th point inside.
    inside = servermanager.Fetch(p["inside"])
    gradient = inside.GetPointData().GetArray("T_Gradient") if inside else None
    magnitudes = sorted(gradient.GetTuple3(i)[0] ** 2 + gradient.GetTuple3(i)[1] ** 2
                        + gradient.GetTuple3(i)[2] ** 2
                        for i in range(gradient.GetNumberOfTuples())) if gradient else [1.0]
    typical = max(magnitudes[int(0.9 * (len(magnitudes) - 1))] ** 0.5, 1e-30)
    p["glyphs"] = pvs.Glyph(Input=p["inside"], GlyphType="Arrow")
    pvs.RenameSource("Arrows of T_Gradient", p["glyphs"])
    p["glyphs"].OrientationArray = ["POINTS", "T_Gradient"]
    p["glyphs"].ScaleArray = ["POINTS", "T_Gradient"]
    p["glyphs"].ScaleFactor = 4.0 * spacing[0] / typical
    p["glyphs"].GlyphMode = "Every Nth Point"
    p["glyphs"].Stride = 11
    return p


def show(p, view):
    """Shows the workflow in a render view: the slice coloured by T, the
    streamlines, the arrows and the skin below the slice for context."""
    slice_display = pvs.Show(p["solver"], view)
    pvs.ColorBy(slice_display, ("POINTS", "T"))
    lut = pvs.GetColorTransferFunction("T")
    lut.ApplyPreset("Inferno (matplotlib)", True)
    # Points outside the head are NaN (the cache and the polynomial control
    # variate solve inside): left out of the picture rather than painted.
    lut.NanOpacity = 0.0
    slice_display.RescaleTransferFunctionToDataRange(False, True)
    slice_display.SetScalarBarVisibility(view, True)
    bar = pvs.GetScalarBar(lut, view)
    bar.Title = "T"
    bar.ComponentTitle = "(deg)"

    lines = pvs.Show(p["streamlines"], view)
    pvs.ColorBy(lines, None)
    lines.AmbientColor = lines.DiffuseColor = [0.3, 0.85, 1.0]
    lines.LineWidth = 1.5
    arrows = pvs.Show(p["glyphs"], view)
    pvs.ColorBy(arrows, None)
    arrows.AmbientColor = arrows.DiffuseColor = [1.0, 1.0, 1.0]

    below = pvs.Clip(Input=p["skin"], ClipType="Plane")
    pvs.RenameSource("Skin below the slice", below)
    below.ClipType.Origin = p["slice"].SliceType.Origin
    below.ClipType.Normal = [0.0, 0.0, 1.0]
    skin_display = pvs.Show(below, view)
    pvs.ColorBy(skin_display, None)
    skin_display.AmbientColor = skin_display.DiffuseColor = [0.85, 0.75, 0.65]
    skin_display.Opacity = 0.35
    p["skin_below"] = below

    view.OrientationAxesVisibility = 0
    view.CameraPosition = [100.0, -260.0, 330.0]
    view.CameraFocalPoint = [100.0, 100.0, p["slice"].SliceType.Origin[2]]
    view.CameraViewUp = [0.0, 0.6, 0.8]
    view.ResetCamera(False)
    pvs.GetActiveCamera().Dolly(1.25)


def save_picture(picture, view, resolution):
    """Saves a view's or a layout's screenshot. An X server slow to come up
    under load can lose the first render: tries once more, and fails loudly
    rather than leave no picture."""
    for _ in range(2):
        if pvs.SaveScreenshot(picture, view, ImageResolution=resolution) and \
                os.path.isfile(picture) and os.path.getsize(picture) > 0:
            return
    sys.exit("could not write " + picture)


def summary(solver):
    fd = solver.FieldData
    return {name: fd[name].GetRange()[0] for name in
            ("ProbePoints", "TotalWalks", "SolveSeconds", "WalksPerSecond",
             "MeanStepsPerWalk", "EscapedWalkFraction")}


def run_headless(args):
    os.makedirs(args.output, exist_ok=True)
    volume = args.volume or os.path.join(data_folder(), VOLUME_NAME)
    p = build_pipeline(volume, args.walks, args.slice_z, args.seed, args.estimator, args.target,
                       args.walks_per_sphere, args.polynomial)
    p["solver"].UpdatePipeline()
    s = summary(p["solver"])
    # Under `mpirun -np N pvbatch` each rank solves its own piece of the slice.
    ranks = pvs.servermanager.ActiveConnection.GetNumberOfDataPartitions()
    if ranks > 1:
        print("ranks: %d" % ranks)
    print("points: %d" % p["solver"].GetDataInformation().GetNumberOfPoints())
    if args.estimator == "sphere":
        fd = p["solver"].FieldData
        print("sphere cache: %d points answered by %d spheres (%d walks), %d points walked "
              "near the skin" % (fd["PointsFromCache"].GetRange()[0],
                                 fd["CacheSpheres"].GetRange()[0], fd["CacheWalks"].GetRange()[0],
                                 fd["PointsWalkedInShell"].GetRange()[0]))
    print("walks%s: %d (%s per point, %.1f steps per walk)"
          % (" near the skin" if args.estimator == "sphere" else "", s["TotalWalks"],
             "at most %d" % args.walks if args.target > 0 else str(args.walks),
             s["MeanStepsPerWalk"]))
    cache_seconds = p["solver"].FieldData["CacheSeconds"].GetRange()[0] \
        if args.estimator == "sphere" else 0.0
    print("seconds: %.2f" % (s["SolveSeconds"] + cache_seconds))
    print("walks per second: %.0f" % s["WalksPerSecond"])
    p["streamlines"].UpdatePipeline()
    print("streamline points: %d" % p["streamlines"].GetDataInformation().GetNumberOfPoints())
    sys.stdout.flush()

    # Inline binary: Debian 12's patched expat makes ParaView 5.11 reject
    # VTK's default appended raw data when reading the files back.
    # Several ranks write one piece each, listed in a .pvtp.
    extension = "pvtp" if ranks > 1 else "vtp"
    names = ["ct_workflow_slice." + extension, "ct_workflow_streamlines." + extension]
    for name, key in zip(names, ("solver", "streamlines")):
        pvs.SaveData(os.path.join(args.output, name), proxy=p[key],
                     DataMode="Binary", CompressorType="ZLib")

    view = pvs.CreateView("RenderView")
    view.ViewSize = [1200, 900]
    view.UseColorPaletteForBackground = 0
    view.Background = [0.12, 0.12, 0.16]
    show(p, view)
    picture = os.path.join(args.output, "ct_workflow.png")
    save_picture(picture, view, [1200, 900])
    print("wrote %s, %s and %s" % (names[0], names[1], picture))
    return p


def run_in_gui():
    p = build_pipeline(os.path.join(data_folder(), VOLUME_NAME))
    view = pvs.GetActiveViewOrCreate("RenderView")
    show(p, view)
    # The Slice selected: its plane widget shows in the view, ready to drag.
    pvs.SetActiveSource(p["slice"])
    pvs.Render(view)


if __name__ == "__main__":
    argv = getattr(sys, "argv", [])[1:]
    if any(a.startswith("--output") for a in argv):
        run_headless(parse_arguments(argv))
    else:
        run_in_gui()
