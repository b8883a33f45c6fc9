"""Benchmark (not part of the tests): are the error bars of the CT
workflow's default solve (Documentation/Examples/ct_workflow.py: 4,096 slice
points, 128 walks, gradient on) right where the solver flags them
unreliable, and where it does not?

The points flagged by the default solve, and a sample of unflagged ones,
are solved again with --reference walks (the reference) and with 128 walks
for each of --seeds seeds; z = (T − reference) / sqrt(var + reference var).
Prints, for both sets, the number of z values, their mean z², the largest
|z| and how often the 128-walk solves flagged them, then each miss (an
unflagged |z| > 5): its point, distance from the skin, seed and numbers.

    pvbatch ct_error_bars.py [--seeds 10] [--reference 32768] [--sample 150] [--polynomial 6]
                             [--splitting 0|1] [--sampling "Green's Function"]
"""
import argparse
import math
import os
import random
import sys

from paraview import servermanager

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "Documentation", "Examples"))
sys.path.insert(0, HERE)
import ct_workflow  # noqa: E402
import seeded_solves  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument("--seeds", type=int, default=10)
parser.add_argument("--reference", type=int, default=32768, help="walks of the reference")
parser.add_argument("--sample", type=int, default=150, help="unflagged points checked")
parser.add_argument("--polynomial", type=int, default=6,
                    help="degree of the polynomial control variate (0: none)")
parser.add_argument("--splitting", type=int, default=-1,
                    help="near-boundary splitting in every solve (0: off, 1: on; "
                         "default: the solver's default, on)")
parser.add_argument("--sampling", default="",
                    help="Source Sampling in every solve, e.g. \"Green's Function\" "
                         "(default: the solver's default, Automatic)")
args = parser.parse_args()

p = ct_workflow.build_pipeline(os.path.join(ct_workflow.data_folder(), ct_workflow.VOLUME_NAME),
                               polynomial=args.polynomial)
solver = p["solver"]
if args.splitting >= 0:
    solver.NearBoundarySplitting = args.splitting
if args.sampling:
    solver.SourceSampling = args.sampling
solver.UpdatePipeline()
first = servermanager.Fetch(solver)
data = first.GetPointData()
reliable = data.GetArray("T_VarianceReliable")
values = data.GetArray("T")
used = first.GetFieldData().GetArray("SourceSamplingUsed")
sampling = {1: "Green's Function", 3: "Source Density"}.get(
    int(used.GetTuple1(0)) if used else 0, "other")
flagged = [i for i in range(first.GetNumberOfPoints()) if reliable.GetValue(i) == 0]
unflagged = [i for i in range(first.GetNumberOfPoints())
             if reliable.GetValue(i) == 1 and not math.isnan(values.GetValue(i))]
random.seed(3)
ids = flagged + random.sample(unflagged, min(args.sample, len(unflagged)))

solver.Probe = seeded_solves.point_probe(first, ids)
solver.ComputeGradient = 0


def solve(walks, seed):
    return seeded_solves.solve(solver, walks, seed, "T")


reference = solve(args.reference, 99)
rows = {"flagged by the default solve": ([], 0), "a sample of the unflagged": ([], 0)}
misses = {}
missed = []  # (point, seed, z, T, reference, its standard error, the reference's)
for seed in range(1, args.seeds + 1):
    for k, (t, v, r) in enumerate(solve(128, seed)):
        name = "flagged by the default solve" if k < len(flagged) else "a sample of the unflagged"
        z, n = rows[name]
        ref, ref_var = reference[k][0], reference[k][1]
        z.append((t - ref) / math.sqrt(v + ref_var) if v + ref_var > 0.0 else 0.0)
        rows[name] = (z, n + (1 if r == 0 else 0))
        misses[name] = misses.get(name, 0) + (1 if r == 1 and abs(z[-1]) > 5.0 else 0)
        if r == 1 and abs(z[-1]) > 5.0:
            missed.append((ids[k], seed, z[-1], t, ref, math.sqrt(v), math.sqrt(ref_var)))

print("CT workflow, default solve: %d of %d points flagged; reference %d walks, %d seeds of 128;"
      " near-boundary splitting %s; source sampling %s" % (
          len(flagged), first.GetNumberOfPoints(), args.reference, args.seeds,
          "on" if solver.NearBoundarySplitting else "off", sampling))
print("| points | z values | mean z² | largest |z| | flagged again | missed (|z| > 5, unflagged) |")
print("|---|---:|---:|---:|---:|---:|")
for name, (z, n) in rows.items():
    if not z:
        print("| %s | 0 | — | — | — | — |" % name)
        continue
    print("| %s | %d | %.2f | %.2f | %d | %d |" % (
        name, len(z), math.fsum(x * x for x in z) / len(z), max(abs(x) for x in z), n,
        misses.get(name, 0)))
distance = first.GetPointData().GetArray("BoundaryDistance")
for (i, seed, z, t, ref, se, ref_se) in missed:
    print("missed: point %d (%.2f from the skin), seed %d: z %.2f, T %.4f ± %.4f, reference %.4f ± %.4f"
          % (i, distance.GetValue(i) if distance else float("nan"), seed, z, t, se, ref, ref_se))
