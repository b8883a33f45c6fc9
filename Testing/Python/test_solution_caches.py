"""The cache estimators in the filters (Boundary Cache, Sphere Cache): the
cache answers the points clear of the boundary's shell (FromBoundaryCache
1, no walks of their own), walks answer the shell, and the answers agree
with the exact solution within their error bars. The cache lives with the
problem: a moved probe reuses it (the boundary cache with no new walks,
field data CacheWalksRun 0; the sphere cache with walks only for spheres it
has not made yet) and gets the numbers a fresh solver gives there; more
walks per boundary cache point run only the missing ones; a new seed or new
boundary values build a new cache. A target standard error grows the
cache's walks. What a cache cannot answer is refused in words."""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import gridfree  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkDataObject  # noqa: E402
from vtkmodules.vtkFiltersSources import vtkPlaneSource  # noqa: E402

from gridfree_testing import (  # noqa: E402
    MessageCatcher, point_cloud, sphere_boundary, update_aborted_at_first_progress)

POINTS = vtkDataObject.FIELD_ASSOCIATION_POINTS
import pytest  # noqa: E402

CACHE = gridfree.vtkWalkOnSpheresAlgorithm.BOUNDARY_CACHE
SPHERES = gridfree.vtkWalkOnSpheresAlgorithm.SPHERE_CACHE


def harmonic(x, y, z):
    return x * x - y * y + 0.3 * z


def harmonic_gradient(x, y, z):
    return (2.0 * x, -2.0 * y, 0.3)


def plane(z, resolution=8):
    source = vtkPlaneSource()
    source.SetOrigin(-0.8, -0.8, z)
    source.SetPoint1(0.8, -0.8, z)
    source.SetPoint2(-0.8, 0.8, z)
    source.SetResolution(resolution, resolution)
    return source


def move(source, z):
    source.SetOrigin(-0.8, -0.8, z)
    source.SetPoint1(0.8, -0.8, z)
    source.SetPoint2(-0.8, 0.8, z)


def cache_solver(boundary, probe, estimator=CACHE, **settings):
    solver = gridfree.vtkWalkOnSpheresSolver()
    solver.SetBoundaryData(boundary)
    solver.SetProbeConnection(probe.GetOutputPort())
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    solver.SetEstimator(estimator)
    solver.SetCachePoints(1024)
    solver.SetWalksPerCachePoint(32)
    solver.SetCacheShellDistance(0.05)
    solver.SetWalksPerPoint(64)
    solver.SetComputeGradient(True)
    for name, value in settings.items():
        getattr(solver, "Set" + name)(value)
    return solver


def field(output, name):
    array = output.GetFieldData().GetArray(name)
    return array.GetTuple1(0) if array else None


def arrays_of(output):
    """Every point array's numbers, as text (NaN equals NaN)."""
    pd = output.GetPointData()
    return {pd.GetArrayName(k): [repr(pd.GetArray(k).GetTuple(i))
                                 for i in range(pd.GetArray(k).GetNumberOfTuples())]
            for k in range(pd.GetNumberOfArrays())}


@pytest.mark.parametrize("estimator", [CACHE, SPHERES])
def test_cache_answers_agree_with_the_exact_solution(estimator):
    boundary = sphere_boundary(harmonic, resolution=48)
    probe = plane(0.1)
    solver = cache_solver(boundary, probe, estimator)
    solver.Update()
    out = solver.GetOutput()
    pd = out.GetPointData()
    from_cache = pd.GetArray("FromBoundaryCache")
    assert from_cache is not None
    walks = pd.GetArray("WalkCount")
    answered = shell = outside = 0
    for i in range(out.GetNumberOfPoints()):
        x = out.GetPoint(i)
        value, variance = pd.GetArray("T").GetTuple1(i), pd.GetArray("T_Variance").GetTuple1(i)
        if math.sqrt(sum(c * c for c in x)) > 1.0:
            outside += 1
            assert math.isnan(value)
            continue
        assert abs(value - harmonic(*x)) < 5.0 * math.sqrt(variance), (i, x)
        gradient = pd.GetArray("T_Gradient").GetTuple3(i)
        gradient_variance = pd.GetArray("T_Gradient_Variance").GetTuple3(i)
        for a in range(3):
            error = gradient[a] - harmonic_gradient(*x)[a]
            assert abs(error) < 5.0 * math.sqrt(gradient_variance[a]), (i, x, a)
        if from_cache.GetValue(i):
            answered += 1
            assert walks.GetValue(i) == 0
        else:
            shell += 1
            assert walks.GetValue(i) == 64
    assert answered > 30 and outside > 0
    # (The boundary cache leaves a shell of points to walks; the sphere cache
    # may answer those too where a lattice node lies close by.)
    assert shell > 0 or estimator == SPHERES
    assert field(out, "PointsFromCache") == answered
    assert field(out, "PointsWalkedInShell") == shell
    assert field(out, "OutsidePoints") == outside
    if estimator == CACHE:
        assert field(out, "CachePoints") == 1024
        assert field(out, "CacheWalksRun") == 1024 * 32
    else:
        spheres = field(out, "CacheSpheres")
        assert 0 < spheres <= answered
        assert field(out, "CacheWalksRun") == spheres * 128 == field(out, "CacheWalks")


def test_the_sphere_cache_answers_the_screened_equation():
    """Δu − 4u = 0 with u = cosh 2x + sinh(2y)/2: the screened ball's kernels
    (series off the centre) give values and gradients within their error
    bars, mean z² near 1; the cache is kept for a moved probe, and a new
    screening coefficient makes a new one."""
    def exact(x, y, z):
        return math.cosh(2.0 * x) + 0.5 * math.sinh(2.0 * y)

    def exact_gradient(x, y, z):
        return (2.0 * math.sinh(2.0 * x), math.cosh(2.0 * y), 0.0)

    boundary = sphere_boundary(exact, resolution=64)
    probe = plane(0.1)
    # (Data of one order of magnitude: screened walks' values W·g have a
    # heavy right tail where small data meet large data far away. With
    # e^{2x} (0.14 to 7.4), the point at x = −0.8 had a mean z² of 2.9
    # over 100 caches of 128 walks per sphere and 1.6 with 512, as
    # pointwise walks would.)
    solver = cache_solver(boundary, probe, SPHERES, WalksPerPoint=256, WalksPerSphere=256)
    solver.SetEquation(gridfree.vtkWalkOnSpheresSolver.SCREENED_POISSON)
    solver.SetScreeningCoefficient(4.0)
    solver.Update()
    out = solver.GetOutput()
    pd = out.GetPointData()
    squares = []
    for i in range(out.GetNumberOfPoints()):
        x = out.GetPoint(i)
        if math.sqrt(sum(c * c for c in x)) > 1.0 or not pd.GetArray("FromBoundaryCache").GetValue(i):
            continue
        z = (pd.GetArray("T").GetTuple1(i) - exact(*x)) / math.sqrt(pd.GetArray("T_Variance").GetTuple1(i))
        gradient = pd.GetArray("T_Gradient").GetTuple3(i)
        variance = pd.GetArray("T_Gradient_Variance").GetTuple3(i)
        zs = [z] + [(gradient[a] - exact_gradient(*x)[a]) / math.sqrt(variance[a]) for a in range(3)]
        assert all(abs(v) < 5.0 for v in zs), (i, x, zs)
        squares += [v * v for v in zs]
    assert len(squares) > 4 * 30
    assert 0.6 < sum(squares) / len(squares) < 1.5, sum(squares) / len(squares)
    assert field(out, "CacheWalksRun") > 0
    move(probe, 0.12)
    solver.Update()
    assert field(solver.GetOutput(), "CacheWalksRun") < field(out, "CacheWalks")
    solver.SetScreeningCoefficient(5.0)
    solver.Update()
    assert field(solver.GetOutput(), "CacheWalksRun") == field(solver.GetOutput(), "CacheWalks")


def test_the_sphere_cache_gives_hessians_and_directional_derivatives():
    """ComputeHessian and ComputeDirectionalDerivative with the Sphere Cache:
    T_Hessian from the spheres' kernels (∇ₓ²P) within their error bars of
    diag(2, −2, 0), and the derivative along (0.6, −0.8, 0.3), mean z² near
    1; points in the shell take theirs from their walks."""
    boundary = sphere_boundary(harmonic, resolution=48)
    solver = cache_solver(boundary, plane(0.1), SPHERES, ComputeHessian=True,
                          ComputeDirectionalDerivative=True, WalksPerSphere=512, WalksPerPoint=512)
    solver.SetDerivativeDirection(0.6, -0.8, 0.3)
    solver.Update()
    out = solver.GetOutput()
    pd = out.GetPointData()
    hessian, variance = pd.GetArray("T_Hessian"), pd.GetArray("T_Hessian_Variance")
    exact = (2.0, 0.0, 0.0, 0.0, -2.0, 0.0, 0.0, 0.0, 0.0)
    squares = []
    answered = 0
    for i in range(out.GetNumberOfPoints()):
        if math.sqrt(sum(c * c for c in out.GetPoint(i))) > 1.0:
            continue
        answered += pd.GetArray("FromBoundaryCache").GetValue(i)
        x = out.GetPoint(i)
        along = 0.6 * 2.0 * x[0] - 0.8 * -2.0 * x[1] + 0.3 * 0.3
        z = ((pd.GetArray("T_DirectionalDerivative").GetTuple1(i) - along)
             / math.sqrt(pd.GetArray("T_DirectionalDerivative_Variance").GetTuple1(i)))
        assert abs(z) < 5.0, (i, z)
        squares.append(z * z)
        h, v = hessian.GetTuple9(i), variance.GetTuple9(i)
        for k in range(9):
            if v[k] > 0.0:
                z = (h[k] - exact[k]) / math.sqrt(v[k])
                assert abs(z) < 5.0, (i, k, z)
                squares.append(z * z)
    assert answered > 30 and len(squares) > 9 * 30
    assert 0.6 < sum(squares) / len(squares) < 1.5, sum(squares) / len(squares)


def test_the_sphere_cache_gives_divergence_and_curl_of_a_vector_solution():
    """A 3-component boundary array (u = (x² − y², xy, xz + y), harmonic) with
    Compute Gradient and the Sphere Cache: T_Divergence = 4x and T_Curl =
    (1, −z, 3y) from the spheres' samples, within their error bars."""
    from gridfree_testing import add_point_array

    boundary = sphere_boundary(harmonic, resolution=48)
    add_point_array(boundary, "V", lambda x, y, z: (x * x - y * y, x * y, x * z + y), 3)
    solver = cache_solver(boundary, plane(0.1), SPHERES, WalksPerSphere=256)
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "V")
    solver.Update()
    out = solver.GetOutput()
    pd = out.GetPointData()
    divergence, curl = pd.GetArray("V_Divergence"), pd.GetArray("V_Curl")
    assert divergence is not None and curl is not None
    squares = []
    for i in range(out.GetNumberOfPoints()):
        x, y, z = out.GetPoint(i)
        if math.sqrt(x * x + y * y + z * z) > 1.0:
            continue
        exact = [4.0 * x, 1.0, -z, 3.0 * y]
        values = [divergence.GetTuple1(i)] + list(curl.GetTuple3(i))
        variances = ([pd.GetArray("V_Divergence_Variance").GetTuple1(i)]
                     + list(pd.GetArray("V_Curl_Variance").GetTuple3(i)))
        for value, variance, want in zip(values, variances, exact):
            if variance > 0.0:
                z_score = (value - want) / math.sqrt(variance)
                assert abs(z_score) < 5.0, (i, z_score)
                squares.append(z_score * z_score)
    assert len(squares) > 4 * 30
    assert 0.6 < sum(squares) / len(squares) < 1.5, sum(squares) / len(squares)


def test_a_moved_probe_reuses_the_cache_with_the_numbers_of_a_fresh_solve():
    boundary = sphere_boundary(harmonic, resolution=48)
    probe = plane(0.0, resolution=5)
    solver = cache_solver(boundary, probe)
    solver.Update()
    assert field(solver.GetOutput(), "CacheWalksRun") == 1024 * 32
    move(probe, 0.25)
    solver.Update()
    assert field(solver.GetOutput(), "CacheWalksRun") == 0
    assert field(solver.GetOutput(), "PointsFromCache") > 0
    fresh = cache_solver(boundary, plane(0.25, resolution=5))
    fresh.Update()
    assert arrays_of(solver.GetOutput()) == arrays_of(fresh.GetOutput())
    # A probe given as data (not a connection) reuses it as well.
    solver.SetProbeData(point_cloud([(0.1, 0.2, 0.3), (-0.2, 0.1, 0.0)]))
    solver.Update()
    assert field(solver.GetOutput(), "CacheWalksRun") == 0
    assert field(solver.GetOutput(), "PointsFromCache") == 2
    # More walks per cache point run only the missing ones; a new seed or
    # new boundary values build a new cache.
    solver.SetWalksPerCachePoint(48)
    solver.Update()
    assert field(solver.GetOutput(), "CacheWalksRun") == 1024 * 16
    solver.SetSeed(3)
    solver.Update()
    assert field(solver.GetOutput(), "CacheWalksRun") == 1024 * 48
    solver.SetBoundaryData(sphere_boundary(lambda x, y, z: harmonic(x, y, z) + 1.0,
                                           resolution=48))
    solver.Update()
    assert field(solver.GetOutput(), "CacheWalksRun") == 1024 * 48


def test_a_target_grows_the_cache():
    boundary = sphere_boundary(harmonic, resolution=48)
    probe = plane(0.0, resolution=4)
    solver = cache_solver(boundary, probe, ComputeGradient=False, WalksPerCachePoint=8,
                          WalksPerPoint=256)
    solver.Update()
    variance = solver.GetOutput().GetPointData().GetArray("T_Variance")
    from_cache = solver.GetOutput().GetPointData().GetArray("FromBoundaryCache")
    largest = max(variance.GetValue(i) for i in range(variance.GetNumberOfTuples())
                  if from_cache.GetValue(i))
    target = 0.5 * math.sqrt(largest)
    solver.SetTargetStandardError(target)
    solver.Update()
    out = solver.GetOutput()
    assert field(out, "WalksPerCachePoint") > 8
    assert field(out, "PointsShortOfTarget") == 0
    variance = out.GetPointData().GetArray("T_Variance")
    from_cache = out.GetPointData().GetArray("FromBoundaryCache")
    for i in range(out.GetNumberOfPoints()):
        if from_cache.GetValue(i):
            assert variance.GetValue(i) <= target * target


def test_a_moved_probe_reuses_the_spheres_it_meets_again():
    boundary = sphere_boundary(harmonic, resolution=48)
    probe = plane(0.0, resolution=5)
    solver = cache_solver(boundary, probe, SPHERES, WalksPerSphere=64)
    solver.Update()
    first = field(solver.GetOutput(), "CacheWalksRun")
    assert first > 0
    solver.Modified()
    solver.Update()
    assert field(solver.GetOutput(), "CacheWalksRun") == 0
    # A slightly moved slice meets the big spheres again: fewer walks.
    move(probe, 0.05)
    solver.Update()
    assert field(solver.GetOutput(), "CacheWalksRun") < first
    fresh = cache_solver(boundary, plane(0.05, resolution=5), SPHERES, WalksPerSphere=64)
    fresh.Update()
    assert arrays_of(solver.GetOutput()) == arrays_of(fresh.GetOutput())
    # Other walks per sphere or another seed: a new cache.
    solver.SetWalksPerSphere(32)
    solver.Update()
    assert field(solver.GetOutput(), "CacheWalks") == field(solver.GetOutput(), "CacheSpheres") * 32


def test_more_walks_per_sphere_top_the_spheres_up_and_refine_and_a_time_budget_grow_them():
    boundary = sphere_boundary(harmonic, resolution=48)
    probe = plane(0.0, resolution=5)
    solver = cache_solver(boundary, probe, SPHERES, WalksPerSphere=32)
    solver.Update()
    spheres = field(solver.GetOutput(), "CacheSpheres")
    solver.SetWalksPerSphere(64)
    solver.Update()
    # The same spheres, each continued by 32 walks: the numbers of a fresh
    # cache of 64 walks per sphere.
    assert field(solver.GetOutput(), "CacheSpheres") == spheres
    assert field(solver.GetOutput(), "CacheWalksRun") == spheres * 32
    fresh = cache_solver(boundary, plane(0.0, resolution=5), SPHERES, WalksPerSphere=64)
    fresh.Update()
    assert arrays_of(solver.GetOutput()) == arrays_of(fresh.GetOutput())
    # Refine doubles the spheres' walks with the points': the numbers of a
    # fresh cache with both doubled.
    solver.Refine()
    solver.Update()
    assert solver.GetWalksPerSphere() == 128 and solver.GetWalksPerPoint() == 128
    assert field(solver.GetOutput(), "CacheWalksRun") == spheres * 64
    doubled = cache_solver(boundary, plane(0.0, resolution=5), SPHERES, WalksPerSphere=128,
                           WalksPerPoint=128)
    doubled.Update()
    assert arrays_of(solver.GetOutput()) == arrays_of(doubled.GetOutput())
    # A time budget's rounds give the spheres at least a point's walks (the
    # first round 128).
    fresh.SetTimeBudgetSeconds(0.5)
    fresh.SetWalksPerPoint(4096)
    fresh.Update()
    assert field(fresh.GetOutput(), "CacheWalks") >= field(fresh.GetOutput(), "CacheSpheres") * 128


@pytest.mark.parametrize("estimator", [CACHE, SPHERES])
def test_an_abort_while_the_cache_walks_leaves_nan_and_resume_continues(estimator):
    """Aborted at the first progress report, while the cache's walks run:
    the output still has its arrays (every point NaN) and says why; Resume
    then continues to the numbers of an uninterrupted solve."""
    boundary = sphere_boundary(harmonic, resolution=48)
    # Enough walks that the cache's batch reports progress (ten times a
    # second) before it ends.
    walks = {"WalksPerCachePoint": 256} if estimator == CACHE else {"WalksPerSphere": 2048}
    solver = cache_solver(boundary, plane(0.0, resolution=4), estimator, **walks)
    catcher = MessageCatcher(solver)
    update_aborted_at_first_progress(solver)
    assert solver.GetLastSolveAborted()
    values = solver.GetOutput().GetPointData().GetArray("T")
    assert values is not None and solver.GetOutput().GetPointData().GetArray("T_Gradient")
    assert all(math.isnan(values.GetValue(i)) for i in range(values.GetNumberOfTuples()))
    assert "aborted while the cache" in catcher.warning_text()
    solver.SetAbortExecute(0)
    solver.Resume()
    solver.Update()
    assert not solver.GetLastSolveAborted()
    fresh = cache_solver(boundary, plane(0.0, resolution=4), estimator, **walks)
    fresh.Update()
    assert arrays_of(solver.GetOutput()) == arrays_of(fresh.GetOutput())


def test_what_the_cache_cannot_answer_is_refused_in_words():
    boundary = sphere_boundary(harmonic, resolution=16)
    solver = cache_solver(boundary, plane(0.0, resolution=2), ComputeHessian=True)
    catcher = MessageCatcher(solver)
    solver.Update()
    assert "Estimator Boundary Cache" in catcher.error_text()
    assert "not the Hessian or a directional derivative" in catcher.error_text()
    solver = cache_solver(boundary, plane(0.0, resolution=2))
    solver.SetEquation(gridfree.vtkWalkOnSpheresSolver.BIHARMONIC)
    solver.SetInputArrayToProcess(1, 0, 0, POINTS, "T")
    catcher = MessageCatcher(solver)
    solver.Update()
    assert "Estimator Boundary Cache" in catcher.error_text()
    assert "Pointwise Walks" in catcher.error_text()


def test_the_stream_tracer_follows_the_cache_and_keeps_it():
    """u = x² − y²: the lines are the hyperbolas x·y = const; moved seeds are
    traced from the same cache (its walks are not run again)."""
    from test_stream_tracer import check_hyperbolas, tracer_for
    seeds = [(0.1, 0.4, 0.0), (0.2, -0.3, 0.1)]
    tracer = tracer_for(seeds, Estimator=CACHE, CachePoints=2048, WalksPerCachePoint=64,
                        CacheShellDistance=0.05)
    tracer.SetBoundaryData(sphere_boundary(resolution=48))
    tracer.Update()
    check_hyperbolas(tracer.GetOutput(), seeds, 0.03)
    first = field(tracer.GetOutput(), "TotalWalks")
    assert first >= 2048 * 64
    moved = [(0.15, 0.35, 0.05), (0.25, -0.25, 0.0)]
    tracer.SetSeedsData(point_cloud(moved))
    tracer.Update()
    check_hyperbolas(tracer.GetOutput(), moved, 0.03)
    # Only walks of points in the shell (2048 each, the tracer's walks per
    # point), none of the cache's.
    second = field(tracer.GetOutput(), "TotalWalks")
    assert second % 2048 == 0 and second < 2048 * 64
