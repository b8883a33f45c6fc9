"""The solver builds the boundary (conversion, hierarchy, distance bounds,
values) once and reuses it while nothing that shapes it changes: moving the
probe, changing the walks, the seed or Epsilon, or refining reuses it, with
the numbers of a fresh solver; new boundary data, another value array, an
expression, the equation's g-and-h layout or an edited implicit function
rebuild it. The stream tracer, which asks its problem at every stage, builds
it once per execution and keeps it the same way, and so do the application
filters (Helmholtz decomposition, cross field, deformation, diffusion curves)."""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import gridfree  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkDataObject  # noqa: E402
from vtkmodules.vtkFiltersSources import vtkPlaneSource  # noqa: E402

from gridfree_testing import (  # noqa: E402
    MessageCatcher, add_point_array, closed_polyline, point_cloud, sphere_boundary)

POINTS = vtkDataObject.FIELD_ASSOCIATION_POINTS
Solver = gridfree.vtkWalkOnSpheresSolver


def plane(z):
    source = vtkPlaneSource()
    source.SetOrigin(-0.5, -0.5, z)
    source.SetPoint1(0.5, -0.5, z)
    source.SetPoint2(-0.5, 0.5, z)
    source.SetResolution(5, 5)
    return source


def solver_for(boundary, probe, **settings):
    solver = Solver()
    solver.SetBoundaryData(boundary)
    solver.SetProbeConnection(probe.GetOutputPort())
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    solver.SetWalksPerPoint(32)
    solver.SetEpsilon(1e-3)
    for name, value in settings.items():
        getattr(solver, "Set" + name)(value)
    return solver


def point_arrays(solver):
    pd = solver.GetOutput().GetPointData()
    return {pd.GetArrayName(k): [pd.GetArray(k).GetTuple(i)
                                 for i in range(pd.GetArray(k).GetNumberOfTuples())]
            for k in range(pd.GetNumberOfArrays())}


def updated(solver):
    solver.Update()
    return solver.GetLastBoundaryBuilt()


def test_moving_the_probe_and_sampling_changes_reuse_the_boundary():
    boundary = sphere_boundary(resolution=32)
    probe = plane(0.0)
    solver = solver_for(boundary, probe, ComputeGradient=True)
    assert updated(solver)
    # A dragged slice: same numbers as a fresh solver at the new place.
    probe.SetOrigin(-0.5, -0.5, 0.3)
    probe.SetPoint1(0.5, -0.5, 0.3)
    probe.SetPoint2(-0.5, 0.5, 0.3)
    assert not updated(solver)
    fresh = solver_for(boundary, plane(0.3), ComputeGradient=True)
    assert updated(fresh)
    assert point_arrays(solver) == point_arrays(fresh)
    for change in (lambda: solver.SetWalksPerPoint(300), solver.Refine,
                   lambda: solver.SetSeed(9), lambda: solver.SetEpsilon(2e-3),
                   lambda: solver.SetNumberOfThreads(1),
                   lambda: solver.SetComputeHessian(True)):
        change()
        assert not updated(solver)
    # A shallow copy of the same data (ParaView hands filters these) is the
    # same boundary.
    from vtkmodules.vtkCommonDataModel import vtkPolyData
    copy = vtkPolyData()
    copy.ShallowCopy(boundary)
    solver.SetBoundaryData(copy)
    assert not updated(solver)


def test_what_shapes_the_boundary_rebuilds_it():
    boundary = sphere_boundary(resolution=24)
    add_point_array(boundary, "U", lambda x, y, z: x + 2.0 * y)
    probe = plane(0.1)
    solver = solver_for(boundary, probe)
    assert updated(solver)
    # Another value array.
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "U")
    assert updated(solver)
    fresh = solver_for(boundary, plane(0.1))
    fresh.SetInputArrayToProcess(0, 0, 0, POINTS, "U")
    fresh.Update()
    assert point_arrays(solver) == point_arrays(fresh)
    # Edited values.
    values = boundary.GetPointData().GetArray("U")
    values.SetValue(0, values.GetValue(0) + 1.0)
    values.Modified()
    assert updated(solver)
    # Moved vertices.
    boundary.GetPoints().SetPoint(0, 1.01, 0.0, 0.0)
    boundary.GetPoints().Modified()
    assert updated(solver)
    # Values from an expression, then another expression.
    solver.SetBoundaryValueExpression("x*y")
    assert updated(solver)
    solver.SetWalksPerPoint(40)
    assert not updated(solver)
    solver.SetBoundaryValueExpression("x*y + 1")
    assert updated(solver)
    # The biharmonic equation stores g and h together.
    solver.SetBoundaryValueExpression("")
    solver.SetEquation(Solver.BIHARMONIC)
    solver.SetInputArrayToProcess(1, 0, 0, POINTS, "T")
    assert updated(solver)
    solver.SetEquation(Solver.LAPLACE)
    assert updated(solver)


def test_an_edited_implicit_boundary_is_rebuilt():
    sphere = gridfree.vtkSignedDistanceSphere()
    sphere.SetRadius(1.0)
    solver = Solver()
    solver.SetImplicitBoundary(sphere)
    solver.SetBoundaryValueExpression("x")
    probe = plane(0.0)
    solver.SetProbeConnection(probe.GetOutputPort())
    solver.SetWalksPerPoint(16)
    assert updated(solver)
    solver.SetWalksPerPoint(32)
    assert not updated(solver)
    sphere.SetRadius(1.2)
    assert updated(solver)


def test_stream_tracer_builds_its_problem_once_and_keeps_it():
    from vtkmodules.vtkFiltersSources import vtkLineSource

    def tracer_for(seeds):
        tracer = gridfree.vtkWalkOnSpheresStreamTracer()
        tracer.SetBoundaryData(boundary)
        tracer.SetSeedsConnection(seeds.GetOutputPort())
        tracer.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
        tracer.SetWalksPerPoint(32)
        tracer.SetMaximumNumberOfSteps(8)
        return tracer

    def lines(tracer):
        out = tracer.GetOutput()
        points = [out.GetPoint(i) for i in range(out.GetNumberOfPoints())]
        return points, point_arrays_of(out)

    boundary = sphere_boundary(resolution=32)
    seeds = vtkLineSource()
    seeds.SetPoint1(-0.2, 0.0, 0.0)
    seeds.SetPoint2(0.2, 0.1, 0.0)
    seeds.SetResolution(2)
    tracer = tracer_for(seeds)
    tracer.Update()
    # Every stage of every line asked one problem: built once.
    assert tracer.GetLastBoundaryBuilt()
    assert tracer.GetOutput().GetNumberOfPoints() > 6
    # New seeds and more walks: the kept boundary, the numbers of a fresh tracer.
    seeds.SetPoint2(0.1, 0.3, 0.1)
    tracer.SetWalksPerPoint(48)
    tracer.Update()
    assert not tracer.GetLastBoundaryBuilt()
    fresh = tracer_for(seeds)
    fresh.SetWalksPerPoint(48)
    fresh.Update()
    assert fresh.GetLastBoundaryBuilt()
    assert lines(tracer) == lines(fresh)
    # Another boundary array rebuilds it.
    add_point_array(boundary, "U", lambda x, y, z: x + y)
    tracer.SetInputArrayToProcess(0, 0, 0, POINTS, "U")
    tracer.Update()
    assert tracer.GetLastBoundaryBuilt()


def point_arrays_of(data):
    pd = data.GetPointData()
    return {pd.GetArrayName(k): [pd.GetArray(k).GetTuple(i)
                                 for i in range(pd.GetArray(k).GetNumberOfTuples())]
            for k in range(pd.GetNumberOfArrays())}


def test_inputs_re_executed_with_the_same_values_keep_boundary_and_sums():
    """ParaView's first Apply after a script re-executes filters whose output
    does not change: new arrays with the same values. The built boundary and
    the kept running sums stay (the next walks continue), as with the same
    arrays; a changed value still starts afresh."""
    from vtkmodules.vtkFiltersCore import vtkArrayCalculator
    from vtkmodules.vtkFiltersSources import vtkSphereSource
    sphere = vtkSphereSource()
    sphere.SetThetaResolution(24)
    sphere.SetPhiResolution(24)
    surface = vtkArrayCalculator()
    surface.SetInputConnection(sphere.GetOutputPort())
    surface.AddCoordinateScalarVariable("coordsX", 0)
    surface.SetFunction("coordsX")
    surface.SetResultArrayName("T")
    probe = plane(0.0)
    solver = Solver()
    solver.SetBoundaryConnection(surface.GetOutputPort())
    solver.SetProbeConnection(probe.GetOutputPort())
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    solver.SetWalksPerPoint(32)
    assert updated(solver)
    first_points = probe.GetOutput().GetPoints().GetData()
    sphere.Modified()  # both inputs run again with the same values
    probe.Modified()
    solver.SetWalksPerPoint(64)
    assert not updated(solver)
    assert probe.GetOutput().GetPoints().GetData() is not first_points  # new arrays
    assert solver.GetLastResumedWalksPerPoint() == 32
    surface.SetFunction("coordsX + 1")  # new values
    solver.SetWalksPerPoint(128)
    assert updated(solver)
    assert solver.GetLastResumedWalksPerPoint() == 0


def circle_points(radius=1.0, sides=128):
    return [(radius * math.cos(2 * math.pi * k / sides), radius * math.sin(2 * math.pi * k / sides))
            for k in range(sides)]


def probe_clouds(dimension):
    """Two probes of a few points each, the second moved."""
    z = 0.1 if dimension == 3 else 0.0
    first = [(0.1 * i - 0.3, 0.05 * i - 0.1, z) for i in range(7)]
    moved = [(x + 0.031, y - 0.017, z) for x, y, z in first]
    return point_cloud(first), point_cloud(moved)


def helmholtz_filter(probe):
    helmholtz = gridfree.vtkWalkOnSpheresHelmholtzDecomposition()
    helmholtz.SetBoundaryData(sphere_boundary(resolution=24))
    helmholtz.SetProbeData(probe)
    helmholtz.SetFieldExpression("(y + x)*iHat + (z - x)*jHat + (x*y)*kHat")
    return helmholtz


def cross_field_filter(probe):
    cross = gridfree.vtkWalkOnSpheresCrossField()
    cross.SetBoundaryData(closed_polyline(circle_points()))
    cross.SetProbeData(probe)
    cross.SetSearchSingularities(True)
    cross.SetSearchGridCells(4)
    cross.SetSearchRefinements(0)
    cross.SetNumberOfSeeds(4)
    cross.SetSearchWalksPerPoint(16)
    cross.SetTraceSeparatrices(False)
    return cross


def deformation_filter(probe):
    source = circle_points()
    deformation = gridfree.vtkWalkOnSpheresDeformation()
    deformation.SetSourceData(closed_polyline(source))
    deformation.SetTargetData(closed_polyline([(1.2 * x - 0.3 * y, 0.3 * x + 1.2 * y + 0.1)
                                               for x, y in source]))
    deformation.SetProbeData(probe)
    return deformation


def diffusion_curves_filter(probe):
    boundary = closed_polyline(circle_points())
    add_point_array(boundary, "FrontColor", lambda x, y, z: x * x - y * y)
    add_point_array(boundary, "BackColor", lambda x, y, z: x)
    curves = gridfree.vtkWalkOnSpheresDiffusionCurves()
    curves.SetBoundaryData(boundary)
    curves.SetProbeData(probe)
    curves.SetInputArrayToProcess(0, 0, 0, POINTS, "FrontColor")
    curves.SetInputArrayToProcess(1, 0, 0, POINTS, "BackColor")
    return curves


def test_application_filters_keep_their_boundaries():
    """Each application filter keeps its solves' boundaries between
    executions: a moved probe, other walks or another seed rebuild nothing
    (the Helmholtz decomposition's two potentials each keep their own), and
    the numbers are those of a fresh filter."""
    for make, dimension in ((helmholtz_filter, 3), (cross_field_filter, 2),
                            (deformation_filter, 2), (diffusion_curves_filter, 2)):
        first, moved = probe_clouds(dimension)
        kept = make(first)
        kept.SetWalksPerPoint(16)
        catcher = MessageCatcher(kept)
        kept.Update()
        assert not catcher.errors, catcher.error_text()
        assert kept.GetLastBoundaryBuilt(), make.__name__
        for change in (lambda f: f.SetProbeData(moved), lambda f: f.SetWalksPerPoint(24),
                       lambda f: f.SetSeed(5)):
            change(kept)
            kept.Update()
            assert not kept.GetLastBoundaryBuilt(), make.__name__
        fresh = make(moved)
        fresh.SetWalksPerPoint(24)
        fresh.SetSeed(5)
        fresh.Update()
        assert fresh.GetLastBoundaryBuilt()
        assert point_arrays_of(kept.GetOutput()) == point_arrays_of(fresh.GetOutput()), \
            make.__name__
        assert not catcher.errors, catcher.error_text()
