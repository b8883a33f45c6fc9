"""Error bars users can trust, through the solver's VTK API: points whose
error bar cannot be trusted are flagged in T_VarianceReliable, counted (the
field UnreliableErrorBars, GetLastUnreliableErrorBars) and announced once;
a light-tailed problem gives none; fixed-count solves (by default) and
target-error mode walk on at flagged points (Core.ErrorBarReliability.* has
the held-out cases and the rule)."""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import gridfree  # noqa: E402
from vtkmodules.vtkCommonCore import vtkPoints  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkDataObject, vtkPolyData  # noqa: E402
from gridfree_testing import (  # noqa: E402
    MessageCatcher,
    bessel_i0,
    circle_boundary,
    sphere_boundary,
    z_scores,
)

POINTS = vtkDataObject.FIELD_ASSOCIATION_POINTS


def probe(points):
    data = vtkPolyData()
    vtk_points = vtkPoints()
    for p in points:
        vtk_points.InsertNextPoint(*p)
    data.SetPoints(vtk_points)
    return data


# 100 points on a line through the unit ball, and on a line across the disk.
LINE = probe([(-0.85 + 1.7 * i / 99, 0.1, 0.05) for i in range(100)])
DISK_LINE = probe([(0.3, -0.9 + 1.8 * i / 99, 0.0) for i in range(100)])


def solver_for(boundary, points, walks, screening=None, target=0.0):
    solver = gridfree.vtkWalkOnSpheresSolver()
    solver.SetBoundaryData(boundary)
    solver.SetProbeData(points)
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    solver.SetWalksPerPoint(walks)
    solver.SetSeed(3)
    if screening is not None:
        solver.SetEquation(gridfree.vtkWalkOnSpheresSolver.SCREENED_POISSON)
        solver.SetScreeningCoefficient(screening)
    solver.SetTargetStandardError(target)
    return solver


def flags(output):
    array = output.GetPointData().GetArray("T_VarianceReliable")
    return [int(array.GetValue(i)) for i in range(array.GetNumberOfTuples())]


def field(output, name):
    return output.GetFieldData().GetArray(name).GetValue(0)


def test_strong_screening_is_flagged_and_announced():
    # u = e^{10x} solves Δu − 100u = 0: with uniform steps the value rests
    # on rare walks.
    boundary = sphere_boundary(lambda x, y, z: math.exp(10.0 * x))
    solver = solver_for(boundary, LINE, 256, screening=100.0)
    solver.SetScreenedSteps(gridfree.vtkWalkOnSpheresSolver.SCREENED_STEPS_UNIFORM)
    catcher = MessageCatcher(solver)
    solver.Update()
    output = solver.GetOutput()
    reliable = flags(output)
    unreliable = reliable.count(0)
    assert unreliable > 30
    assert solver.GetLastUnreliableErrorBars() == unreliable
    assert field(output, "UnreliableErrorBars") == unreliable
    scores = z_scores(output, lambda x, y, z: math.exp(10.0 * x))
    assert all(r == 0 for r, z in zip(reliable, scores) if not abs(z) < 5.0)
    assert len(catcher.warnings) == 1, catcher.warning_text()
    text = catcher.warnings[0]
    assert "%d of 100 probe points have error bars that cannot be trusted" % unreliable in text
    assert "T_VarianceReliable = 0" in text and "screening weights are very uneven" in text
    relative = output.GetPointData().GetArray("T_VarianceRelativeError")
    assert all(0.0 <= relative.GetValue(i) <= 1.0 for i in range(100))


def test_strong_screening_takes_guided_steps_with_right_error_bars():
    # The same problem with the default steps: √c × the diagonal is about
    # 35, so steps are guided; every error bar is right and none is flagged.
    exact = lambda x, y, z: math.exp(10.0 * x)  # noqa: E731
    boundary = sphere_boundary(exact)
    solver = solver_for(boundary, LINE, 256, screening=100.0)
    assert solver.GetScreenedSteps() == solver.SCREENED_STEPS_AUTOMATIC
    catcher = MessageCatcher(solver)
    solver.Update()
    output = solver.GetOutput()
    assert flags(output).count(0) == 0
    assert not catcher.warnings, catcher.warning_text()
    scores = z_scores(output, exact)
    assert max(abs(z) for z in scores) < 5.0
    assert 0.6 < sum(z * z for z in scores) / len(scores) < 1.5
    # The setting is checked like the others.
    checker = MessageCatcher(solver)
    solver.SetScreenedSteps(3)
    assert checker.errors and solver.GetScreenedSteps() == solver.SCREENED_STEPS_AUTOMATIC


def test_a_narrow_peak_of_the_data_takes_steps_toward_it():
    # u = 1/|x − a| with a just outside the unit sphere: harmonic inside,
    # and its values on the sphere (from the expression, exact where walks
    # end) a narrow peak near a, which uniform steps rarely reach. By default steps lean toward the peak; the error
    # bars are right at every point of the line and none is flagged.
    a = (1.05, 0.1, 0.0)
    exact = lambda x, y, z: 1.0 / math.dist((x, y, z), a)  # noqa: E731
    boundary = sphere_boundary(lambda x, y, z: 0.0, resolution=64)
    solver = solver_for(boundary, LINE, 256)
    solver.SetBoundaryValueExpression("1/sqrt((x-1.05)^2+(y-0.1)^2+z^2)")
    assert solver.GetPeakSteps() == solver.PEAK_STEPS_AUTOMATIC
    catcher = MessageCatcher(solver)
    solver.Update()
    output = solver.GetOutput()
    reliable = output.GetPointData().GetArray("Solution_VarianceReliable")
    assert all(reliable.GetValue(i) == 1 for i in range(100))
    assert not catcher.warnings, catcher.warning_text()
    scores = z_scores(output, exact, "Solution")
    assert max(abs(z) for z in scores) < 5.0
    assert 0.6 < sum(z * z for z in scores) / len(scores) < 1.5
    # Uniform steps: the same line's error bars are too small (the walks as
    # drawn: walking on, where the data's range flags points, brings more of
    # the rare walks to the peak at more cost).
    solver.SetPeakSteps(solver.PEAK_STEPS_UNIFORM)
    solver.SetWalkOnWhereUnreliable(1)
    solver.Update()
    uniform = z_scores(solver.GetOutput(), exact, "Solution")
    assert sum(z * z for z in uniform) / len(uniform) > 1.5
    # The setting is checked like the others.
    checker = MessageCatcher(solver)
    solver.SetPeakSteps(3)
    assert checker.errors and solver.GetPeakSteps() == solver.PEAK_STEPS_UNIFORM


def test_jumping_data_with_few_walks_is_flagged_where_the_walks_agree():
    # g = sign(y) on the unit circle; with 32 walks, points near the circle
    # often see one side only (variance 0, and no error bar at all), or
    # just one walk on the far side.
    boundary = circle_boundary(lambda x, y, z: 1.0 if y >= 0.0 else -1.0)
    solver = solver_for(boundary, DISK_LINE, 32)
    # No walking on here (the default walks on at flagged points: below).
    solver.SetWalkOnWhereUnreliable(1)
    catcher = MessageCatcher(solver)
    solver.Update()
    output = solver.GetOutput()
    variance = output.GetPointData().GetArray("T_Variance")
    reliable = flags(output)
    no_spread = [i for i in range(100) if variance.GetValue(i) == 0.0]
    assert no_spread, "the case no longer shows points whose walks all agree"
    assert all(reliable[i] == 0 for i in no_spread)
    exact = lambda x, y, z: 2.0 / math.pi * math.atan2(2.0 * y, 1.0 - x * x - y * y)  # noqa: E731
    values = output.GetPointData().GetArray("T")
    for i in range(100):
        x, y, _ = output.GetPoint(i)
        error = abs(values.GetValue(i) - exact(x, y, 0.0))
        if not error <= 5.0 * math.sqrt(variance.GetValue(i)):
            assert reliable[i] == 0, i
    text = catcher.warning_text()
    assert "all their walks, or all but one, gave the same value" in text
    assert "%d of 100 probe points" % reliable.count(0) in text


def test_flagged_points_walk_on_by_default():
    # The same case with the default Walk On Where Unreliable (4): only the
    # flagged points walk on, to 64 and then 128 walks, and their error bars
    # settle; the others keep their numbers.
    boundary = circle_boundary(lambda x, y, z: 1.0 if y >= 0.0 else -1.0)
    plain = solver_for(boundary, DISK_LINE, 32)
    plain.SetWalkOnWhereUnreliable(1)
    plain.Update()
    before = flags(plain.GetOutput())
    solver = solver_for(boundary, DISK_LINE, 32)
    assert solver.GetWalkOnWhereUnreliable() == 4
    catcher = MessageCatcher(solver)
    solver.Update()
    output = solver.GetOutput()
    walks = output.GetPointData().GetArray("WalkCount")
    values = output.GetPointData().GetArray("T")
    plain_values = plain.GetOutput().GetPointData().GetArray("T")
    moved = [i for i in range(100) if before[i] == 0]
    assert len(moved) > 5
    # Without walking on every point holds 32 walks: no WalkCount array.
    assert plain.GetOutput().GetPointData().GetArray("WalkCount") is None
    for i in range(100):
        if before[i] == 1:
            assert walks.GetValue(i) == 32
            assert values.GetValue(i) == plain_values.GetValue(i)
        else:
            assert walks.GetValue(i) in (64, 128), (i, walks.GetValue(i))
    assert field(output, "PointsWalkedOnForReliability") == len(moved)
    after = flags(output)
    assert after.count(0) * 4 <= len(moved), (after.count(0), len(moved))
    scores = z_scores(output, lambda x, y, z: 2.0 / math.pi * math.atan2(
        2.0 * y, 1.0 - x * x - y * y), "T")
    assert all(abs(z) < 5.0 for z, ok in zip(scores, after) if ok)
    if after.count(0) == 0:
        assert not catcher.warnings, catcher.warning_text()
    # The setting is checked.
    checker = MessageCatcher(solver)
    solver.SetWalkOnWhereUnreliable(0)
    assert checker.errors and solver.GetWalkOnWhereUnreliable() == 4


def test_light_tails_are_not_flagged_and_not_announced():
    boundary = sphere_boundary(lambda x, y, z: math.exp(x))
    solver = solver_for(boundary, LINE, 128, screening=1.0)
    catcher = MessageCatcher(solver)
    solver.Update()
    assert flags(solver.GetOutput()) == [1] * 100
    assert solver.GetLastUnreliableErrorBars() == 0
    assert catcher.warnings == []
    laplace = solver_for(sphere_boundary(), LINE, 128)
    laplace.Update()
    assert flags(laplace.GetOutput()) == [1] * 100


def test_points_closer_than_epsilon_are_not_flagged_with_derivatives():
    # On the boundary itself a point's value is g at its closest point,
    # exactly: no spread, rightly. Its derivative walks take steps, which
    # must not make the value's lack of spread look like a missing tail
    # (the CT workflow's slice crosses the skin at such points).
    boundary = sphere_boundary(lambda x, y, z: math.exp(x) + y)
    on_boundary = probe([boundary.GetPoint(i) for i in range(0, 200, 10)])
    for target in (0.0, 0.01):
        solver = solver_for(boundary, on_boundary, 256, target=target)
        solver.SetComputeGradient(True)
        catcher = MessageCatcher(solver)
        solver.Update()
        output = solver.GetOutput()
        status = output.GetPointData().GetArray("DerivativeStatus")
        assert all(status.GetValue(i) == 1 for i in range(20))
        assert output.GetPointData().GetArray("T_Variance").GetRange() == (0.0, 0.0)
        assert flags(output) == [1] * 20, target
        assert catcher.warnings == [], catcher.warning_text()
        if target > 0.0:
            # The exact value meets the target at the first check.
            assert field(output, "TotalWalks") < 20 * 256, field(output, "TotalWalks")


def test_target_mode_walks_on_at_unreliable_points():
    boundary = sphere_boundary(lambda x, y, z: math.exp(10.0 * x))
    solver = solver_for(boundary, LINE, 1024, screening=100.0, target=1e300)
    solver.SetScreenedSteps(gridfree.vtkWalkOnSpheresSolver.SCREENED_STEPS_UNIFORM)
    solver.Update()
    output = solver.GetOutput()
    walks = output.GetPointData().GetArray("WalkCount")
    reliable = flags(output)
    # Any variance meets the target: only an unreliable error bar walks on,
    # to the maximum if it stays unreliable.
    assert reliable.count(0) > 30
    for i in range(100):
        if not reliable[i]:
            assert walks.GetValue(i) == 1024, i
    # The same target without screening: every point stops at once.
    laplace = solver_for(sphere_boundary(), LINE, 1024, target=1e300)
    laplace.Update()
    counts = laplace.GetOutput().GetPointData().GetArray("WalkCount")
    assert all(counts.GetValue(i) == 128 for i in range(100))


def test_a_bounded_source_bounds_the_walks_and_clears_uneven_weights():
    # Δu − 9u = f with u = I0(3r) + 5 on the unit disk, f = −45: the walk
    # values are W·g + (1 − W)·5 (ErrorBarReliability.h), bounded, so the
    # weights' unevenness flags nothing while the bars are right. The
    # source written so that it reads x (u = I0(3r) + 5 + 2x, f = −45 − 18x)
    # states no range; the problem samples it (SourceDensityMap's samples),
    # and its points are judged alike (42 of 100 were flagged before, with
    # right bars). Source Sampling Uniform takes samples that are unbounded
    # near the walker: there the weights flag points.
    base = lambda x, y, z: bessel_i0(3.0 * math.hypot(x, y)) + 5.0  # noqa: E731
    tilted = lambda x, y, z: base(x, y, z) + 2.0 * x  # noqa: E731
    flagged = {}
    for expression, exact, uniform in (("-45", base, False), ("-45 - 18*x", tilted, False),
                                       ("-45 - 18*x", tilted, True)):
        solver = solver_for(circle_boundary(exact), DISK_LINE, 256, screening=9.0)
        solver.SetSourceExpression(expression)
        if uniform:
            solver.SetSourceSampling(gridfree.vtkWalkOnSpheresSolver.UNIFORM)
        catcher = MessageCatcher(solver)
        solver.Update()
        output = solver.GetOutput()
        assert all(abs(z) < 5.0 for z in z_scores(output, exact))
        flagged[expression, uniform] = flags(output).count(0)
        if flagged[expression, uniform]:
            # Every flagged point is counted under its reason.
            assert ("%d of them because their walks' screening weights are very uneven"
                    % flagged[expression, uniform]) in catcher.warning_text()
    assert flagged["-45", False] == 0
    assert flagged["-45 - 18*x", False] == 0
    assert flagged["-45 - 18*x", True] > 10, flagged


def test_near_boundary_splitting_walks_on_only_near_the_boundary():
    # A Poisson problem (f = 6, u = |x|^2 with its data on the sphere):
    # walks from near the boundary take more steps with splitting (the rare
    # deep walks, shared); points far from it give the same numbers, with
    # control variates too (their walks start anew on the first ball's
    # sphere, near the boundary, but split only beyond twice its radius).
    # Toggled on one solver, the setting takes effect at once, with the
    # polynomial control variate too (whose shifted problem is kept).
    near = [(0.97 * math.cos(0.3 * i), 0.97 * math.sin(0.3 * i), 0.1) for i in range(20)]
    far = [(0.05 * i - 0.5, 0.1, 0.0) for i in range(20)]
    for polynomial in (0, 2):
        solver = solver_for(sphere_boundary(lambda x, y, z: x * x + y * y + z * z),
                            probe(near + far), 128)
        solver.SetEquation(gridfree.vtkWalkOnSpheresSolver.POISSON)
        solver.SetSourceExpression("6 + 0.5 * x")
        solver.SetPolynomialControlVariate(polynomial)
        solver.SetComputeGradient(polynomial == 0)
        results = {}
        for split in (False, True):
            solver.SetNearBoundarySplitting(split)
            assert solver.GetNearBoundarySplitting() == split
            solver.Update()
            out = solver.GetOutput()
            values = out.GetPointData().GetArray("T")
            results[split] = ([values.GetValue(i) for i in range(40)],
                              out.GetFieldData().GetArray("MeanStepsPerWalk").GetValue(0))
        assert results[True][0][20:] == results[False][0][20:], polynomial
        assert results[True][0][:20] != results[False][0][:20], polynomial
        assert results[True][1] > results[False][1], polynomial
