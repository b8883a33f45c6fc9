"""Output-sensitive streamlines (paper Sec. 5.2.6): vtkWalkOnSpheresStreamTracer
follows the estimated gradient, calling the solver only at the integrator's
points. For u = x² − y² in the unit ball, ∇u = (2x, −2y, 0): the lines are
the hyperbolas x·y = const in planes z = const."""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import gridfree  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkDataObject  # noqa: E402

from gridfree_testing import MessageCatcher, point_cloud, sphere_boundary  # noqa: E402

POINTS = vtkDataObject.FIELD_ASSOCIATION_POINTS
Tracer = gridfree.vtkWalkOnSpheresStreamTracer
SEEDS = [(0.1, 0.5, 0.0), (0.2, -0.4, 0.2), (-0.15, 0.3, -0.3)]


def tracer_for(seeds=SEEDS, **settings):
    tracer = Tracer()
    tracer.SetBoundaryData(sphere_boundary(resolution=64))
    tracer.SetSeedsData(point_cloud(seeds))
    tracer.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    tracer.SetWalksPerPoint(2048)
    tracer.SetStepLength(0.02)
    tracer.SetStepLengthIsRelative(False)
    tracer.SetMaximumPropagation(0.6)
    tracer.SetMaximumNumberOfSteps(100)
    for name, value in settings.items():
        getattr(tracer, "Set" + name)(value)
    return tracer


def lines_of(output):
    """Each polyline as (points, seed id, reason)."""
    lines = []
    cells = output.GetLines()
    cells.InitTraversal()
    ids = output.GetCellData().GetArray("SeedIds")
    reasons = output.GetCellData().GetArray("ReasonForTermination")
    from vtkmodules.vtkCommonCore import vtkIdList
    pts = vtkIdList()
    c = 0
    while cells.GetNextCell(pts):
        lines.append(([output.GetPoint(pts.GetId(k)) for k in range(pts.GetNumberOfIds())],
                      ids.GetValue(c), reasons.GetValue(c)))
        c += 1
    return lines


def check_hyperbolas(output, seeds, tolerance):
    lines = lines_of(output)
    assert len(lines) >= len(seeds)
    for points, seed, _ in lines:
        x0, y0, z0 = seeds[seed]
        assert points[0] == seeds[seed]
        for x, y, z in points:
            assert abs(x * y - x0 * y0) < tolerance, (seed, x, y, x * y, x0 * y0)
            assert abs(z - z0) < tolerance, (seed, z, z0)
    return lines


def test_heun_lines_follow_the_hyperbolas_up_the_gradient():
    tracer = tracer_for()
    catcher = MessageCatcher(tracer)
    tracer.Update()
    assert catcher.errors == []
    out = tracer.GetOutput()
    lines = check_hyperbolas(out, SEEDS, 0.02)
    for points, seed, reason in lines:
        # Up the gradient of x² − y²: |x| grows and |y| shrinks.
        assert abs(points[-1][0]) > abs(points[0][0]) and abs(points[-1][1]) < abs(points[0][1])
        assert reason in (Tracer.OUT_OF_LENGTH, Tracer.OUT_OF_STEPS, Tracer.CLOSE_TO_BOUNDARY)
    # Value and gradient along the lines match u and ∇u within 5 standard errors.
    pd = out.GetPointData()
    t, tv = pd.GetArray("T"), pd.GetArray("T_Variance")
    g, gv = pd.GetArray("T_Gradient"), pd.GetArray("T_Gradient_Variance")
    assert pd.GetVectors().GetName() == "T_Gradient"
    for i in range(out.GetNumberOfPoints()):
        x, y, z = out.GetPoint(i)
        assert abs(t.GetValue(i) - (x * x - y * y)) < 5 * math.sqrt(tv.GetValue(i)) + 1e-9
        for k, exact in enumerate((2 * x, -2 * y, 0.0)):
            assert abs(g.GetComponent(i, k) - exact) < 5 * math.sqrt(gv.GetComponent(i, k)) + 1e-9
    # IntegrationTime is the arc length from the seed.
    time = pd.GetArray("IntegrationTime")
    assert time.GetValue(0) == 0.0 and max(time.GetRange()) <= 0.6 + 1e-9


def test_rk4_both_directions():
    tracer = tracer_for(IntegratorType=Tracer.RUNGE_KUTTA_4, IntegrationDirection=Tracer.BOTH,
                        MaximumPropagation=0.3)
    tracer.Update()
    lines = check_hyperbolas(tracer.GetOutput(), SEEDS, 0.02)
    assert len(lines) == 2 * len(SEEDS)
    times = tracer.GetOutput().GetPointData().GetArray("IntegrationTime").GetRange()
    assert times[0] < 0.0 < times[1]  # backward lines count time down


def test_lines_stop_near_the_boundary_and_the_same_seed_gives_the_same_lines():
    tracer = tracer_for(seeds=[(0.5, 0.05, 0.0)], MaximumPropagation=2.0,
                        MaximumNumberOfSteps=400, NumberOfThreads=1)
    tracer.Update()
    ((points, _, reason),) = lines_of(tracer.GetOutput())
    assert reason in (Tracer.CLOSE_TO_BOUNDARY, Tracer.OUT_OF_DOMAIN)
    assert math.sqrt(sum(c * c for c in points[-1])) > 0.95  # ran to the sphere
    again = tracer_for(seeds=[(0.5, 0.05, 0.0)], MaximumPropagation=2.0,
                       MaximumNumberOfSteps=400, NumberOfThreads=2)
    again.Update()
    assert lines_of(again.GetOutput())[0][0] == points


def test_bad_input_is_reported():
    tracer = Tracer()
    catcher = MessageCatcher(tracer, tracer.GetExecutive())
    tracer.SetBoundaryData(sphere_boundary(resolution=16))
    tracer.SetSeedsData(point_cloud([(0.1, 0.1, 0.1)]))
    tracer.SetInputArrayToProcess(0, 0, 0, POINTS, "Missing")
    tracer.Update()
    assert "no point or cell array named 'Missing'" in catcher.error_text()
    assert tracer.GetOutput().GetNumberOfPoints() == 0


def test_nan_input_never_crashes():
    """NaN seeds are left out with a warning, and boundary values with NaN
    in them are refused with an error: the tracer neither crashes nor
    traces NaN lines."""
    nan = float("nan")
    tracer = tracer_for(seeds=[(nan, 0.2, 0.0), (0.1, 0.5, 0.0), (0.0, nan, nan)],
                        WalksPerPoint=64, MaximumNumberOfSteps=5)
    catcher = MessageCatcher(tracer, tracer.GetExecutive())
    tracer.Update()
    out = tracer.GetOutput()
    for i in range(out.GetNumberOfPoints()):
        assert all(math.isfinite(c) for c in out.GetPoint(i)), out.GetPoint(i)
    assert out.GetNumberOfPoints() > 0  # the finite seed's line
    boundary = sphere_boundary(resolution=16)
    boundary.GetPointData().GetArray("T").SetValue(0, nan)
    tracer = tracer_for(WalksPerPoint=16, MaximumNumberOfSteps=3)
    catcher = MessageCatcher(tracer, tracer.GetExecutive())
    tracer.SetBoundaryData(boundary)
    tracer.Update()
    assert catcher.error_text() or catcher.warning_text()
    out = tracer.GetOutput()
    for i in range(out.GetNumberOfPoints()):
        assert all(math.isfinite(c) for c in out.GetPoint(i)), out.GetPoint(i)
