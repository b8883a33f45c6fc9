"""Target-error mode of vtkWalkOnSpheresSolver: each probe point walks until
the standard error of its value is at most TargetStandardError (Walks Per
Point the most it takes)."""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import gridfree  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkDataObject  # noqa: E402
from vtkmodules.vtkFiltersSources import vtkPlaneSource  # noqa: E402

from gridfree_testing import MessageCatcher, saddle, sphere_boundary, z_scores  # noqa: E402

POINTS = vtkDataObject.FIELD_ASSOCIATION_POINTS
BOUNDARY = sphere_boundary()  # x^2 - y^2 on the unit sphere: range 2


def probe(resolution=19):
    # 20 x 20 points from near the centre to near the sphere.
    source = vtkPlaneSource()
    source.SetOrigin(-0.9, -0.3, 0.1)
    source.SetPoint1(0.9, -0.3, 0.1)
    source.SetPoint2(-0.9, 0.3, 0.1)
    source.SetResolution(resolution, resolution)
    source.Update()
    return source.GetOutput()


PROBE = probe()


def one_point(point):
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkPolyData
    points = vtkPoints()
    points.SetDataTypeToDouble()
    points.InsertNextPoint(point)
    data = vtkPolyData()
    data.SetPoints(points)
    return data


def solve(target=0.0, relative=False, walks=4096, threads=0, gradient=False, boundary=BOUNDARY,
          where=PROBE):
    solver = gridfree.vtkWalkOnSpheresSolver()
    solver.SetBoundaryData(boundary)
    solver.SetProbeData(where)
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    solver.SetWalksPerPoint(walks)
    solver.SetTargetStandardError(target)
    solver.SetTargetErrorIsRelative(relative)
    solver.SetNumberOfThreads(threads)
    solver.SetComputeGradient(gradient)
    solver.SetSeed(11)
    messages = MessageCatcher(solver)
    solver.Update()
    return solver.GetOutput(), messages


def values(output, name):
    array = output.GetPointData().GetArray(name)
    return [array.GetValue(i) for i in range(array.GetNumberOfValues())]


def test_each_point_stops_at_the_target_and_the_errors_stay_calibrated():
    out, messages = solve(target=0.02)
    assert not messages.errors and not messages.warnings, messages.warning_text()
    walks = values(out, "WalkCount")
    variances = values(out, "T_Variance")
    for n, v in zip(walks, variances):
        assert v <= 0.02 ** 2 and 128 <= n <= 4096 and (n - 128) % 32 == 0, (n, v)
    # Points near the sphere stop sooner than points near the centre.
    assert min(walks) < max(walks) / 2, (min(walks), max(walks))
    scores = z_scores(out, saddle)
    assert max(abs(z) for z in scores) < 5.0
    mean_z2 = sum(z * z for z in scores) / len(scores)
    assert 0.7 < mean_z2 < 1.4, mean_z2
    field = out.GetFieldData()
    assert field.GetArray("TargetStandardError").GetValue(0) == 0.02
    assert field.GetArray("TotalWalks").GetValue(0) == sum(walks)


def test_a_point_gets_the_numbers_of_a_fixed_count_solve_cut_at_its_count():
    # With control variates (the derivative estimator, its control history
    # kept across the checks) and without.
    for gradient in (False, True):
        target, _ = solve(target=0.04, gradient=gradient)
        walks = values(target, "WalkCount")
        means = values(target, "T")
        for i in (0, 57, 210, 399):
            # The walks' random streams are keyed by the point's coordinates.
            fixed, _ = solve(walks=walks[i], gradient=gradient,
                             where=one_point(PROBE.GetPoint(i)))
            assert values(fixed, "T")[0] == means[i], (gradient, i, walks[i])


def test_same_numbers_for_any_thread_count():
    one, _ = solve(target=0.02, threads=1, gradient=True)
    two, _ = solve(target=0.02, threads=2, gradient=True)
    for name in ("T", "T_Variance", "T_Gradient", "WalkCount"):
        assert values(one, name) == values(two, name), name


def test_relative_target_is_a_fraction_of_the_boundary_values_range():
    low, high = BOUNDARY.GetPointData().GetArray("T").GetRange()  # about -1 and 1
    absolute, _ = solve(target=0.02 * (high - low))
    relative, messages = solve(target=0.02, relative=True)
    assert not messages.errors
    assert relative.GetFieldData().GetArray("TargetStandardError").GetValue(0) == \
        absolute.GetFieldData().GetArray("TargetStandardError").GetValue(0)
    assert values(relative, "T") == values(absolute, "T")


def test_points_that_cannot_reach_the_target_are_reported():
    out, messages = solve(target=0.001, walks=256)
    assert max(values(out, "WalkCount")) == 256
    assert "without reaching the target standard error" in messages.warning_text()


def test_refine_keeps_the_points_at_the_target_and_continues_the_others():
    # Rounds of Refine (what the GUI's Refine Until Target does), from 150
    # walks (points cut off between two checks continue to the next one):
    # each round runs only the walks of the points still above the target,
    # and the last equals one solve with that maximum.
    target = 0.02
    solver = gridfree.vtkWalkOnSpheresSolver()
    small = probe(9)  # 100 points
    solver.SetBoundaryData(BOUNDARY)
    solver.SetProbeData(small)
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    solver.SetSeed(11)
    solver.SetComputeGradient(True)
    solver.SetTargetStandardError(target)
    solver.SetWalksPerPoint(150)
    solver.Update()
    short = [solver.GetLastPointsShortOfTarget()]
    while short[-1] > 0:
        before = values(solver.GetOutput(), "WalkCount")
        solver.Refine()
        solver.Update()
        after = values(solver.GetOutput(), "WalkCount")
        assert solver.GetLastResumedWalksPerPoint() == solver.GetWalksPerPoint() // 2
        # Only the walks the counts grew by ran.
        assert solver.GetLastNumberOfWalks() == sum(after) - sum(before)
        short.append(solver.GetLastPointsShortOfTarget())
    assert len(short) >= 3 and short[0] > short[1] > 0, short
    walks = solver.GetWalksPerPoint()
    refined = solver.GetOutput()
    whole, _ = solve(target=target, walks=walks, gradient=True, where=small)
    for name in ("T", "T_Variance", "T_Gradient", "WalkCount"):
        assert values(refined, name) == values(whole, name), name
    assert max(math.sqrt(v) for v in values(refined, "T_Variance")) <= target


def test_relative_target_with_constant_values_is_an_error():
    constant = sphere_boundary(function=lambda x, y, z=0.0: 3.0)
    out, messages = solve(target=0.01, relative=True, boundary=constant)
    assert "turn TargetErrorIsRelative off" in messages.error_text(), messages.error_text()


def test_fixed_count_mode_has_no_walk_count_array():
    out, _ = solve(walks=64)
    assert out.GetPointData().GetArray("WalkCount") is None
    assert out.GetFieldData().GetArray("TargetStandardError") is None
