"""Benchmark (not part of the tests): error bars of 2D data with a narrow
peak, through the solver, with uniform steps (Peak Steps Uniform) and with
Peak Steps Automatic, which leans toward the peak of screened data. The
unit circle (2,048 segments) with the 2D Yukawa data K0(√c s)
(c = 6.25) or the Laplace data −log s of a pole at (1.05, 0.1), 0.055
outside it, s the distance to the pole; 300 random points in the disk
(seed 5), 256 walks.

    PYTHONPATH=build/lib/python3.11/site-packages /usr/bin/python3 \\
        Testing/Benchmarks/peak_steps_2d.py [--walks 256] [--walk-on 1] [--seeds 3,4,5]

Prints, per case, Peak Steps and seed: mean z², largest |z|, points
flagged, points missed (|z| > 5 and not flagged), the mean z² of the
flagged and of the unflagged points (right flags have the first well
above 1), the RMS error and the solve's seconds. Documentation/ErrorBars.md has its figures.
"""
import argparse
import math
import os
import random
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "Python"))

import gridfree  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkDataObject  # noqa: E402
from gridfree_testing import circle_boundary, point_cloud  # noqa: E402

POLE = (1.05, 0.1)
T = np.linspace(0.0, 12.0, 20001)


def bessel_k0(z):
    """K0(z) = ∫_0^∞ e^{−z cosh t} dt, by the trapezoidal rule (z ≥ 0.1)."""
    return float(np.trapz(np.exp(-z * np.cosh(T)), T))


def solve(points, exact, screening, peak_steps, seed, args):
    solver = gridfree.vtkWalkOnSpheresSolver()
    solver.SetBoundaryData(circle_boundary(exact))
    solver.SetProbeData(point_cloud(points))
    solver.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS, "T")
    solver.SetWalksPerPoint(args.walks)
    solver.SetWalkOnWhereUnreliable(args.walk_on)
    solver.SetSeed(seed)
    solver.SetPeakSteps(peak_steps)
    if screening > 0.0:
        solver.SetEquation(gridfree.vtkWalkOnSpheresSolver.SCREENED_POISSON)
        solver.SetScreeningCoefficient(screening)
    start = time.perf_counter()
    solver.Update()
    seconds = time.perf_counter() - start
    output = solver.GetOutput()
    data = output.GetPointData()
    values, variances = data.GetArray("T"), data.GetArray("T_Variance")
    reliable = data.GetArray("T_VarianceReliable")
    n = output.GetNumberOfPoints()
    errors = [values.GetTuple1(i) - exact(*output.GetPoint(i)) for i in range(n)]
    z = [errors[i] / math.sqrt(variances.GetTuple1(i)) for i in range(n)]
    flagged = [v for i, v in enumerate(z) if reliable.GetValue(i) == 0]
    unflagged = [v for i, v in enumerate(z) if reliable.GetValue(i) == 1]
    missed = sum(1 for v in unflagged if abs(v) > 5.0)

    def mean_z2(values):
        return sum(v * v for v in values) / len(values) if values else float("nan")

    print("  %-9s seed %d: mean z² %.2f, largest |z| %.2f, flagged %d, missed %d; "
          "mean z² of flagged / unflagged points %.2f / %.2f; RMS error %.2e, %.2f s" % (
              "uniform" if peak_steps == 1 else "automatic", seed, mean_z2(z), max(abs(v) for v in z), len(flagged), missed,
              mean_z2(flagged), mean_z2(unflagged),
              math.sqrt(sum(e * e for e in errors) / n), seconds), flush=True)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--walks", type=int, default=256)
    parser.add_argument("--walk-on", type=int, default=1,
                        help="Walk On Where Unreliable (1: off; the solver's default is 4)")
    parser.add_argument("--seeds", default="3,4,5", help="the walks' seeds")
    args = parser.parse_args()
    rng = random.Random(5)
    points = []
    while len(points) < 300:
        x, y = rng.uniform(-1, 1), rng.uniform(-1, 1)
        if x * x + y * y < 0.95 ** 2:
            points.append((x, y, 0.0))
    for screening in (6.25, 0.0):
        k = math.sqrt(screening)
        if screening > 0.0:
            def exact(x, y, z):
                return bessel_k0(k * math.hypot(x - POLE[0], y - POLE[1]))
        else:
            def exact(x, y, z):
                return -math.log(math.hypot(x - POLE[0], y - POLE[1]))
        print("2D unit circle, c = %g, %s of a pole at (%g, %g), %d walks, walk on %d" % (
            screening, "K0(sqrt(c) s)" if screening > 0.0 else "-log s", POLE[0], POLE[1],
            args.walks, args.walk_on))
        for peak_steps in (1, 0):
            for seed in (int(s) for s in args.seeds.split(",")):
                solve(points, exact, screening, peak_steps, seed, args)


if __name__ == "__main__":
    main()
