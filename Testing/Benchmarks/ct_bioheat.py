"""Benchmark (not part of the tests): the steady Pennes bioheat equation on
the CT head, ∇·(k∇T) − w(T − T_a) + Q = 0, with the skin at 34 °C and the
arterial blood at 37 °C, solved on the CT workflow's slice
(Documentation/Examples/ct_workflow.py) to a target standard error at every
point inside the head, gradient on:

- varying coefficients: k, w and Q per voxel from a tissue table of the CT
  values (bioheat_tissues.py), smoothed by a Gaussian and the cubic B-spline;
- constant coefficients: the same equation with the brain's k, w and Q
  everywhere, solved as the screened Poisson equation (the walk the varying
  one is measured against: same boundary, slice, target and seed).

    pvbatch ct_bioheat.py [--target 0.05] [--most 2048] [--smoothing 2.0]
                          [--splitting 0|1]

Prints one row per solve (points inside the head, seconds, walks, steps per
walk, walks per second, RMS and largest standard error, and the gradient's
RMS standard error) and the ratio of
the costs at equal error, seconds × mean variance (time to an error scales
as the variance; screened walks rarely stop at the target, because their
uneven weights leave error bars the target mode does not trust, so most
points run to --most). Lengths
are millimetres, so k stays in W/(m K) and w, Q are scaled by 1e-6
(bioheat_tissues.py)."""
import argparse
import builtins
import math
import os
import sys

import paraview.simple as pvs
from paraview import servermanager

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "Documentation", "Examples"))
import bioheat_tissues  # noqa: E402
import ct_workflow  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument("--target", type=float, default=0.05, help="standard error (°C)")
parser.add_argument("--most", type=int, default=2048, help="the most walks per point")
parser.add_argument("--smoothing", type=float, default=2.0, help="Gaussian width (mm)")
parser.add_argument("--seed", type=int, default=1)
parser.add_argument("--splitting", type=int, choices=(0, 1), default=None,
                    help="Near-Boundary Splitting off (0) or on (1) for both solves "
                         "(default: the solver's default, on)")
parser.add_argument("--constant-tissue", default="brain",
                    choices=sorted(k for k, v in bioheat_tissues.TISSUES.items() if v),
                    help="whose k, w and Q the constant-coefficient walk takes")
args = parser.parse_args()

p = bioheat_tissues.head_inputs()
ct_array, inside, skin, tissues = p["ct_array"], p["inside"], p["skin_u"], p["tissues"]


def solver_of(equation):
    s = bioheat_tissues.bioheat_solver(skin, inside, tissues, constant=equation == "constant",
                                       walks=args.most, target=args.target,
                                       smoothing=args.smoothing, seed=args.seed,
                                       constant_tissue=args.constant_tissue)
    if args.splitting is not None:
        s.NearBoundarySplitting = args.splitting
    return s


def row(name, s):
    s.UpdatePipeline()
    data = servermanager.Fetch(s)
    ct = data.GetPointData().GetArray(ct_array)
    variance = data.GetPointData().GetArray("U_Variance")
    gradient_variance = data.GetPointData().GetArray("U_Gradient_Variance")
    inside_points = [i for i in range(data.GetNumberOfPoints())
                     if ct.GetTuple1(i) >= ct_workflow.SKIN_ISO_VALUE]
    errors = [math.sqrt(variance.GetTuple1(i)) for i in inside_points]
    mean_variance = math.fsum(e * e for e in errors) / len(errors)
    # The gradient's variance (summed over its components) where it is finite.
    gradient_sums = [math.fsum(gradient_variance.GetTuple(i)) for i in inside_points]
    gradient_sums = [v for v in gradient_sums if math.isfinite(v)]
    gradient_rms = math.sqrt(math.fsum(gradient_sums) / builtins.max(1, len(gradient_sums)))
    field = data.GetFieldData()
    seconds = field.GetArray("SolveSeconds").GetTuple1(0)
    walks = field.GetArray("TotalWalks").GetTuple1(0)
    steps = field.GetArray("MeanStepsPerWalk").GetTuple1(0)
    print("| %s | %d | %.2f | %.3g | %.1f | %.0f | %.3f | %.3f | %.4f |" % (
        name, len(errors), seconds, walks, steps, walks / seconds, math.sqrt(mean_variance),
        max(errors), gradient_rms), flush=True)
    # Time to a given error scales as seconds × variance: the cost at equal error.
    return seconds * mean_variance


print("| solve | points inside | seconds | walks | steps per walk | walks per second | "
      "RMS standard error (°C) | largest standard error (°C) | "
      "gradient's RMS standard error (°C/mm) |")
print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
# The boundary's hierarchy is built by a first, small update of each.
for equation in ("constant", "varying"):
    warm = solver_of(equation)
    warm.TargetStandardError = 0.0
    warm.WalksPerPoint = 1
    warm.UpdatePipeline()
    pvs.Delete(warm)
constant = row("constant coefficients (%s's k, w, Q)" % args.constant_tissue,
               solver_of("constant"))
varying = row("varying coefficients (tissue table, %.1f mm)" % args.smoothing,
              solver_of("varying"))
print("\ncost at equal error (seconds × mean variance): varying coefficients %.2f times the "
      "constant-coefficient walk" % (varying / constant))
