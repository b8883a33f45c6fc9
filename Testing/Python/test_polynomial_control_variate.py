"""The polynomial control variate through the solver's VTK API: the walks
estimate u − P for a polynomial P fitted to the data, the answers stay
calibrated against the exact solution (values and gradients) with a
narrower spread, points outside the closed boundary are NaN with a warning,
and the problems it cannot take are clear errors."""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import gridfree  # noqa: E402
from vtkmodules.vtkCommonCore import vtkPoints  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkDataObject, vtkPolyData  # noqa: E402
from vtkmodules.vtkFiltersSources import vtkPlaneSource  # noqa: E402

from gridfree_testing import (  # noqa: E402
    MessageCatcher, add_point_array, sphere_boundary, z_scores)

POINTS = vtkDataObject.FIELD_ASSOCIATION_POINTS


def u(x, y, z):
    return math.exp(0.7 * x) * math.cos(0.7 * y) + z * z


def gradient(x, y, z):
    e = math.exp(0.7 * x)
    return (0.7 * e * math.cos(0.7 * y), -0.7 * e * math.sin(0.7 * y), 2.0 * z)


def probe(count=200, outside=2):
    """Points filling the ball of radius 0.8, then `outside` points beyond it."""
    points = vtkPoints()
    golden = math.pi * (3.0 - math.sqrt(5.0))
    for i in range(count):
        r = 0.8 * ((i + 0.5) / count) ** (1.0 / 3.0)
        zc = 1.0 - 2.0 * ((i * 0.618033988749895) % 1.0)
        rho = math.sqrt(max(0.0, 1.0 - zc * zc))
        points.InsertNextPoint(r * rho * math.cos(i * golden), r * rho * math.sin(i * golden), r * zc)
    for k in range(outside):
        points.InsertNextPoint(1.5 + k, 0.1, 0.0)
    data = vtkPolyData()
    data.SetPoints(points)
    return data


def solve(degree, walks=256, boundary=None, equation=None):
    solver = gridfree.vtkWalkOnSpheresSolver()
    catcher = MessageCatcher(solver, solver.GetExecutive())
    solver.SetBoundaryData(boundary if boundary is not None else sphere_boundary(u))
    solver.SetProbeData(probe())
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    solver.SetEquation(equation if equation is not None else gridfree.vtkWalkOnSpheresSolver.POISSON)
    # Δu = 0 for the exponential part (harmonic), 2 for z².
    solver.SetSourceExpression("2 + 0*x")
    solver.SetComputeGradient(True)
    solver.SetWalksPerPoint(walks)
    solver.SetSeed(3)
    solver.SetPolynomialControlVariate(degree)
    solver.Update()
    return solver, catcher


def mean_walk_variance(output, count=200, walks=256):
    variance = output.GetPointData().GetArray("T_Variance")
    return walks * sum(variance.GetValue(i) for i in range(count)) / count


def test_shifted_walks_stay_calibrated_and_narrower():
    plain, _ = solve(0)
    shifted, catcher = solve(3)
    out = shifted.GetOutput()
    assert out.GetFieldData().GetArray("PolynomialControlVariate").GetValue(0) == 3
    assert out.GetFieldData().GetArray("OutsideControlVariate").GetValue(0) == 2
    inside = [i for i in range(out.GetNumberOfPoints()) if i < 200]
    values = z_scores(out, u, "T")
    assert all(math.isnan(values[i]) for i in (200, 201))
    scores = [values[i] for i in inside]
    assert max(abs(z) for z in scores) < 5.0
    assert 0.7 < sum(z * z for z in scores) / len(scores) < 1.4
    g = out.GetPointData().GetArray("T_Gradient")
    gv = out.GetPointData().GetArray("T_Gradient_Variance")
    gz = []
    for i in inside:
        exact = gradient(*out.GetPoint(i))
        for a in range(3):
            gz.append((g.GetComponent(i, a) - exact[a]) / math.sqrt(gv.GetComponent(i, a)))
    assert max(abs(z) for z in gz) < 5.0
    assert 0.7 < sum(z * z for z in gz) / len(gz) < 1.4
    # The fit takes most of the spread away.
    assert mean_walk_variance(out) < 0.5 * mean_walk_variance(plain.GetOutput())
    assert "2 of 202 probe points lie outside the closed boundary" in catcher.warning_text()
    assert "overflowed" not in catcher.warning_text()


def test_problems_it_cannot_take_are_errors():
    # Values of two components (one polynomial fits one).
    pair = sphere_boundary(u)
    pair.GetPointData().RemoveArray("T")
    add_point_array(pair, "T", lambda x, y, z: (u(x, y, z), x), components=2)
    _, catcher = solve(4, walks=8, boundary=pair)
    assert "polynomial control variate takes the Laplace" in catcher.error_text()
    assert "one component" in catcher.error_text()
    # An open surface has no inside.
    plane = vtkPlaneSource()
    plane.Update()
    sheet = plane.GetOutput()
    add_point_array(sheet, "T", u)
    _, catcher = solve(4, walks=8, boundary=sheet)
    assert "closed mesh enclosing a volume" in catcher.error_text()


def test_cache_leaves_points_outside_nan_where_triangles_are_flipped():
    # The sphere's cap above z = 0.8 turned inside out: the caches' own
    # inside test reads the closest triangle's side, so points outside above
    # the cap look inside to them; ray parity says outside, and with the
    # control variate (w grows like P outside) they must be NaN, not answers.
    boundary = sphere_boundary(u)
    from vtkmodules.vtkCommonCore import vtkIdList
    ids = vtkIdList()
    for cell in range(boundary.GetNumberOfCells()):
        boundary.GetCellPoints(cell, ids)
        corners = [ids.GetId(k) for k in range(3)]
        if sum(boundary.GetPoint(k)[2] for k in corners) / 3.0 > 0.8:
            boundary.ReplaceCell(cell, 3, [corners[0], corners[2], corners[1]])
    points = vtkPoints()
    for z in (1.12, 1.2):
        points.InsertNextPoint(0.02, -0.01, z)
    points.InsertNextPoint(0.1, 0.2, -0.1)
    cloud = vtkPolyData()
    cloud.SetPoints(points)
    solver = gridfree.vtkWalkOnSpheresSolver()
    solver.SetBoundaryData(boundary)
    solver.SetProbeData(cloud)
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    solver.SetEquation(gridfree.vtkWalkOnSpheresSolver.POISSON)
    solver.SetSourceExpression("2 + 0*x")
    solver.SetEstimator(gridfree.vtkWalkOnSpheresSolver.SPHERE_CACHE)
    solver.SetPolynomialControlVariate(3)
    solver.Update()
    t = solver.GetOutput().GetPointData().GetArray("T")
    assert math.isnan(t.GetValue(0)) and math.isnan(t.GetValue(1)), (t.GetValue(0), t.GetValue(1))
    assert abs(t.GetValue(2) - u(0.1, 0.2, -0.1)) < 0.1
