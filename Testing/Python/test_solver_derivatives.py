"""Gradient and Hessian of vtkWalkOnSpheresSolver through the Python API: the
saddle x^2 - y^2 on the unit sphere, whose gradient is (2x, -2y, 0) and whose
Hessian is diag(2, -2, 0) everywhere inside."""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import gridfree  # noqa: E402
from vtkmodules.vtkCommonCore import vtkIdList  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkDataObject  # noqa: E402
from vtkmodules.vtkFiltersFlowPaths import vtkStreamTracer  # noqa: E402
from vtkmodules.vtkFiltersSources import vtkPlaneSource  # noqa: E402

from gridfree_testing import saddle, sphere_boundary  # noqa: E402

POINTS = vtkDataObject.FIELD_ASSOCIATION_POINTS
WALKS = 256


def exact_gradient(x, y, z):
    return (2.0 * x, -2.0 * y, 0.0)


def exact_hessian(x, y, z):
    return (2.0, 0.0, 0.0,
            0.0, -2.0, 0.0,
            0.0, 0.0, 0.0)


def probe_plane():
    # 14 x 14 points on a slice at z = 0.2, all at least 0.3 inside the sphere.
    plane = vtkPlaneSource()
    plane.SetOrigin(-0.55, -0.55, 0.2)
    plane.SetPoint1(0.55, -0.55, 0.2)
    plane.SetPoint2(-0.55, 0.55, 0.2)
    plane.SetResolution(13, 13)
    plane.Update()
    return plane.GetOutput()


def solve(control_variates, seed=5, offset=0.0, antithetic=False, walks=WALKS):
    solver = gridfree.vtkWalkOnSpheresSolver()
    solver.SetBoundaryData(sphere_boundary(lambda x, y, z: offset + saddle(x, y), resolution=128))
    solver.SetProbeData(probe_plane())
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    solver.SetWalksPerPoint(walks)
    solver.SetSeed(seed)
    solver.ComputeGradientOn()
    solver.ComputeHessianOn()
    solver.SetControlVariates(control_variates)
    solver.SetAntitheticPairs(antithetic)
    solver.Update()
    return solver, solver.GetOutput()


def worst_z_score(output, name, exact):
    values = output.GetPointData().GetArray(name)
    variances = output.GetPointData().GetArray(name + "_Variance")
    assert values is not None and variances is not None, name
    components = values.GetNumberOfComponents()
    assert variances.GetNumberOfComponents() == components, name
    worst = (0.0, None)
    for i in range(output.GetNumberOfPoints()):
        point = output.GetPoint(i)
        expected = exact(*point)
        for c in range(components):
            error = values.GetComponent(i, c) - expected[c]
            variance = variances.GetComponent(i, c)
            if variance > 0.0:
                z = abs(error) / math.sqrt(variance)
            else:
                # No spread at all: the estimate must then be exact.
                z = 0.0 if abs(error) < 1e-9 else math.inf
            if z > worst[0]:
                worst = (z, (i, c, point, values.GetComponent(i, c), expected[c], variance))
    return worst


def mean_variance(output, name):
    variances = output.GetPointData().GetArray(name)
    total = 0.0
    for i in range(variances.GetNumberOfTuples()):
        total += sum(variances.GetTuple(i))
    return total / (variances.GetNumberOfTuples() * variances.GetNumberOfComponents())


def test_gradient_and_hessian_of_saddle():
    solver, output = solve(control_variates=True)
    assert solver.GetControlVariates()
    assert output.GetNumberOfPoints() == 196
    data = output.GetPointData()

    gradient = data.GetArray("T_Gradient")
    hessian = data.GetArray("T_Hessian")
    assert gradient.GetNumberOfComponents() == 3
    assert hessian.GetNumberOfComponents() == 9
    assert data.GetScalars().GetName() == "T"
    assert data.GetVectors() is not None and data.GetVectors().GetName() == "T_Gradient"
    assert data.GetTensors() is not None and data.GetTensors().GetName() == "T_Hessian"

    status = data.GetArray("DerivativeStatus")
    assert status is not None
    assert status.GetRange() == (0.0, 0.0), status.GetRange()

    z, where = worst_z_score(output, "T_Gradient", exact_gradient)
    assert z < 5.0, ("gradient", z, where)
    z, where = worst_z_score(output, "T_Hessian", exact_hessian)
    assert z < 5.0, ("Hessian", z, where)

    # The estimate is symmetric, as the Hessian of a smooth function is.
    for i in range(output.GetNumberOfPoints()):
        h = hessian.GetTuple(i)
        for r in range(3):
            for c in range(r + 1, 3):
                assert abs(h[3 * r + c] - h[3 * c + r]) <= 1e-9 * (1.0 + abs(h[3 * r + c]))


def test_control_variates_reduce_gradient_variance():
    # The gradient's control variate is the running estimate of u at the
    # point times the zero-mean sphere weight, so what it removes is the
    # noise of the level of u, not of its variation: for the bare saddle,
    # u is near 0 around the centre and the gain is about 1. A temperature
    # 2 degrees above it (same gradient and Hessian) shows the gain.
    _, with_cv = solve(control_variates=True, offset=2.0)
    _, without_cv = solve(control_variates=False, offset=2.0)
    # Without control variates the estimates stay unbiased, only noisier.
    z, where = worst_z_score(without_cv, "T_Gradient", exact_gradient)
    assert z < 5.0, ("gradient without control variates", z, where)
    ratio = (mean_variance(without_cv, "T_Gradient_Variance")
             / mean_variance(with_cv, "T_Gradient_Variance"))
    assert ratio >= 3.0, ratio


def test_antithetic_pairs_keep_derivatives_calibrated():
    # Each sample is a pair of walks from opposite points of the first ball.
    # At the same number of walks (WALKS / 2 pairs) the gradient and Hessian
    # stay within 5 standard errors everywhere, and the gradient's variance
    # is no higher (here about 5% lower: the walks' own noise dominates the
    # even part of the saddle that a pair cancels). A pair whose second walk
    # repeated the first would be about twice as noisy, one whose second walk
    # did not replay the first one's random numbers about 8% noisier.
    solver, pairs = solve(control_variates=True, antithetic=True, walks=WALKS // 2)
    assert solver.GetAntitheticPairs()
    _, single = solve(control_variates=True)
    for name, exact in (("T_Gradient", exact_gradient), ("T_Hessian", exact_hessian)):
        z, where = worst_z_score(pairs, name, exact)
        assert z < 5.0, (name + " with antithetic pairs", z, where)
    ratio = (mean_variance(single, "T_Gradient_Variance")
             / mean_variance(pairs, "T_Gradient_Variance"))
    assert ratio >= 0.97, ratio


def test_stream_tracer_follows_gradient():
    solver, _ = solve(control_variates=True)
    # A 3 x 3 grid of seeds in the slice.
    seeds = vtkPlaneSource()
    seeds.SetOrigin(-0.3, -0.3, 0.2)
    seeds.SetPoint1(0.3, -0.3, 0.2)
    seeds.SetPoint2(-0.3, 0.3, 0.2)
    seeds.SetResolution(2, 2)
    tracer = vtkStreamTracer()
    tracer.SetInputConnection(solver.GetOutputPort())
    tracer.SetSourceConnection(seeds.GetOutputPort())
    tracer.SetInputArrayToProcess(0, 0, 0, POINTS, "T_Gradient")
    tracer.SurfaceStreamlinesOn()
    tracer.SetIntegrationDirectionToBoth()
    tracer.SetIntegratorTypeToRungeKutta4()
    tracer.SetIntegrationStepUnit(vtkStreamTracer.CELL_LENGTH_UNIT)
    tracer.SetInitialIntegrationStep(0.2)
    tracer.SetMaximumPropagation(3.0)
    tracer.Update()
    lines = tracer.GetOutput()
    assert lines.GetNumberOfLines() >= 1
    lengths = []
    cells = lines.GetLines()
    cells.InitTraversal()
    ids = vtkIdList()
    while cells.GetNextCell(ids):
        lengths.append(ids.GetNumberOfIds())
    assert max(lengths) > 10, lengths
    # Surface streamlines stay in the slice.
    low_z, high_z = lines.GetBounds()[4:6]
    assert abs(low_z - 0.2) < 1e-6 and abs(high_z - 0.2) < 1e-6, (low_z, high_z)
