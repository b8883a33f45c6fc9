"""Cross fields (paper Sec. 6.5): psi = nu^4 extended harmonically. On a
square the field is the constant, axis-aligned cross; on a disk psi = z^4
and the singularities' indices (quarter turns) sum to 4 x Euler
characteristic; on regular polygons the single singularity at the centre has
the index the corners imply, with its separatrices running to the edges'
midpoints. The Sphere Cache on a domain with a hole whose loops run the same
way agrees with pointwise walks and answers a moved probe with no walks.
Also thread independence and errors."""
import cmath
import math
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import gridfree  # noqa: E402
from vtkmodules.vtkFiltersCore import vtkAppendPolyData  # noqa: E402
from vtkmodules.vtkFiltersSources import vtkSphereSource  # noqa: E402

from gridfree_testing import MessageCatcher, closed_polyline, point_cloud  # noqa: E402


def regular_closed_polyline(sides, phase=0.0):
    return closed_polyline([(math.cos(2 * math.pi * k / sides + phase),
                     math.sin(2 * math.pi * k / sides + phase)) for k in range(sides)])


def cross_field(boundary, probe_points, **settings):
    filter_ = gridfree.vtkWalkOnSpheresCrossField()
    filter_.SetBoundaryData(boundary)
    filter_.SetProbeData(point_cloud(probe_points))
    for name, value in settings.items():
        getattr(filter_, "Set" + name)(value)
    catcher = MessageCatcher(filter_)
    filter_.Update()
    assert not catcher.errors, catcher.error_text()
    return filter_


def singularities(filter_):
    data = filter_.GetOutput(1)
    index = data.GetPointData().GetArray("Index")
    residual = data.GetPointData().GetArray("IndexResidual")
    return [(data.GetPoint(i), index.GetValue(i), residual.GetValue(i))
            for i in range(data.GetNumberOfPoints())]


def separatrix_ends(filter_):
    lines = filter_.GetOutput(2)
    reasons = lines.GetCellData().GetArray("StopReason")
    ends = []
    for c in range(lines.GetNumberOfCells()):
        cell = lines.GetCell(c)
        ends.append((cell.GetPoints().GetPoint(cell.GetNumberOfPoints() - 1), reasons.GetValue(c)))
    return ends


def test_square_is_the_axis_aligned_cross():
    points = [(0.3, 0.2, 0.0), (-0.7, 0.5, 0.0), (0.9, -0.9, 0.0)]
    filter_ = cross_field(closed_polyline([(-1, -1), (1, -1), (1, 1), (-1, 1)]), points,
                          WalksPerPoint=64, NumberOfSeeds=8)
    data = filter_.GetOutput().GetPointData()
    psi = data.GetArray("CrossField")
    expected = [(1, 0, 0), (0, 1, 0), (-1, 0, 0), (0, -1, 0)]
    for i in range(len(points)):
        # Every normal of a square has nu^4 = 1: every walk returns 1.
        assert psi.GetTuple2(i) == (1.0, 0.0)
        assert data.GetArray("CrossField_Variance").GetTuple2(i) == (0.0, 0.0)
        for k in range(4):
            direction = data.GetArray("CrossDirection%d" % (k + 1)).GetTuple3(i)
            assert max(abs(a - b) for a, b in zip(direction, expected[k])) < 1e-12
    # |psi| = 1 everywhere: no singularity, no separatrix.
    assert filter_.GetOutput(1).GetNumberOfPoints() == 0
    assert filter_.GetOutput(2).GetNumberOfCells() == 0


def test_disk_is_z4_and_indices_sum_to_four():
    points = [(0.5, 0.3, 0.0), (-0.2, -0.6, 0.0), (0.7, -0.1, 0.0)]
    # psi = z^4 vanishes to fourth order at the centre: a flat zero, so the
    # search needs many walks, a wide merge radius and a wide index circle.
    filter_ = cross_field(regular_closed_polyline(1024), points, WalksPerPoint=4096,
                          SearchMethod=1, SearchWalksPerPoint=65536, NumberOfSeeds=6,
                          MergeRadius=0.2, IndexRadius=0.2, Seed=2)
    data = filter_.GetOutput().GetPointData()
    psi = data.GetArray("CrossField")
    variance = data.GetArray("CrossField_Variance")
    for i, (x, y, _) in enumerate(points):
        exact = complex(x, y) ** 4
        for c, value in enumerate((exact.real, exact.imag)):
            assert abs(psi.GetComponent(i, c) - value) < 5 * math.sqrt(variance.GetComponent(i, c))
    found = singularities(filter_)
    # Euler characteristic 1: the indices sum to 4 quarter turns.
    assert sum(index for _, index, _ in found) == 4, found
    assert len(found) == 1 and math.hypot(*found[0][0][:2]) < 0.2, found


def check_polygon_singularity(sides, expected_index):
    """A regular polygon's single singularity sits at its centre; its
    separatrices are the |4 - n| radii through the edges' midpoints."""
    filter_ = cross_field(regular_closed_polyline(sides, phase=math.pi / 2), [(0.1, 0.1, 0.0)],
                          WalksPerPoint=64, SearchWalksPerPoint=1024, Seed=1)
    found = singularities(filter_)
    assert len(found) == 1, found
    (x, y, _), index, residual = found[0]
    assert index == expected_index and abs(residual) < 0.25, found
    assert math.hypot(x, y) < 0.03, found
    ends = separatrix_ends(filter_)
    assert len(ends) == abs(4 - expected_index), ends
    apothem = math.cos(math.pi / sides)
    midpoints = [cmath.rect(apothem, math.pi / 2 + math.pi / sides + 2 * math.pi * k / sides)
                 for k in range(sides)]
    for (ex, ey, _), reason in ends:
        assert reason == 0, ends  # stopped at the boundary
        assert min(abs(complex(ex, ey) - m) for m in midpoints) < 0.05, ends
    return filter_


def test_triangle_has_one_three_armed_singularity():
    # Corners of 60 degrees: nu^4 turns by +120 degrees at each; winding 1.
    check_polygon_singularity(3, 1)


def test_pentagon_has_one_five_armed_singularity():
    # Corners of 108 degrees: nu^4 turns by -72 degrees at each; winding -1.
    filter_ = check_polygon_singularity(5, -1)
    field_data = filter_.GetOutput().GetFieldData()
    assert field_data.GetArray("SearchEstimates").GetValue(0) == filter_.GetLastNumberOfEstimates()
    assert field_data.GetArray("TotalWalks").GetValue(0) == filter_.GetLastNumberOfWalks()


def test_same_result_for_any_thread_count():
    results = []
    for threads in (1, 2):
        filter_ = cross_field(regular_closed_polyline(3, phase=math.pi / 2), [(0.2, 0.1, 0.0)],
                              WalksPerPoint=64, SearchWalksPerPoint=256, NumberOfSeeds=8,
                              NumberOfThreads=threads, TraceSeparatrices=False)
        results.append((filter_.GetOutput().GetPointData().GetArray("CrossField").GetTuple2(0),
                        singularities(filter_)))
    assert results[0] == results[1]


def test_errors():
    sphere = vtkSphereSource()
    sphere.Update()
    filter_ = gridfree.vtkWalkOnSpheresCrossField()
    filter_.SetBoundaryData(sphere.GetOutput())
    filter_.SetProbeData(point_cloud([(0.0, 0.0, 0.0)]))
    catcher = MessageCatcher(filter_)
    filter_.Update()
    assert "2D domain" in catcher.error_text(), catcher.error_text()
    tilted = closed_polyline([(0, 0), (1, 0), (1, 1)])
    tilted.GetPoints().SetPoint(2, 1.0, 1.0, 0.5)
    filter_.SetBoundaryData(tilted)
    catcher = MessageCatcher(filter_)
    filter_.Update()
    assert "one z-plane" in catcher.error_text(), catcher.error_text()
    filter_.SetBoundaryData(closed_polyline([(-1, -1), (1, -1), (1, 1), (-1, 1)]))
    filter_.SetEstimator(filter_.BOUNDARY_CACHE)
    catcher = MessageCatcher(filter_)
    filter_.Update()
    assert "not the Boundary Cache" in catcher.error_text(), catcher.error_text()
    # The Sphere Cache needs closed loops to tell inside from outside.
    open_line = closed_polyline([(-1, -1), (1, -1), (1, 1), (-1, 1)])
    open_line.GetLines().Initialize()
    open_line.GetLines().InsertNextCell(4, [0, 1, 2, 3])
    filter_.SetBoundaryData(open_line)
    filter_.SetEstimator(filter_.SPHERE_CACHE)
    catcher = MessageCatcher(filter_)
    filter_.Update()
    assert "must form closed loops" in catcher.error_text(), catcher.error_text()


def test_sphere_cache_on_a_domain_with_a_hole():
    """A quadrilateral with a round hole, both loops running the same way
    (the cache turns them so that the domain is on their left): the cache's
    crosses agree with pointwise walks at every point (z of the difference),
    a point in the hole is outside (NaN), the singularities found from the
    cache add up to the boundary's indices, and a moved probe afterwards is
    answered with no walks."""
    outer = [(-2, -1.5), (2, -1.5), (2.4, 1.2), (-1.6, 1.5)]
    inner = [(0.2 + 0.5 * math.cos(2 * math.pi * k / 24), 0.5 * math.sin(2 * math.pi * k / 24))
             for k in range(24)]
    both = vtkAppendPolyData()
    both.AddInputData(closed_polyline(outer))
    both.AddInputData(closed_polyline(inner))
    both.Update()
    points = []
    for i in range(200):
        x = -1.8 + 4.0 * ((i * 0.7548776662) % 1)
        y = -1.3 + 2.6 * ((i * 0.5698402910) % 1)
        if (x - 0.2) ** 2 + y ** 2 > 0.6 ** 2 and len(points) < 40:
            points.append((x, y, 0.0))
    hole = (0.25, 0.1, 0.0)
    pointwise = cross_field(both.GetOutput(), points, WalksPerPoint=4096, SearchSingularities=0,
                            Seed=7)
    cached = cross_field(both.GetOutput(), points + [hole], WalksPerPoint=512, WalksPerSphere=512,
                         Estimator=gridfree.vtkWalkOnSpheresCrossField.SPHERE_CACHE, Seed=7)
    a = pointwise.GetOutput().GetPointData()
    b = cached.GetOutput().GetPointData()
    scores = []
    for k in range(len(points)):
        for c in range(2):
            difference = (a.GetArray("CrossField").GetComponent(k, c) -
                          b.GetArray("CrossField").GetComponent(k, c))
            spread = math.sqrt(a.GetArray("CrossField_Variance").GetComponent(k, c) +
                               b.GetArray("CrossField_Variance").GetComponent(k, c))
            scores.append(difference / spread)
            assert abs(scores[-1]) < 5, (k, c, scores[-1])
    mean_z2 = sum(z * z for z in scores) / len(scores)
    assert 0.5 < mean_z2 < 1.6, mean_z2
    assert all(math.isnan(v) for v in b.GetArray("CrossField").GetTuple2(len(points)))
    fields = cached.GetOutput().GetFieldData()
    assert fields.GetArray("OutsidePoints").GetValue(0) == 1
    assert fields.GetArray("PointsFromCache").GetValue(0) == len(points)
    search = cached.GetOutput(1).GetFieldData()
    assert search.GetArray("IndexSum").GetValue(0) == search.GetArray("BoundaryIndexSum").GetValue(0)
    cached.SetProbeData(point_cloud([(x + 0.05, y - 0.03, 0.0) for x, y, _ in points]))
    cached.SetSearchSingularities(0)
    cached.Update()
    moved = cached.GetOutput().GetFieldData()
    assert moved.GetArray("CacheWalksRun").GetValue(0) == 0
    assert moved.GetArray("TotalWalks").GetValue(0) == 0


# Held-out polygons (Poincare-Hopf: the indices inside add up to the sum over
# the corners of 4 x turn, wrapped into (-180, 180] degrees, over 360).
HELD_OUT = {
    "regular hexagon": ([(math.cos(k * math.pi / 3), math.sin(k * math.pi / 3)) for k in range(6)], -2),
    "irregular hexagon": ([(0, 0), (1.0, -0.15), (1.55, 0.5), (1.2, 1.25), (0.35, 1.4), (-0.3, 0.7)], -2),
    "irregular pentagon": ([(0, 0), (1.2, 0.1), (1.4, 1.0), (0.6, 1.5), (-0.2, 0.9)], -1),
    "irregular triangle": ([(0, 0), (1.3, 0.1), (0.4, 1.0)], 1),
    "arrow (non-convex)": ([(0, 0), (2, 0), (2, -0.5), (3.2, 0.6), (2, 1.7), (2, 1.2), (0, 1.2)], 1),
}


def test_winding_search_matches_the_boundary_at_default_settings():
    for name, (vertices, expected) in HELD_OUT.items():
        filter_ = gridfree.vtkWalkOnSpheresCrossField()
        filter_.SetBoundaryData(closed_polyline(vertices))
        centroid = (sum(x for x, _ in vertices) / len(vertices),
                    sum(y for _, y in vertices) / len(vertices), 0.0)
        filter_.SetProbeData(point_cloud([centroid]))
        filter_.SetTraceSeparatrices(False)
        catcher = MessageCatcher(filter_)
        filter_.Update()
        assert not catcher.errors and not catcher.warnings, (name, catcher.warning_text())
        field_data = filter_.GetOutput(1).GetFieldData()
        found = [index for _, index, _ in singularities(filter_)]
        assert 0 not in found, name
        assert sum(found) == expected, (name, found)
        assert field_data.GetArray("IndexSum").GetValue(0) == expected, name
        assert field_data.GetArray("BoundaryIndexSum").GetValue(0) == expected, name


def test_seed_descent_misses_the_regular_hexagon_and_says_so():
    # psi ~ r^2 around the hexagon's centre: too flat for the seeds at 1024
    # walks. The check against the boundary catches it.
    vertices, expected = HELD_OUT["regular hexagon"]
    filter_ = gridfree.vtkWalkOnSpheresCrossField()
    filter_.SetBoundaryData(closed_polyline(vertices))
    filter_.SetProbeData(point_cloud([(0.1, 0.1, 0.0)]))
    filter_.SetTraceSeparatrices(False)
    filter_.SetSearchMethodToSeedDescent()
    catcher = MessageCatcher(filter_)
    filter_.Update()
    found = sum(index for _, index, _ in singularities(filter_))
    assert found != expected
    assert ("indices summing to %d quarter turns, but the boundary requires %d" % (found, expected)
            in catcher.warning_text())
    bad = gridfree.vtkWalkOnSpheresCrossField()
    errors = MessageCatcher(bad)
    bad.SetSearchMethod(5)
    assert "SearchMethod 5 is not a choice" in errors.error_text()
    assert bad.GetSearchMethod() == 0
