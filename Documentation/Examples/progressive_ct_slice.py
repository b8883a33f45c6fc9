"""Progressive refinement on the CT slice: a quick preview with few walks,
then Refine (the GUI's button) doubles the walks and runs only the new ones.

Run with pvbatch (the GridFree plugin loads through PV_PLUGIN_PATH, which
`./gridfree env` prints):

    pvbatch progressive_ct_slice.py --data Data/headsq_skin_iso500_closed.vtp

Prints, for each stage, the walks per point, the walks run by that stage, its
seconds and the slice's median standard error; at the end checks that the
refined slice equals one solve with all the walks, bit for bit.
"""
import argparse
import statistics
import sys

import paraview.simple as pvs
from paraview import servermanager

from head_ct_demo import TEMPERATURE  # the demo's boundary temperature


def parse_arguments():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", required=True, help="skin surface (.vtp)")
    parser.add_argument("--resolution", type=int, default=200,
                        help="slice points along each side")
    parser.add_argument("--walks", type=int, default=8, help="walks per point of the preview")
    parser.add_argument("--refinements", type=int, default=3, help="times to press Refine")
    return parser.parse_args()


def solver_on_slice(boundary, args, walks):
    (xmin, xmax, ymin, ymax, zmin, zmax) = boundary.GetDataInformation().GetBounds()
    margin = 0.05 * (xmax - xmin)
    zmid = 0.5 * (zmin + zmax)
    probe = pvs.Plane(Origin=[xmin - margin, ymin - margin, zmid],
                      Point1=[xmax + margin, ymin - margin, zmid],
                      Point2=[xmin - margin, ymax + margin, zmid],
                      XResolution=args.resolution - 1, YResolution=args.resolution - 1)
    solver = pvs.WalkOnSpheresSolver(Boundary=boundary, Probe=probe)
    solver.BoundaryValues = ["POINTS", "T"]
    solver.WalksPerPoint = walks
    solver.ControlVariates = 0
    return solver


def stage(solver, label, walks):
    solver.UpdatePipeline()
    data = servermanager.Fetch(solver)
    variance = data.GetPointData().GetArray("T_Variance")
    errors = [variance.GetTuple1(i) ** 0.5 for i in range(variance.GetNumberOfTuples())]
    field = data.GetFieldData()
    resumed = field.GetArray("ResumedWalksPerPoint").GetValue(0)
    run = int(field.GetArray("TotalWalks").GetValue(0) - resumed * data.GetNumberOfPoints())
    seconds = field.GetArray("SolveSeconds").GetValue(0)
    print(f"| {label} | {walks} | {run} | {seconds:.2f} | {statistics.median(errors):.3f} |")
    sys.stdout.flush()
    return data


def main():
    args = parse_arguments()
    if not hasattr(pvs, "WalkOnSpheresSolver"):
        sys.exit("The GridFree plugin is not loaded: set PV_PLUGIN_PATH to its folder.")
    skin = pvs.XMLPolyDataReader(FileName=[args.data])
    boundary = pvs.Calculator(Input=skin, ResultArrayName="T", Function=TEMPERATURE)
    boundary.UpdatePipeline()

    solver = solver_on_slice(boundary, args, args.walks)
    print(f"{args.resolution}² slice points.\n")
    print("| stage | walks per point | walks run | seconds | median standard error (°) |")
    print("|---|---:|---:|---:|---:|")
    walks = args.walks
    data = stage(solver, "preview", walks)
    for k in range(args.refinements):
        solver.SMProxy.InvokeCommand("Refine")
        walks *= 2
        data = stage(solver, f"Refine {k + 1}", walks)

    once = solver_on_slice(boundary, args, walks)
    reference = stage(once, "one solve", walks)
    a, b = data.GetPointData().GetArray("T"), reference.GetPointData().GetArray("T")
    same = all(a.GetTuple1(i) == b.GetTuple1(i) for i in range(a.GetNumberOfTuples()))
    print(f"\nrefined slice equals one solve with {walks} walks: {same}")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
