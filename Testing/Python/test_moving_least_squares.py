"""Moving least squares interpolation of scattered samples (paper Sec. 5.2.1):
exact on quadratics, the propagated variance, visibility that keeps values
from bleeding across a thin wall, 2D boundaries, errors and reproducibility."""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import gridfree  # noqa: E402
from vtkmodules.vtkCommonCore import vtkPoints  # noqa: E402
from vtkmodules.vtkCommonDataModel import (  # noqa: E402
    vtkCellArray, vtkDataObject, vtkImageData, vtkPolyData)
from vtkmodules.vtkFiltersSources import vtkPlaneSource  # noqa: E402

from gridfree_testing import (  # noqa: E402
    MessageCatcher, add_point_array, circle_boundary, point_cloud, saddle)

POINTS = vtkDataObject.FIELD_ASSOCIATION_POINTS


def lattice(n, lo, hi, z=0.0, jitter=0.0):
    """n x n points in [lo, hi]^2 at height z, shifted by a fixed pattern."""
    points = []
    for j in range(n):
        for i in range(n):
            dx = jitter * math.sin(12.9898 * i + 78.233 * j)
            dy = jitter * math.cos(39.3468 * i + 11.135 * j)
            points.append((lo + (hi - lo) * i / (n - 1) + dx,
                           lo + (hi - lo) * j / (n - 1) + dy, z))
    return points


def sample_cloud(points, value, gradient=None):
    cloud = point_cloud(points)
    add_point_array(cloud, "T", lambda x, y, z: value(x, y, z))
    if gradient is not None:
        add_point_array(cloud, "T_Gradient", lambda x, y, z: gradient(x, y, z), components=3)
    return cloud


def image(n, lo, hi, z=0.0):
    data = vtkImageData()
    data.SetDimensions(n, n, 1)
    data.SetOrigin(lo, lo, z)
    data.SetSpacing((hi - lo) / (n - 1), (hi - lo) / (n - 1), 1.0)
    return data


def interpolate(target, samples, boundary=None, **settings):
    mls = gridfree.vtkMovingLeastSquaresInterpolator()
    catcher = MessageCatcher(mls, mls.GetExecutive())
    mls.SetInputData(target)
    if samples is not None:
        mls.SetSourceData(samples)
    if boundary is not None:
        mls.SetBoundaryData(boundary)
    mls.SetInputArrayToProcess(0, 1, 0, POINTS, settings.pop("array", "T"))
    for name, value in settings.items():
        getattr(mls, "Set" + name)(value)
    mls.Update()
    return mls.GetOutput(), catcher


def test_quadratics_are_reproduced_with_and_without_gradients():
    samples = sample_cloud(lattice(9, -1.0, 1.0, jitter=0.03), saddle,
                           lambda x, y, z: (2 * x, -2 * y, 0.0))
    target = image(17, -0.9, 0.9)
    for use_gradients in (True, False):
        out, catcher = interpolate(target, samples, UseGradients=use_gradients)
        assert not catcher.errors
        assert out.IsA("vtkImageData") and out.GetNumberOfPoints() == 17 * 17
        values = out.GetPointData().GetArray("T")
        gradients = out.GetPointData().GetArray("T_Gradient")
        for i in range(out.GetNumberOfPoints()):
            x, y, _ = out.GetPoint(i)
            assert abs(values.GetTuple1(i) - saddle(x, y)) < 1e-9
            gx, gy, _ = gradients.GetTuple3(i)
            assert abs(gx - 2 * x) < 1e-7 and abs(gy + 2 * y) < 1e-7
        assert out.GetPointData().GetScalars().GetName() == "T"


def test_solver_samples_interpolate_within_their_noise_and_variance_is_consistent():
    """Samples of the solver (x^2 - y^2 on the unit sphere) interpolated onto a
    slice: the error is that of the samples' noise carried through the fit,
    which T_Variance reports: mean z^2 near 1 and every |z| < 5."""
    from gridfree_testing import sphere_boundary
    boundary = sphere_boundary(resolution=64)
    cloud = point_cloud(lattice(12, -0.6, 0.6, jitter=0.01))
    solver = gridfree.vtkWalkOnSpheresSolver()
    solver.SetBoundaryData(boundary)
    solver.SetProbeData(cloud)
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    solver.SetWalksPerPoint(256)
    solver.ComputeGradientOn()
    solver.SetSeed(3)
    solver.Update()
    out, catcher = interpolate(image(15, -0.5, 0.5), solver.GetOutput(), boundary)
    assert not catcher.errors and not catcher.warnings
    values = out.GetPointData().GetArray("T")
    variances = out.GetPointData().GetArray("T_Variance")
    squares = []
    for i in range(out.GetNumberOfPoints()):
        x, y, _ = out.GetPoint(i)
        z = (values.GetTuple1(i) - saddle(x, y)) / math.sqrt(variances.GetTuple1(i))
        assert abs(z) < 5.0
        squares.append(z * z)
    # Neighbouring target points share samples, so the z are correlated:
    # a loose band, still far from what a variance off by 2x would give.
    assert 0.5 < sum(squares) / len(squares) < 1.6


def thin_wall():
    """A single square wall at x = 0 spanning y, z in [-1, 1]."""
    points = vtkPoints()
    for p in ((0, -1, -1), (0, 1, -1), (0, 1, 1), (0, -1, 1)):
        points.InsertNextPoint(*p)
    cells = vtkCellArray()
    cells.InsertNextCell(4, [0, 1, 2, 3])
    wall = vtkPolyData()
    wall.SetPoints(points)
    wall.SetPolys(cells)
    return wall


def test_visibility_keeps_values_from_bleeding_across_a_thin_wall():
    # Samples 0 left of the wall and 1 right of it, spaced 0.1 apart; the
    # targets lie 0.01 left of the wall, nearer to some right samples than
    # to most left ones.
    left = [(x, y, 0.0) for x in (-0.05, -0.15, -0.25) for y in (-0.2, -0.1, 0.0, 0.1, 0.2)]
    right = [(-x, y, z) for (x, y, z) in left]
    samples = sample_cloud(left + right, lambda x, y, z: 0.0 if x < 0 else 1.0,
                           lambda x, y, z: (0.0, 0.0, 0.0))
    target = point_cloud([(-0.01, y, 0.0) for y in (-0.1, 0.0, 0.1)])
    seen, catcher = interpolate(target, samples, thin_wall())
    assert not catcher.errors
    blind, _ = interpolate(target, samples, thin_wall(), UseVisibility=False)
    for i in range(3):
        assert abs(seen.GetPointData().GetArray("T").GetTuple1(i)) < 1e-12
        assert blind.GetPointData().GetArray("T").GetTuple1(i) > 0.1
        assert seen.GetPointData().GetArray("MLSNeighbors").GetValue(i) == 12


def test_a_point_walled_off_from_every_sample_is_nan_with_a_warning():
    samples = sample_cloud([(0.1 * (i + 1), 0.05 * j, 0.0) for i in range(4) for j in range(4)],
                           lambda x, y, z: 1.0)
    target = point_cloud([(-0.1, 0.0, 0.0), (0.2, 0.1, 0.0)])
    out, catcher = interpolate(target, samples, thin_wall())
    values = out.GetPointData().GetArray("T")
    assert math.isnan(values.GetTuple1(0))
    assert abs(values.GetTuple1(1) - 1.0) < 1e-12
    assert "1 of 2 target points see no sample" in catcher.warning_text()


def test_two_dimensional_boundaries_block_visibility_too():
    # A circle: samples inside carry 0, outside 1; a target just inside sees
    # only inside samples.
    circle = circle_boundary(lambda x, y, z: 0.0, sides=256)
    inside = [(r * math.cos(a), r * math.sin(a), 0.0) for r in (0.9, 0.8, 0.7)
              for a in [k * 2 * math.pi / 24 for k in range(24)]]
    outside = [(r * math.cos(a), r * math.sin(a), 0.0) for r in (1.05, 1.15)
               for a in [k * 2 * math.pi / 24 for k in range(24)]]
    samples = sample_cloud(inside + outside, lambda x, y, z: 0.0 if x * x + y * y < 1 else 1.0)
    target = point_cloud([(0.98, 0.0, 0.0), (0.0, -0.98, 0.0)])
    seen, catcher = interpolate(target, samples, circle)
    assert not catcher.errors
    blind, _ = interpolate(target, samples, circle, UseVisibility=False)
    for i in range(2):
        assert abs(seen.GetPointData().GetArray("T").GetTuple1(i)) < 1e-9
        assert blind.GetPointData().GetArray("T").GetTuple1(i) > 0.1


def test_bad_inputs_are_errors_not_crashes():
    target = image(4, 0.0, 1.0)
    _, catcher = interpolate(target, None)
    assert "Input port 1" in catcher.error_text()  # the pipeline's own check
    _, catcher = interpolate(target, point_cloud([]))
    assert "has no points" in catcher.error_text()
    samples = sample_cloud(lattice(3, 0.0, 1.0), saddle)
    _, catcher = interpolate(target, samples, array="Missing")
    assert "No value array" in catcher.error_text()
    # A boundary of vertices only cannot block anything.
    vertices = point_cloud([(0, 0, 0), (1, 0, 0)])
    _, catcher = interpolate(target, samples, vertices)
    assert "cannot block visibility" in catcher.error_text()


def test_the_same_for_any_thread_count():
    samples = sample_cloud(lattice(10, -1.0, 1.0, jitter=0.04),
                           lambda x, y, z: math.sin(3 * x) * math.cosh(3 * y))
    plane = vtkPlaneSource()
    plane.SetResolution(40, 40)
    plane.Update()
    one, _ = interpolate(plane.GetOutput(), samples, NumberOfThreads=1)
    two, _ = interpolate(plane.GetOutput(), samples, NumberOfThreads=2)
    a, b = one.GetPointData().GetArray("T"), two.GetPointData().GetArray("T")
    assert all(a.GetTuple1(i) == b.GetTuple1(i) for i in range(one.GetNumberOfPoints()))
