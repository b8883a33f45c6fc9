"""Time Budget of vtkWalkOnSpheresSolver: rounds of 128, 256, ... walks per
point, each continuing from the last, until Walks Per Point, the target, or
the budget. Whatever count the budget reaches, the numbers are those of one
solve with that count (no test here depends on the machine's speed)."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import gridfree  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkDataObject  # noqa: E402
from gridfree_testing import MessageCatcher, plane_probe, sphere_boundary  # noqa: E402

POINTS = vtkDataObject.FIELD_ASSOCIATION_POINTS
BOUNDARY = sphere_boundary()  # x^2 - y^2 on the unit sphere


def plane(resolution):
    return plane_probe((-0.8, -0.3, 0.1), (0.8, -0.3, 0.1), (-0.8, 0.3, 0.1), resolution)


PROBE = plane(9)


def solver_for(walks, budget=0.0, target=0.0, gradient=False, probe=PROBE, keep=True):
    solver = gridfree.vtkWalkOnSpheresSolver()
    solver.SetBoundaryData(BOUNDARY)
    solver.SetProbeData(probe)
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    solver.SetWalksPerPoint(walks)
    solver.SetTimeBudgetSeconds(budget)
    solver.SetTargetStandardError(target)
    solver.SetComputeGradient(gradient)
    solver.SetKeepRunningSums(keep)
    solver.SetSeed(5)
    return solver


def arrays(output, names=("T", "T_Variance")):
    pd = output.GetPointData()
    return {name: [pd.GetArray(name).GetValue(i)
                   for i in range(pd.GetArray(name).GetNumberOfValues())]
            for name in names if pd.GetArray(name) is not None}


def field(output, name):
    return output.GetFieldData().GetArray(name).GetValue(0)


def test_a_spent_budget_stops_after_the_first_round():
    solver = solver_for(4096, budget=1e-9)
    messages = MessageCatcher(solver)
    solver.Update()
    out = solver.GetOutput()
    assert solver.GetLastWalksPerPointReached() == 128
    assert field(out, "WalksPerPointReached") == 128
    assert field(out, "TimeBudgetSeconds") == 1e-9
    assert set(arrays(out, ("WalkCount",))["WalkCount"]) == {128}
    fixed = solver_for(128)
    fixed.Update()
    assert arrays(out) == arrays(fixed.GetOutput())
    assert not messages.warnings and not messages.errors


def test_an_ample_budget_reaches_walks_per_point_with_derivatives():
    # Rounds 128, 256, 512, 600: gradients with control variates continue
    # inside their blocks of 256 walks.
    solver = solver_for(600, budget=1e6, gradient=True)
    solver.Update()
    assert solver.GetLastWalksPerPointReached() == 600
    fixed = solver_for(600, gradient=True)
    fixed.Update()
    names = ("T", "T_Variance", "T_Gradient")
    assert arrays(solver.GetOutput(), names) == arrays(fixed.GetOutput(), names)
    # Every walk ran once: 600 per point over the rounds.
    assert solver.GetLastNumberOfWalks() == 600 * PROBE.GetNumberOfPoints()


def test_whatever_count_a_budget_reaches_the_numbers_are_that_counts():
    probe = plane(29)
    solver = solver_for(1 << 16, budget=0.5, probe=probe)
    solver.Update()
    reached = solver.GetLastWalksPerPointReached()
    assert reached >= 128 and reached & (reached - 1) == 0  # 128 * 2^k
    fixed = solver_for(reached, probe=probe)
    fixed.Update()
    assert arrays(solver.GetOutput()) == arrays(fixed.GetOutput())


def test_with_a_target_the_rounds_stop_at_the_target():
    target = 0.02
    solver = solver_for(1 << 16, budget=1e6, target=target)
    messages = MessageCatcher(solver)
    solver.Update()
    reached = solver.GetLastWalksPerPointReached()
    assert solver.GetLastPointsShortOfTarget() == 0
    assert 128 < reached < (1 << 16)
    one = solver_for(reached, target=target)
    one.Update()
    names = ("T", "T_Variance", "WalkCount")
    assert arrays(solver.GetOutput(), names) == arrays(one.GetOutput(), names)
    assert not messages.warnings


def test_a_target_the_budget_cannot_reach_is_reported():
    solver = solver_for(1 << 16, budget=1e-9, target=1e-4)
    messages = MessageCatcher(solver)
    solver.Update()
    assert solver.GetLastWalksPerPointReached() == 128
    assert solver.GetLastPointsShortOfTarget() > 0
    text = messages.warning_text()
    assert "time budget" in text and "raise the time budget" in text
    assert len(messages.warnings) == 1  # one warning, not one per round


def test_a_larger_budget_continues_and_no_kept_sums_start_afresh():
    solver = solver_for(512, budget=1e-9)
    solver.Update()
    assert solver.GetLastWalksPerPointReached() == 128
    solver.SetTimeBudgetSeconds(1e6)
    solver.Update()
    assert solver.GetLastResumedWalksPerPoint() == 128
    assert solver.GetLastWalksPerPointReached() == 512
    assert solver.GetLastNumberOfWalks() == (512 - 128) * PROBE.GetNumberOfPoints()
    fixed = solver_for(512)
    fixed.Update()
    assert arrays(solver.GetOutput()) == arrays(fixed.GetOutput())

    # Keep Running Sums off: the rounds still continue from each other, but
    # nothing is kept for the next solve.
    forgetful = solver_for(512, budget=1e6, keep=False)
    forgetful.Update()
    assert arrays(forgetful.GetOutput()) == arrays(fixed.GetOutput())
    forgetful.SetWalksPerPoint(1024)
    forgetful.Update()
    assert forgetful.GetLastResumedWalksPerPoint() == 0


def test_negative_or_nan_budgets_are_off():
    solver = solver_for(64)
    solver.SetTimeBudgetSeconds(-3.0)
    assert solver.GetTimeBudgetSeconds() == 0.0
    solver.SetTimeBudgetSeconds(float("nan"))
    assert solver.GetTimeBudgetSeconds() == 0.0
    solver.Update()
    assert solver.GetLastWalksPerPointReached() == 64
