"""Biharmonic shape deformation (paper Sec. 6.7): a similarity between the
source and target curves is reproduced inside (within 5 standard errors at
every point, reported variances calibrated), the second-order condition
changes a bending map, the warped copy keeps the probe's structure (an image
becomes a structured grid of the same dimensions), and bad input gives clear
errors."""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import gridfree  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkImageData  # noqa: E402
from vtkmodules.vtkFiltersSources import vtkPlaneSource  # noqa: E402

from gridfree_testing import MessageCatcher, closed_polyline, point_cloud  # noqa: E402

ANGLE, SCALE, SHIFT = math.radians(30.0), 1.3, (0.5, -0.2)


def similarity(x, y):
    c, s = math.cos(ANGLE), math.sin(ANGLE)
    return (SCALE * (c * x - s * y) + SHIFT[0], SCALE * (s * x + c * y) + SHIFT[1])


def circle(sides=256):
    return [(math.cos(2 * math.pi * k / sides), math.sin(2 * math.pi * k / sides))
            for k in range(sides)]


def deform(source, target, probe, walks=1024, **settings):
    deformation = gridfree.vtkWalkOnSpheresDeformation()
    deformation.SetSourceData(closed_polyline(source))
    deformation.SetTargetData(closed_polyline(target))
    deformation.SetProbeData(probe)
    deformation.SetWalksPerPoint(walks)
    for name, value in settings.items():
        getattr(deformation, "Set" + name)(value)
    catcher = MessageCatcher(deformation)
    deformation.Update()
    assert not catcher.errors, catcher.error_text()
    return deformation.GetOutput()


def test_similarity_is_reproduced():
    source = circle()
    points = [(0.8 * math.sqrt((i + 0.5) / 30) * math.cos(2.39996 * i),
               0.8 * math.sqrt((i + 0.5) / 30) * math.sin(2.39996 * i), 0.0) for i in range(30)]
    output = deform(source, [similarity(x, y) for x, y in source], point_cloud(points), walks=2048)
    variance = output.GetPointData().GetArray("Deformation_Variance")
    displacement = output.GetPointData().GetArray("Displacement")
    scores = []
    for i, (x, y, _) in enumerate(points):
        moved = output.GetPoint(i)
        exact = similarity(x, y)
        for c in range(2):
            sigma = math.sqrt(variance.GetComponent(i, c))
            assert abs(moved[c] - exact[c]) < 5 * sigma, (i, c, moved, exact, sigma)
            scores.append((moved[c] - exact[c]) / sigma)
            assert abs(displacement.GetComponent(i, c) - (moved[c] - (x, y)[c])) < 1e-12
        # The estimate resolves the map: the standard error is small
        # against the displacement.
        assert max(math.sqrt(variance.GetComponent(i, c)) for c in range(2)) < 0.05
    mean_z2 = sum(z * z for z in scores) / len(scores)
    assert 0.5 < mean_z2 < 1.6, mean_z2
    assert output.GetFieldData().GetArray("TotalWalks").GetValue(0) == 30 * 2048


def sheared(x, y):
    """A bending of an ellipse (y + x^2/4): not a similarity, so h is not 0."""
    return (x, y + 0.25 * x * x)


def test_second_order_condition_changes_a_bending():
    source = [(1.5 * math.cos(2 * math.pi * k / 256), math.sin(2 * math.pi * k / 256))
              for k in range(256)]
    target = [sheared(x, y) for x, y in source]
    probe = point_cloud([(0.0, 0.0, 0.0)])
    changes = []
    for seed in (1, 2):
        with_h = deform(source, target, probe, walks=4096, Seed=seed)
        without_h = deform(source, target, probe, walks=4096, Seed=seed, AsLinearAsPossible=False)
        changes.append(with_h.GetPoint(0)[1] - without_h.GetPoint(0)[1])
    # The same walks with h = 0 would give the very same numbers: h moves
    # the centre down by about 0.05, by the same amount for both seeds.
    assert all(-0.08 < c < -0.03 for c in changes), changes
    assert abs(changes[0] - changes[1]) < 0.3 * abs(changes[0]), changes


def test_warped_copies_keep_the_structure():
    source = [(-1, -1), (1, -1), (1, 1), (-1, 1)]
    target = [similarity(x, y) for x, y in source]
    image = vtkImageData()
    image.SetDimensions(5, 4, 1)
    image.SetOrigin(-0.8, -0.6, 0.0)
    image.SetSpacing(0.4, 0.4, 1.0)
    warped = deform(source, target, image, walks=16)
    assert warped.GetClassName() == "vtkStructuredGrid"
    dimensions = [0, 0, 0]
    warped.GetDimensions(dimensions)
    assert dimensions == [5, 4, 1]
    assert warped.GetNumberOfCells() == image.GetNumberOfCells()
    plane = vtkPlaneSource()
    plane.SetOrigin(-0.5, -0.5, 0.0)
    plane.SetPoint1(0.5, -0.5, 0.0)
    plane.SetPoint2(-0.5, 0.5, 0.0)
    plane.SetResolution(3, 3)
    plane.Update()
    warped = deform(source, target, plane.GetOutput(), walks=16)
    assert warped.GetClassName() == "vtkPolyData"
    assert warped.GetNumberOfPolys() == 9
    assert warped.GetPointData().GetArray("SourcePosition").GetTuple3(0) == (-0.5, -0.5, 0.0)


def test_points_outside_the_source_curves_are_not_moved_and_say_so():
    # The map is defined inside the curves only: outside, walks leave the
    # domain, and a finite value there would be a confident wrong answer.
    source = circle(64)
    deformation = gridfree.vtkWalkOnSpheresDeformation()
    deformation.SetSourceData(closed_polyline(source))
    deformation.SetTargetData(closed_polyline([similarity(x, y) for x, y in source]))
    deformation.SetProbeData(point_cloud([(0.2, 0.1, 0.0), (2.0, 0.0, 0.0), (0.0, -1.5, 0.0)]))
    deformation.SetWalksPerPoint(64)
    catcher = MessageCatcher(deformation)
    deformation.Update()
    out = deformation.GetOutput()
    inside = out.GetPointData().GetArray("InsideSource")
    assert [inside.GetValue(i) for i in range(3)] == [1, 0, 0]
    deformation_array = out.GetPointData().GetArray("Deformation")
    assert all(math.isnan(deformation_array.GetComponent(i, 0)) for i in (1, 2))
    assert not math.isnan(deformation_array.GetComponent(0, 0))
    assert out.GetPoint(1) == (2.0, 0.0, 0.0) and out.GetPoint(2) == (0.0, -1.5, 0.0)
    text = catcher.warning_text()
    assert "2 of 3 probe points lie outside the Source curves" in text, text
    assert "EscapedFraction" not in text
    assert deformation.GetLastNumberOfWalks() == 64  # only the inside point walked


def test_errors():
    deformation = gridfree.vtkWalkOnSpheresDeformation()
    deformation.SetSourceData(closed_polyline(circle(16)))
    deformation.SetTargetData(closed_polyline(circle(15)))
    deformation.SetProbeData(point_cloud([(0.0, 0.0, 0.0)]))
    catcher = MessageCatcher(deformation)
    deformation.Update()
    assert "as many points as the Source" in catcher.error_text(), catcher.error_text()
    deformation.RemoveAllInputConnections(2)
    catcher = MessageCatcher(deformation)
    deformation.Update()
    assert "none is connected" in catcher.error_text(), catcher.error_text()
