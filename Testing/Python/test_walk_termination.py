"""Every walk ends: MaxSteps bounds it, a region the boundary does not
enclose ends in escapes that are counted, and gaps narrower than epsilon end
walks at once. Each case is timed: a hang fails it (or ctest's timeout)."""
import math
import os
import sys
import time

sys.path.insert(0, os.path.dirname(__file__))

import gridfree  # noqa: E402
from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkPoints  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkDataObject, vtkPolyData  # noqa: E402
from vtkmodules.vtkFiltersSources import vtkSphereSource  # noqa: E402

from gridfree_testing import (  # noqa: E402
    MessageCatcher, add_point_array, point_cloud, sphere_boundary)

POINTS = vtkDataObject.FIELD_ASSOCIATION_POINTS
Solver = gridfree.vtkWalkOnSpheresSolver


def timed_solve(boundary, probe, walks=64, seconds=20.0, **settings):
    solver = Solver()
    catcher = MessageCatcher(solver, solver.GetExecutive())
    solver.SetBoundaryData(boundary)
    solver.SetProbeData(probe)
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    solver.SetWalksPerPoint(walks)
    for name, value in settings.items():
        getattr(solver, "Set" + name)(value)
    start = time.monotonic()
    solver.Update()
    elapsed = time.monotonic() - start
    assert elapsed < seconds, "the solve took %.1f s" % elapsed
    assert catcher.errors == [], catcher.error_text()
    return solver.GetOutput(), catcher


def column(output, name, component=0):
    array = output.GetPointData().GetArray(name)
    return [array.GetComponent(i, component) for i in range(array.GetNumberOfTuples())]


def field(output, name):
    return output.GetFieldData().GetArray(name).GetValue(0)


PROBE = [(0.1, 0.2, 0.0), (-0.5, 0.1, 0.3), (0.0, 0.0, -0.7)]


def test_max_steps_bounds_every_walk():
    """With an epsilon far below what the walks can reach in 3 steps, every
    walk stops at MaxSteps: counted per point and in all, with a warning."""
    for controls, gradient in ((False, False), (True, True)):
        out, catcher = timed_solve(sphere_boundary(resolution=32), point_cloud(PROBE),
                                   Epsilon=1e-12, MaxSteps=3, ControlVariates=controls,
                                   ComputeGradient=gradient)
        assert all(f > 0.5 for f in column(out, "TruncatedFraction"))
        assert "reached MaxSteps = 3" in catcher.warning_text()
        # A derivative walk is a plain walk plus at most one first ball.
        steps_per_walk = field(out, "TotalSteps") / field(out, "TotalWalks")
        assert steps_per_walk <= 3 + 1
        assert all(math.isfinite(v) for v in column(out, "T"))


def test_max_steps_bounds_nested_biharmonic_walks():
    boundary = sphere_boundary(resolution=32)
    add_point_array(boundary, "H", lambda x, y, z: 1.0)
    solver = Solver()
    catcher = MessageCatcher(solver)
    solver.SetBoundaryData(boundary)
    solver.SetProbeData(point_cloud(PROBE))
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    solver.SetInputArrayToProcess(1, 0, 0, POINTS, "H")
    solver.SetEquation(Solver.BIHARMONIC)
    solver.SetBiharmonicStrategy(Solver.NESTED)
    solver.SetNestedWalks(4)
    solver.SetEpsilon(1e-12)
    solver.SetMaxSteps(4)
    solver.SetWalksPerPoint(32)
    start = time.monotonic()
    solver.Update()
    assert time.monotonic() - start < 20.0
    assert "reached MaxSteps = 4" in catcher.warning_text()
    assert all(math.isfinite(v) for v in column(solver.GetOutput(), "T"))


def open_hemisphere():
    """The upper half of the unit sphere: a boundary with a hole, enclosing
    nothing."""
    source = vtkSphereSource()
    source.SetRadius(1.0)
    source.SetThetaResolution(48)
    source.SetPhiResolution(48)
    source.SetEndPhi(90.0)
    source.Update()
    boundary = vtkPolyData()
    boundary.DeepCopy(source.GetOutput())
    add_point_array(boundary, "T", lambda x, y, z: 1.0)
    return boundary


def test_region_not_enclosed_by_the_boundary():
    """Walks from under an open hemisphere leave through the hole. Laplace and
    Poisson have an exterior strategy (returns from a far sphere); screened
    walks far from everything end by roulette (the solution decays); the
    biharmonic solver warns that it needs a bounded domain. All end, and no
    walk needs MaxSteps."""
    probe = point_cloud([(0.0, 0.0, 0.5), (0.3, 0.0, -0.2), (0.0, 0.0, -3.0)])
    out, catcher = timed_solve(open_hemisphere(), probe)
    values = column(out, "T")
    assert all(0.0 <= v <= 1.0 for v in values)  # maximum principle, u -> 0 far away
    assert "MaxSteps" not in catcher.warning_text()

    out, catcher = timed_solve(open_hemisphere(), probe, Equation=Solver.SCREENED_POISSON,
                               ScreeningCoefficient=1.0)
    assert all(0.0 <= v <= 1.0 for v in column(out, "T"))
    assert "MaxSteps" not in catcher.warning_text()

    boundary = open_hemisphere()
    add_point_array(boundary, "H", lambda x, y, z: 0.0)
    solver = Solver()
    catcher = MessageCatcher(solver)
    solver.SetBoundaryData(boundary)
    solver.SetProbeData(probe)
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    solver.SetInputArrayToProcess(1, 0, 0, POINTS, "H")
    solver.SetEquation(Solver.BIHARMONIC)
    solver.SetWalksPerPoint(64)
    solver.Update()
    assert "biharmonic walks left the region enclosed by the boundary" in catcher.warning_text()
    assert all(f > 0.0 for f in column(solver.GetOutput(), "EscapedFraction"))


def parallel_plates(gap):
    """Two unit squares at z = 0 and z = gap, carrying T = 0 and T = 1."""
    points = vtkPoints()
    points.SetDataTypeToDouble()
    for z in (0.0, gap):
        for x, y in ((0, 0), (1, 0), (1, 1), (0, 1)):
            points.InsertNextPoint(x, y, z)
    plates = vtkPolyData()
    plates.SetPoints(points)
    plates.AllocateEstimate(4, 3)
    for base in (0, 4):
        plates.InsertNextCell(5, 3, [base, base + 1, base + 2])
        plates.InsertNextCell(5, 3, [base, base + 2, base + 3])
    values = vtkDoubleArray()
    values.SetName("T")
    for i in range(8):
        values.InsertNextValue(0.0 if i < 4 else 1.0)
    plates.GetPointData().AddArray(values)
    return plates


def test_gap_narrower_than_epsilon():
    """Between plates 1e-7 apart with epsilon = 1e-4 (absolute), every walk
    ends at its start with the nearer plate's value."""
    gap = 1e-7
    probe = point_cloud([(0.5, 0.5, 0.2 * gap), (0.3, 0.6, 0.8 * gap)])
    out, _ = timed_solve(parallel_plates(gap), probe, Epsilon=1e-4, EpsilonIsRelative=False,
                         ControlVariates=False)
    assert column(out, "T") == [0.0, 1.0]
    assert column(out, "WalkSteps") == [0.0, 0.0]
    assert column(out, "T_Variance") == [0.0, 0.0]
