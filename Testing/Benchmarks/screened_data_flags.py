"""Benchmark (not part of the tests): how many points of a screened problem
with right error bars does the solver flag unreliable, with its boundary
values read from an array (bounds known: the array's range) and from
BoundaryValueExpression (its range sampled at the mesh's points and cell
centers)? Screened Poisson, c = 9 on the unit disk with u = e^{3x}, and
c = 4 in the unit ball with u = e^{2x}; 300 random points each (seed 5),
walk seed 3 unless told.

With --source, screened problems with a volume source instead, radial
data plus a tilt: u = I0(3r) + 5 + 2x on the disk (c = 9, f = −45 − 18x) and
u = sinh(2r)/(2r) + 5 + 2x in the ball (c = 4, f = −20 − 8x), the source
given as an expression in x (whose range the solver samples) and, for
comparison, under Source Sampling Uniform (whose samples it cannot bound).

With --other-geometry, boundaries that are not meshes, their data from
Boundary Value Expression: an implicit unit sphere (vtkSignedDistanceSphere)
with u = e^{2x} at c = 4 and with the plane wave u = e^{20x - 10} at
c = 400, and the unit circle as eight cubic Bézier arcs with u = e^{3x} at
c = 9 (the data are exact wherever they are read, round or not), and a
narrow peak on the implicit sphere: the potential of a charge at
a = (1.05, 0.1, 0), 0.055 outside it, 1/|x - a| for the Laplace equation
and e^{-2.5|x - a|}/|x - a| at c = 6.25.

    PYTHONPATH=build/lib/python3.11/site-packages /usr/bin/python3 \\
        Testing/Benchmarks/screened_data_flags.py [--walks 256] [--walk-on 4] [--seed 3] \\
        [--screened-steps 0] [--peak-steps 0] [--source | --other-geometry]

Prints, per case and data: points, mean z², largest |z|, points flagged and
points missed (|z| > 5 and not flagged), the mean z² of the flagged and
of the unflagged points, the RMS error and the solve's seconds.
Documentation/ErrorBars.md has its figures.
"""
import argparse
import math
import os
import random
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "Python"))

import gridfree  # noqa: E402
from vtkmodules.vtkCommonCore import vtkIntArray, vtkPoints  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkDataObject, vtkPolyData  # noqa: E402
from gridfree_testing import (  # noqa: E402
    bessel_i0, circle_boundary, point_cloud, sphere_boundary)


def solve(boundary, points, exact, screening, expression, args, source=None, label=None,
          implicit=None):
    solver = gridfree.vtkWalkOnSpheresSolver()
    if implicit:
        solver.SetImplicitBoundary(implicit)
    else:
        solver.SetBoundaryData(boundary)
    solver.SetProbeData(point_cloud(points))
    solver.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS, "T")
    solver.SetWalksPerPoint(args.walks)
    solver.SetWalkOnWhereUnreliable(args.walk_on)
    solver.SetSeed(args.seed)
    if screening > 0:
        solver.SetEquation(gridfree.vtkWalkOnSpheresSolver.SCREENED_POISSON)
        solver.SetScreeningCoefficient(screening)
    else:
        solver.SetEquation(gridfree.vtkWalkOnSpheresSolver.LAPLACE)
    solver.SetScreenedSteps(args.screened_steps)
    solver.SetPeakSteps(args.peak_steps)
    if expression:
        solver.SetBoundaryValueExpression(expression)
    if source:
        solver.SetSourceExpression(source[0])
        solver.SetSourceSampling(source[1])
    start = time.perf_counter()
    solver.Update()
    seconds = time.perf_counter() - start
    output = solver.GetOutput()
    name = "Solution" if expression else "T"
    data = output.GetPointData()
    values, variances = data.GetArray(name), data.GetArray(name + "_Variance")
    reliable = data.GetArray(name + "_VarianceReliable")
    z = [(values.GetTuple1(i) - exact(*output.GetPoint(i))) / math.sqrt(variances.GetTuple1(i))
         for i in range(output.GetNumberOfPoints())]
    flagged = [v for i, v in enumerate(z) if reliable.GetValue(i) == 0]
    unflagged = [v for i, v in enumerate(z) if reliable.GetValue(i) == 1]
    missed = sum(1 for v in unflagged if abs(v) > 5.0)
    rms = math.sqrt(sum((values.GetTuple1(i) - exact(*output.GetPoint(i))) ** 2
                        for i in range(output.GetNumberOfPoints())) / output.GetNumberOfPoints())

    def mean_z2(values):
        return sum(v * v for v in values) / len(values) if values else float("nan")

    # The flagged points' mean z² against the others' says whether the flags
    # are right (their bars measurably too small) or false alarms.
    print("  %-12s points %d, mean z² %.2f, largest |z| %.2f, flagged %d, missed %d; "
          "mean z² of flagged / unflagged points %.2f / %.2f; RMS error %.2e, %.2f s" % (
              label or ("expression" if expression else "array"), len(z), mean_z2(z),
              max(abs(v) for v in z), len(flagged), missed, mean_z2(flagged),
              mean_z2(unflagged), rms, seconds), flush=True)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--walks", type=int, default=256)
    parser.add_argument("--walk-on", type=int, default=4, help="Walk On Where Unreliable (1: off)")
    parser.add_argument("--seed", type=int, default=3, help="the walks' seed")
    parser.add_argument("--screened-steps", type=int, default=0,
                        help="Screened Steps: 0 Automatic, 1 Uniform, 2 Guided")
    parser.add_argument("--peak-steps", type=int, default=0,
                        help="Peak Steps: 0 Automatic, 1 Uniform, 2 Guided")
    parser.add_argument("--source", action="store_true",
                        help="the cases with a volume source in x")
    parser.add_argument("--other-geometry", action="store_true",
                        help="implicit and Bezier boundaries")
    args = parser.parse_args()
    rng = random.Random(5)
    if args.source:
        with_source(rng, args)
        return
    if args.other_geometry:
        other_geometry(rng, args)
        return

    disk = []
    while len(disk) < 300:
        x, y = rng.uniform(-1, 1), rng.uniform(-1, 1)
        if x * x + y * y < 0.95 ** 2:
            disk.append((x, y, 0.0))
    exact = lambda x, y, z: math.exp(3.0 * x)  # noqa: E731
    print("2D unit disk, c = 9, u = e^{3x}, %d walks, walk on %d, seed %d" % (
        args.walks, args.walk_on, args.seed))
    for expression in (None, "exp(3*x)"):
        solve(circle_boundary(exact), disk, exact, 9.0, expression, args)

    ball = []
    while len(ball) < 300:
        x, y, z = rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)
        if x * x + y * y + z * z < 0.9 ** 2:
            ball.append((x, y, z))
    exact = lambda x, y, z: math.exp(2.0 * x)  # noqa: E731
    print("3D unit ball, c = 4, u = e^{2x}, %d walks, walk on %d, seed %d" % (
        args.walks, args.walk_on, args.seed))
    for expression in (None, "exp(2*x)"):
        solve(sphere_boundary(exact), ball, exact, 4.0, expression, args)


def with_source(rng, args):
    automatic = gridfree.vtkWalkOnSpheresSolver.AUTOMATIC_SOURCE_SAMPLING
    uniform = gridfree.vtkWalkOnSpheresSolver.UNIFORM
    disk = []
    while len(disk) < 300:
        x, y = rng.uniform(-1, 1), rng.uniform(-1, 1)
        if x * x + y * y < 0.95 ** 2:
            disk.append((x, y, 0.0))
    exact = lambda x, y, z: bessel_i0(3.0 * math.hypot(x, y)) + 5.0 + 2.0 * x  # noqa: E731
    print("2D unit disk, c = 9, u = I0(3r) + 5 + 2x, f = -45 - 18x, %d walks, walk on %d, "
          "seed %d" % (args.walks, args.walk_on, args.seed))
    for sampling, label in ((automatic, "sampled f"), (uniform, "uniform")):
        solve(circle_boundary(exact), disk, exact, 9.0, None, args, ("-45 - 18*x", sampling),
              label)

    def radial(r):
        return math.sinh(2.0 * r) / (2.0 * r) if r > 1e-8 else 1.0

    ball = []
    while len(ball) < 300:
        x, y, z = rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)
        if x * x + y * y + z * z < 0.9 ** 2:
            ball.append((x, y, z))
    exact = lambda x, y, z: radial(math.sqrt(x * x + y * y + z * z)) + 5.0 + 2.0 * x  # noqa: E731
    print("3D unit ball, c = 4, u = sinh(2r)/(2r) + 5 + 2x, f = -20 - 8x, %d walks, walk on %d, "
          "seed %d" % (args.walks, args.walk_on, args.seed))
    for sampling, label in ((automatic, "sampled f"), (uniform, "uniform")):
        solve(sphere_boundary(exact), ball, exact, 4.0, None, args, ("-20 - 8*x", sampling), label)


def bezier_circle(arcs=8):
    """The unit circle as `arcs` cubic Bézier arcs (handles at
    4/3 tan(pi / (2 arcs))), one closed polyline marked BezierControlPoints."""
    handle = 4.0 / 3.0 * math.tan(math.pi / (2 * arcs))
    points = vtkPoints()
    points.SetDataTypeToDouble()
    for i in range(arcs):
        a0, a1 = 2 * math.pi * i / arcs, 2 * math.pi * (i + 1) / arcs
        p0 = (math.cos(a0), math.sin(a0))
        p3 = (math.cos(a1), math.sin(a1))
        points.InsertNextPoint(p0[0], p0[1], 0.0)
        points.InsertNextPoint(p0[0] - handle * p0[1], p0[1] + handle * p0[0], 0.0)
        points.InsertNextPoint(p3[0] + handle * p3[1], p3[1] - handle * p3[0], 0.0)
    lines = vtkCellArray()
    lines.InsertNextCell(3 * arcs + 1)
    for i in range(3 * arcs + 1):
        lines.InsertCellPoint(i % (3 * arcs))
    marks = vtkIntArray()
    marks.SetName("BezierControlPoints")
    marks.InsertNextValue(1)
    curve = vtkPolyData()
    curve.SetPoints(points)
    curve.SetLines(lines)
    curve.GetCellData().AddArray(marks)
    return curve


def other_geometry(rng, args):
    ball = []
    while len(ball) < 300:
        x, y, z = rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)
        if x * x + y * y + z * z < 0.9 ** 2:
            ball.append((x, y, z))
    sphere = gridfree.vtkSignedDistanceSphere()
    sphere.SetRadius(1.0)
    print("3D implicit unit sphere, %d walks, walk on %d, seed %d, Screened Steps %d" % (
        args.walks, args.walk_on, args.seed, args.screened_steps))
    solve(None, ball, lambda x, y, z: math.exp(2.0 * x), 4.0, "exp(2*x)", args,
          label="c = 4", implicit=sphere)
    solve(None, ball, lambda x, y, z: math.exp(20.0 * x - 10.0), 400.0, "exp(20*x - 10)", args,
          label="c = 400", implicit=sphere)
    charge = "sqrt((x - 1.05)^2 + (y - 0.1)^2 + z^2)"
    distance = lambda x, y, z: math.dist((x, y, z), (1.05, 0.1, 0.0))  # noqa: E731
    solve(None, ball, lambda x, y, z: 1.0 / distance(x, y, z), 0.0, "1/" + charge, args,
          label="Coulomb", implicit=sphere)
    solve(None, ball, lambda x, y, z: math.exp(-2.5 * distance(x, y, z)) / distance(x, y, z), 6.25,
          "exp(-2.5*%s)/%s" % (charge, charge), args, label="Yukawa", implicit=sphere)
    disk = []
    while len(disk) < 300:
        x, y = rng.uniform(-1, 1), rng.uniform(-1, 1)
        if x * x + y * y < 0.95 ** 2:
            disk.append((x, y, 0.0))
    print("2D circle of 8 Bezier arcs, c = 9, u = e^{3x}")
    solve(bezier_circle(), disk, lambda x, y, z: math.exp(3.0 * x), 9.0, "exp(3*x)", args,
          label="Bezier")


if __name__ == "__main__":
    main()
