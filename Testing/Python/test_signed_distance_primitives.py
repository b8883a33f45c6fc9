"""The signed distance primitives from Python: importable from `gridfree`
like vtkWalkOnSpheresSolver, exact distances with unit gradients, their
bounds and Lipschitz constants, invalid parameters, and the solver on them."""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import gridfree  # noqa: E402
from gridfree import (  # noqa: E402
    vtkSignedDistanceBox,
    vtkSignedDistanceCapsule,
    vtkSignedDistanceCylinder,
    vtkSignedDistancePlane,
    vtkSignedDistancePrimitive,
    vtkSignedDistanceRoundedBox,
    vtkSignedDistanceSphere,
    vtkSignedDistanceTorus,
)
from vtkmodules.vtkCommonCore import vtkPoints  # noqa: E402
from vtkmodules.vtkCommonDataModel import (  # noqa: E402
    vtkImplicitBoolean,
    vtkImplicitFunction,
    vtkPolyData,
)
from vtkmodules.vtkCommonTransforms import vtkTransform  # noqa: E402

from gridfree_testing import MessageCatcher  # noqa: E402

ALL = (vtkSignedDistanceSphere, vtkSignedDistanceBox, vtkSignedDistanceRoundedBox,
       vtkSignedDistanceTorus, vtkSignedDistanceCylinder, vtkSignedDistanceCapsule,
       vtkSignedDistancePlane)


def test_import_and_types():
    for cls in ALL:
        f = cls()
        assert isinstance(f, vtkSignedDistancePrimitive)
        assert isinstance(f, vtkImplicitFunction)
        assert cls.__name__ in gridfree.__all__
        assert f.HasValidParameters(), (cls.__name__, f.GetParameterError())
        assert f.GetParameterError() == ""
        assert f.GetLipschitzConstant() == 1.0
        assert cls.__name__ in str(f)  # PrintSelf


def test_sphere_values_gradient_and_bounds():
    s = vtkSignedDistanceSphere()
    s.SetCenter(1.0, 2.0, 3.0)
    s.SetRadius(0.5)
    assert s.GetCenter() == (1.0, 2.0, 3.0) and s.GetRadius() == 0.5
    assert abs(s.FunctionValue(1.0, 2.0, 5.0) - 1.5) < 1e-15
    assert abs(s.FunctionValue(1.0, 2.0, 3.0) + 0.5) < 1e-15
    g = s.FunctionGradient(4.0, 6.0, 3.0)
    assert max(abs(a - b) for a, b in zip(g, (0.6, 0.8, 0.0))) < 1e-15
    bounds = [0.0] * 6
    assert s.GetZeroSetBounds(bounds)
    assert bounds == [0.5, 1.5, 1.5, 2.5, 2.5, 3.5]


def test_every_primitive_is_a_distance():
    # A signed distance has |grad| = 1 and moving by t along the gradient
    # changes it by t (away from edges and medial points).
    torus = vtkSignedDistanceTorus()
    torus.SetAxis(0.0, 1.0, 1.0)
    cylinder = vtkSignedDistanceCylinder()
    cylinder.SetAxis(1.0, 0.0, 0.0)
    capsule = vtkSignedDistanceCapsule()
    capsule.SetPoint2(0.5, 0.5, 0.0)
    plane = vtkSignedDistancePlane()
    plane.SetNormal(0.0, 3.0, 4.0)
    for f in (vtkSignedDistanceSphere(), vtkSignedDistanceBox(), vtkSignedDistanceRoundedBox(),
              torus, cylinder, capsule, plane):
        p = (1.3, 0.7, -0.9)
        value = f.FunctionValue(p)
        g = f.FunctionGradient(p)
        assert abs(math.hypot(*g) - 1.0) < 1e-12, f.GetClassName()
        t = 0.01
        q = tuple(a + t * b for a, b in zip(p, g))
        assert abs(f.FunctionValue(q) - value - t) < 1e-9, f.GetClassName()
    assert abs(plane.FunctionValue(0.0, 1.0, 1.0) - 7.0 / 5.0) < 1e-15
    assert not plane.GetZeroSetBounds([0.0] * 6)


def test_invalid_parameters():
    s = vtkSignedDistanceSphere()
    s.SetRadius(0.0)
    assert not s.HasValidParameters()
    assert "vtkSignedDistanceSphere" in s.GetParameterError()
    assert "Radius" in s.GetParameterError()
    assert math.isnan(s.FunctionValue(0.1, 0.2, 0.3))
    assert all(math.isnan(c) for c in s.FunctionGradient(0.1, 0.2, 0.3))
    assert not s.GetZeroSetBounds([0.0] * 6)
    t = vtkSignedDistanceTorus()
    t.SetMinorRadius(2.0 * t.GetMajorRadius())
    assert "MinorRadius" in t.GetParameterError()


def test_transform_and_lipschitz_constant():
    s = vtkSignedDistanceSphere()
    s.SetRadius(1.0)
    transform = vtkTransform()
    transform.Scale(2.0, 2.0, 2.0)
    s.SetTransform(transform)  # the function is now phi(2 x)
    assert abs(s.GetLipschitzConstant() - 2.0) < 1e-12
    assert abs(s.FunctionValue(1.0, 0.0, 0.0) - 1.0) < 1e-15
    bounds = [0.0] * 6
    assert s.GetZeroSetBounds(bounds)
    assert max(abs(a - b) for a, b in zip(bounds, [-0.5, 0.5] * 3)) < 1e-12


def _solve(function, probe_points, lipschitz=1.0):
    points = vtkPoints()
    for p in probe_points:
        points.InsertNextPoint(p)
    probe = vtkPolyData()
    probe.SetPoints(points)
    solver = gridfree.vtkWalkOnSpheresSolver()
    catcher = MessageCatcher(solver, solver.GetExecutive())
    solver.SetImplicitBoundary(function)
    solver.SetLipschitzBound(lipschitz)
    solver.SetBoundaryValueExpression("x*x - y*y + 0.5*z")
    solver.SetProbeData(probe)
    solver.SetWalksPerPoint(512)
    solver.SetSeed(9)
    solver.Update()
    return solver.GetOutput(), catcher


def _ball_points(count, center, radius):
    import random
    rng = random.Random(77)
    out = []
    while len(out) < count:
        d = [rng.uniform(-1.0, 1.0) for _ in range(3)]
        if sum(c * c for c in d) <= 1.0:
            out.append(tuple(c + radius * e for c, e in zip(center, d)))
    return out


def _expect_calibrated(output, count):
    mean = output.GetPointData().GetArray("Solution")
    var = output.GetPointData().GetArray("Solution_Variance")
    total = 0.0
    for i in range(count):
        x, y, z = output.GetPoint(i)
        score = (mean.GetTuple1(i) - (x * x - y * y + 0.5 * z)) / math.sqrt(var.GetTuple1(i))
        assert abs(score) < 5.0, (i, score)
        total += score * score
    assert 0.5 < total / count < 1.7, total / count


def test_solver_on_a_torus_and_a_union():
    torus = vtkSignedDistanceTorus()
    torus.SetMajorRadius(1.0)
    torus.SetMinorRadius(0.4)
    # Points inside the tube: around the core circle in the xy-plane.
    probe = [(math.cos(a) * (1.0 + 0.2 * math.cos(3 * a)), math.sin(a) * (1.0 + 0.2 * math.cos(3 * a)),
              0.2 * math.sin(5 * a)) for a in [2 * math.pi * k / 40 for k in range(40)]]
    output, catcher = _solve(torus, probe)
    assert catcher.error_text() == "" and catcher.warning_text() == ""
    _expect_calibrated(output, len(probe))

    a = vtkSignedDistanceCapsule()
    a.SetPoint1(-0.6, 0.0, 0.0)
    a.SetPoint2(0.6, 0.0, 0.0)
    a.SetRadius(0.4)
    b = vtkSignedDistanceRoundedBox()
    b.SetHalfExtents(0.4, 0.9, 0.4)
    union = vtkImplicitBoolean()
    union.SetOperationTypeToUnion()
    union.AddFunction(a)
    union.AddFunction(b)
    probe = _ball_points(20, (-0.6, 0.0, 0.0), 0.35) + _ball_points(20, (0.0, 0.55, 0.0), 0.3)
    output, catcher = _solve(union, probe, lipschitz=0.5)  # not used below 1
    assert catcher.error_text() == "" and catcher.warning_text() == ""
    _expect_calibrated(output, len(probe))


def test_solver_reports_invalid_primitive():
    s = vtkSignedDistanceCylinder()
    s.SetAxis(0.0, 0.0, 0.0)
    output, catcher = _solve(s, [(0.0, 0.0, 0.0)])
    assert "vtkSignedDistanceCylinder" in catcher.error_text()
    assert "Axis" in catcher.error_text()
    assert output.GetPointData().GetArray("Solution") is None
