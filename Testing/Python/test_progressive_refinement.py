"""Progressive refinement: raising WalksPerPoint with nothing else changed
runs only the missing walks and gives, bit for bit, what one solve with all
the walks gives; any other change starts afresh."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import gridfree  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkDataObject  # noqa: E402
from vtkmodules.vtkFiltersSources import vtkPlaneSource  # noqa: E402

from gridfree_testing import (  # noqa: E402
    point_cloud, sphere_boundary, update_aborted_at_first_progress)

POINTS = vtkDataObject.FIELD_ASSOCIATION_POINTS
BOUNDARY = sphere_boundary(resolution=24)


def plane(resolution=6):
    source = vtkPlaneSource()
    source.SetOrigin(-0.5, -0.5, 0.1)
    source.SetPoint1(0.5, -0.5, 0.1)
    source.SetPoint2(-0.5, 0.5, 0.1)
    source.SetResolution(resolution, resolution)
    source.Update()
    return source.GetOutput()


PROBE = plane()


def solver_for(probe=PROBE, walks=64, **settings):
    solver = gridfree.vtkWalkOnSpheresSolver()
    solver.SetBoundaryData(BOUNDARY)
    solver.SetProbeData(probe)
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    solver.SetWalksPerPoint(walks)
    solver.SetEpsilon(1e-3)
    for name, value in settings.items():
        getattr(solver, "Set" + name)(value)
    return solver


def arrays(solver):
    """Every point array of the output, as lists of tuples, and the field
    data totals."""
    out = solver.GetOutput()
    result = {}
    pd = out.GetPointData()
    for k in range(pd.GetNumberOfArrays()):
        array = pd.GetArray(k)
        result[array.GetName()] = [array.GetTuple(i) for i in range(array.GetNumberOfTuples())]
    for name in ("TotalWalks", "TotalSteps", "EscapedWalks", "TruncatedWalks"):
        result[name] = out.GetFieldData().GetArray(name).GetValue(0)
    return result


def one_shot(walks, probe=PROBE, **settings):
    solver = solver_for(probe, walks, **settings)
    solver.Update()
    return arrays(solver)


def check_progressive(first, second, resumed, probe=PROBE, **settings):
    solver = solver_for(probe, first, **settings)
    solver.Update()
    assert arrays(solver) == one_shot(first, probe, **settings)
    solver.SetWalksPerPoint(second)
    solver.Update()
    points = probe.GetNumberOfPoints()
    assert solver.GetLastResumedWalksPerPoint() == resumed
    assert solver.GetLastNumberOfWalks() == (second - resumed) * points
    assert arrays(solver) == one_shot(second, probe, **settings)


def test_plain_walks_continue_bit_for_bit():
    check_progressive(40, 100, 40, ControlVariates=False)


def test_derivative_walks_continue_from_any_walk_count():
    # The control variates' block state (blocks of 256 walks) is kept with
    # the sums: 300 walks continue inside the second block, 100 inside the
    # first.
    check_progressive(300, 700, 300, ComputeGradient=True, ComputeHessian=True)
    check_progressive(100, 200, 100, ComputeGradient=True)


def test_walks_of_few_points_spread_over_threads_continue_too():
    few = point_cloud([(0.1, 0.2, 0.0), (-0.3, 0.0, 0.4)])
    check_progressive(1000, 2600, 1000, probe=few, ControlVariates=False, NumberOfThreads=2)
    check_progressive(600, 1500, 600, probe=few, ComputeGradient=True, NumberOfThreads=2)


def test_poisson_with_a_source_continues_too():
    check_progressive(50, 130, 50, ControlVariates=False,
                      Equation=gridfree.vtkWalkOnSpheresSolver.POISSON, SourceExpression="1 + x")


def test_refine_doubles_the_walks():
    solver = solver_for(walks=48, ControlVariates=False)
    solver.Update()
    solver.Refine()
    assert solver.GetWalksPerPoint() == 96
    solver.Update()
    assert solver.GetLastResumedWalksPerPoint() == 48
    assert arrays(solver) == one_shot(96, ControlVariates=False)


def test_fewer_walks_or_any_other_change_start_afresh():
    solver = solver_for(walks=80, ControlVariates=False)
    solver.Update()
    solver.SetWalksPerPoint(30)  # fewer: cannot continue
    solver.Update()
    assert solver.GetLastResumedWalksPerPoint() == 0
    assert arrays(solver) == one_shot(30, ControlVariates=False)
    solver.SetSeed(7)  # another setting
    solver.SetWalksPerPoint(60)
    solver.Update()
    assert solver.GetLastResumedWalksPerPoint() == 0
    assert arrays(solver) == one_shot(60, ControlVariates=False, Seed=7)
    # Modified boundary data: the sums are stale.
    boundary = sphere_boundary(resolution=24)
    solver.SetBoundaryData(boundary)
    solver.Update()
    values = boundary.GetPointData().GetArray("T")
    values.SetValue(0, values.GetValue(0) + 1.0)
    values.Modified()
    boundary.Modified()
    solver.SetWalksPerPoint(90)
    solver.Update()
    assert solver.GetLastResumedWalksPerPoint() == 0
    # Keep Running Sums off: nothing is kept.
    solver.SetKeepRunningSums(False)
    solver.Update()
    solver.SetWalksPerPoint(120)
    solver.Update()
    assert solver.GetLastResumedWalksPerPoint() == 0


def test_an_aborted_solve_keeps_its_walks_and_resumes():
    """Aborted (at the first progress report) while raising 64 walks to
    2000: every point shows an estimate (the walks it ran, at least the 64
    kept), an update without Resume runs nothing, and Resume then continues
    each point from its own count to one uninterrupted solve's numbers."""
    import math
    probe = plane(10)
    solver = solver_for(probe, walks=64, ControlVariates=False)
    solver.Update()
    solver.SetWalksPerPoint(2000)
    update_aborted_at_first_progress(solver)
    assert solver.GetLastSolveAborted()
    out = solver.GetOutput().GetPointData()
    counts = [out.GetArray("WalkCount").GetValue(i) for i in range(probe.GetNumberOfPoints())]
    assert min(counts) >= 64 and min(counts) < 2000, (min(counts), max(counts))
    assert not any(math.isnan(out.GetArray("T").GetValue(i)) for i in range(len(counts)))
    # Aborting did not mark the solver modified: nothing runs again.
    solver.SetAbortExecute(0)
    solver.Update()
    assert solver.GetLastSolveAborted()
    solver.Resume()
    solver.Update()
    assert not solver.GetLastSolveAborted()
    assert solver.GetLastResumedWalksPerPoint() == min(counts)
    assert solver.GetLastNumberOfWalks() == 2000 * len(counts) - sum(counts)
    assert arrays(solver) == one_shot(2000, probe, ControlVariates=False)
