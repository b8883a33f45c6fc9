"""GridFree demo: heat in a living head, the steady Pennes bioheat equation
with the tissues' own conductivity, perfusion and metabolic heat taken from
the CT scan, solved on a slice with no volume mesh.

Run with pvbatch (the GridFree plugin loads through PV_PLUGIN_PATH, which
`./gridfree demo` sets):

    pvbatch bioheat_head.py --output output

    ∇·(k∇T) − w(T − T_a) + Q = 0 inside the head,  T = 34 °C on the skin,

with the arterial blood at T_a = 37 °C. The CT workflow's pipeline
(ct_workflow.py) gives the skin (the CT's iso-surface) and a horizontal
slice; a Programmable Filter turns the CT values into tissue classes and
their k, w and Q (bioheat_tissues.py: skin, fat, muscle, brain and bone,
values from the IT'IS database); the Walk On Spheres Solver's Varying
Coefficients equation solves for u = T − T_a at the slice's points inside
the head, to a target standard error. The same equation with the brain's k,
w and Q everywhere (constant coefficients, the screened Poisson equation)
is solved beside it for comparison. Writes into the output folder:
  bioheat_slice.vtp  the slice inside the head with T (tissue coefficients),
                     T_Variance, T_Gradient, T_Constant (the brain's
                     coefficients everywhere) and the CT values
  bioheat_slice.png  both temperatures side by side with isotherms every
                     0.25 °C and the bone's outline
and prints, per solve, points, walks, seconds and the error bars, then
where and by how much the tissues change the temperature.
"""
import argparse
import math
import os
import sys
# The Programmable Filter runs its script in this module's namespace under
# pvbatch, and its imports replace min and max by array reductions.
import builtins

import paraview.simple as pvs
from paraview import servermanager

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import bioheat_tissues  # noqa: E402
import ct_workflow  # noqa: E402


def parse_arguments():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--volume", help="the CT volume (default: Data/headsq_headCT.mhd)")
    parser.add_argument("--output", default="output", help="folder for the results")
    parser.add_argument("--target", type=float, default=0.05,
                        help="standard error to reach at every point (°C)")
    parser.add_argument("--walks", type=int, default=512, help="the most walks per point")
    parser.add_argument("--smoothing", type=float, default=2.0,
                        help="Gaussian width of the coefficients (mm)")
    parser.add_argument("--slice-z", type=float, default=70.0, help="height of the slice (mm)")
    parser.add_argument("--seed", type=int, default=0)
    return parser.parse_args()


def solve(name, solver):
    """Runs a solver, prints its figures and returns T = u + T_a with its
    variance and gradient, the slice's CT values passed through."""
    solver.UpdatePipeline()
    fd = solver.FieldData
    seconds = fd["SolveSeconds"].GetRange()[0]
    walks = fd["TotalWalks"].GetRange()[0]
    data = servermanager.Fetch(solver)
    variance = data.GetPointData().GetArray("U_Variance")
    errors = [math.sqrt(variance.GetTuple1(i)) for i in range(data.GetNumberOfPoints())]
    rms = math.sqrt(math.fsum(e * e for e in errors) / builtins.max(len(errors), 1))
    print(f"{name}: {data.GetNumberOfPoints()} points, {walks:.0f} walks, {seconds:.2f} s, "
          f"standard error RMS {rms:.3f} °C, largest {builtins.max(errors, default=0.0):.3f} °C")
    sys.stdout.flush()
    return pvs.Calculator(Input=solver, ResultArrayName="T",
                          Function="U + %g" % bioheat_tissues.ARTERIAL_TEMPERATURE)


def main():
    args = parse_arguments()
    os.makedirs(args.output, exist_ok=True)
    # The CT workflow's skin, padded volume and slice, the slice's points
    # inside the head (where the equation holds), the skin at u = −3 °C and
    # the tissue arrays (ct_workflow.build_pipeline stops with a message when
    # the plugin is not loaded).
    p = bioheat_tissues.head_inputs(args.volume, args.slice_z)
    ct_array, inside, skin, tissues = p["ct_array"], p["inside"], p["skin_u"], p["tissues"]
    (x0, x1, y0, y1, _, _) = p["volume"].GetDataInformation().GetBounds()

    options = dict(walks=args.walks, target=args.target, smoothing=args.smoothing,
                   seed=args.seed)
    varying = solve("tissue coefficients from the CT",
                    bioheat_tissues.bioheat_solver(skin, inside, tissues, **options))
    constant = solve("the brain's coefficients everywhere",
                     bioheat_tissues.bioheat_solver(skin, inside, tissues, constant=True,
                                                    **options))

    # One dataset: T with its variance and gradient (those of u), and T_Constant.
    renamed = pvs.Calculator(Input=constant, ResultArrayName="T_Constant", Function="T")
    output = pvs.AppendAttributes(Input=[
        pvs.PassArrays(Input=varying, PointDataArrays=["T", "U_Variance", "U_Gradient",
                                                        ct_array]),
        pvs.PassArrays(Input=renamed, PointDataArrays=["T_Constant"])])
    output = pvs.Calculator(Input=output, ResultArrayName="T_Variance", Function="U_Variance")
    output = pvs.Calculator(Input=output, ResultArrayName="T_Gradient", Function="U_Gradient",
                            ResultArrayType="Double")
    output = pvs.PassArrays(Input=output, PointDataArrays=["T", "T_Variance", "T_Gradient",
                                                            "T_Constant", ct_array])
    # The Threshold's cells as polygons again, for a .vtp.
    output = pvs.ExtractSurface(Input=output)
    # Inline binary: Debian 12's patched expat makes ParaView 5.11 reject
    # VTK's default appended raw data when reading the files back.
    slice_file = os.path.join(args.output, "bioheat_slice.vtp")
    pvs.SaveData(slice_file, proxy=output, DataMode="Binary", CompressorType="ZLib")

    data = servermanager.Fetch(output)
    t = data.GetPointData().GetArray("T")
    tc = data.GetPointData().GetArray("T_Constant")
    ct = data.GetPointData().GetArray(ct_array)
    differences = [t.GetTuple1(i) - tc.GetTuple1(i) for i in range(data.GetNumberOfPoints())]
    in_bone = [d for i, d in enumerate(differences)
               if ct.GetTuple1(i) > bioheat_tissues.BONE_ABOVE]
    print(f"T with tissue coefficients: {t.GetRange()[0]:.2f} to {t.GetRange()[1]:.2f} °C; "
          f"with the brain's everywhere: {tc.GetRange()[0]:.2f} to {tc.GetRange()[1]:.2f} °C")
    print(f"tissue minus constant: mean {math.fsum(differences) / len(differences):+.3f} °C, "
          f"from {builtins.min(differences):+.3f} to {builtins.max(differences):+.3f} °C"
          + (f"; in bone {math.fsum(in_bone) / len(in_bone):+.3f} °C on average"
             if in_bone else ""))
    sys.stdout.flush()

    # Both temperatures side by side, one colour scale, isotherms every
    # 0.25 °C (light blue) and the outline of the bone (white).
    low = builtins.min(t.GetRange()[0], tc.GetRange()[0])
    high = builtins.max(t.GetRange()[1], tc.GetRange()[1])
    bone = pvs.Contour(Input=output, ContourBy=["POINTS", ct_array],
                       Isosurfaces=[bioheat_tissues.BONE_ABOVE])
    layout = pvs.CreateLayout("Bioheat")
    layout.SplitHorizontal(0, 0.5)
    panels = [("T_Constant", "T (°C): the brain's k, w, Q everywhere"),
              ("T", "T (°C): k, w, Q of the tissues from the CT")]
    centre = [0.5 * (x0 + x1), 0.5 * (y0 + y1), args.slice_z]
    for cell, (array, title) in zip((1, 2), panels):
        view = pvs.CreateView("RenderView")
        layout.AssignView(cell, view)
        view.OrientationAxesVisibility = 0
        view.UseColorPaletteForBackground = 0
        view.Background = [0.12, 0.12, 0.16]
        display = pvs.Show(output, view)
        pvs.ColorBy(display, ("POINTS", array))
        lut = pvs.GetColorTransferFunction(array)
        lut.ApplyPreset("Inferno (matplotlib)", True)
        lut.RescaleTransferFunction(low, high)
        display.SetScalarBarVisibility(view, True)
        bar = pvs.GetScalarBar(lut, view)
        bar.Title = title
        bar.ComponentTitle = ""
        bar.WindowLocation = "Upper Center"
        bar.Orientation = "Horizontal"
        bar.LabelFormat = "%-#.2f"
        bar.RangeLabelFormat = "%-#.2f"
        levels = [math.ceil(low * 4.0) / 4.0 + 0.25 * k
                  for k in range(int((high - low) * 4.0) + 1)]
        isotherms = pvs.Contour(Input=output, ContourBy=["POINTS", array], Isosurfaces=levels)
        lines = pvs.Show(isotherms, view)
        lines.ColorArrayName = ["POINTS", ""]
        lines.AmbientColor = lines.DiffuseColor = [0.3, 0.8, 1.0]
        lines.LineWidth = 1.5
        outline = pvs.Show(bone, view)
        outline.ColorArrayName = ["POINTS", ""]
        outline.AmbientColor = outline.DiffuseColor = [1.0, 1.0, 1.0]
        outline.LineWidth = 2.0
        view.CameraFocalPoint = centre
        view.CameraPosition = [centre[0], centre[1], centre[2] + 4.0 * (x1 - x0)]
        view.CameraViewUp = [0.0, 1.0, 0.0]
        view.ResetCamera(False)

    picture = os.path.join(args.output, "bioheat_slice.png")
    ct_workflow.save_picture(picture, layout, [1280, 640])
    print(f"wrote {slice_file} and {picture}")


if __name__ == "__main__":
    main()
