"""Diffusion curves and surfaces (paper Sec. 6.4): two-sided boundary colours
against closed forms (an open slit whose two sides differ, a sphere with
different values inside and outside), a source term, the image made without
a probe (a zoomed window or a piece of the extent gives the same pixels and
costs only its own walks), the RGB copy, thread independence, and clear
errors for bad input."""
import cmath
import math
import os
import random
import sys

sys.path.insert(0, os.path.dirname(__file__))

import gridfree  # noqa: E402
from vtkmodules.vtkCommonCore import vtkPoints  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkImageData, vtkPolyData  # noqa: E402

from gridfree_testing import (  # noqa: E402
    MessageCatcher, add_point_array, closed_polyline, point_cloud, sphere_boundary)


def slit(n=400):
    """The open segment from (-1, 0) to (1, 0), left to right: its front
    (left) side faces +y."""
    points = vtkPoints()
    for i in range(n + 1):
        points.InsertNextPoint(-1.0 + 2.0 * i / n, 0.0, 0.0)
    lines = vtkCellArray()
    lines.InsertNextCell(n + 1)
    for i in range(n + 1):
        lines.InsertCellPoint(i)
    curve = vtkPolyData()
    curve.SetPoints(points)
    curve.SetLines(lines)
    return curve


def slit_solution(x, y):
    """The bounded harmonic function outside the slit, 1 on its upper side and
    0 on its lower side: z = (ζ + 1/ζ)/2 maps |ζ| > 1 onto the slit plane,
    the upper side onto the upper half circle; with w = 1/ζ (the unit disk,
    upper side onto the lower half circle) it is 1 minus the harmonic measure
    of the upper half circle, 1/2 + arctan(2 Im w / (1 - |w|²)) / π."""
    z = complex(x, y)
    zeta = z + cmath.sqrt(z - 1) * cmath.sqrt(z + 1)
    w = 1 / zeta
    upper = 0.5 + math.atan2(2 * w.imag, 1 - abs(w) ** 2) / math.pi
    return 1.0 - upper


def run(boundary, probe=None, walks=256, front="FrontColor", back="BackColor", **settings):
    curves = gridfree.vtkWalkOnSpheresDiffusionCurves()
    curves.SetBoundaryData(boundary)
    if probe is not None:
        curves.SetProbeData(probe)
    curves.SetInputArrayToProcess(0, 0, 0, 0, front)
    curves.SetInputArrayToProcess(1, 0, 0, 0, back)
    curves.SetWalksPerPoint(walks)
    for name, value in settings.items():
        getattr(curves, "Set" + name)(*value if isinstance(value, tuple) else (value,))
    catcher = MessageCatcher(curves)
    curves.Update()
    return curves, catcher


def check_scores(output, exact, name="FrontColor", component=0, low=0.6, high=1.5):
    values = output.GetPointData().GetArray(name)
    variances = output.GetPointData().GetArray(name + "_Variance")
    scores = []
    for i in range(output.GetNumberOfPoints()):
        x, y, z = output.GetPoint(i)
        sigma = math.sqrt(variances.GetComponent(i, component))
        score = (values.GetComponent(i, component) - exact(x, y, z)) / sigma
        assert abs(score) < 5.0, (i, (x, y, z), values.GetComponent(i, component),
                                  exact(x, y, z), sigma)
        scores.append(score)
    mean_z2 = sum(s * s for s in scores) / len(scores)
    assert low < mean_z2 < high, mean_z2


def test_open_slit_takes_each_sides_colour():
    boundary = slit()
    add_point_array(boundary, "FrontColor", lambda x, y, z: 1.0)
    add_point_array(boundary, "BackColor", lambda x, y, z: 0.0)
    rng = random.Random(5)
    points = [(rng.uniform(-2, 2), rng.uniform(-1.5, 1.5), 0.0) for _ in range(200)]
    curves, catcher = run(boundary, point_cloud(points), walks=512)
    assert not catcher.errors, catcher.error_text()
    output = curves.GetOutput()
    check_scores(output, lambda x, y, z: slit_solution(x, y))
    # The colours are far from the mean of the sides next to the slit.
    values = output.GetPointData().GetArray("FrontColor")
    for i, (x, y, _) in enumerate(points):
        if abs(x) < 0.8 and 0.0 < abs(y) < 0.05:
            assert (values.GetValue(i) > 0.8) == (y > 0), (x, y, values.GetValue(i))


def test_sphere_inside_and_outside():
    # vtkSphereSource winds its triangles outward: the front is outside.
    boundary = sphere_boundary(lambda x, y, z: z, name="FrontColor", resolution=96)
    add_point_array(boundary, "BackColor", lambda x, y, z: 1.0 + x)
    rng = random.Random(6)
    inside, outside = [], []
    while len(inside) < 60 or len(outside) < 60:
        p = (rng.uniform(-2.5, 2.5), rng.uniform(-2.5, 2.5), rng.uniform(-2.5, 2.5))
        r = math.sqrt(sum(c * c for c in p))
        if r < 0.9 and len(inside) < 60:
            inside.append(p)
        elif 1.1 < r < 2.5 and len(outside) < 60:
            outside.append(p)
    # Interior: the back values' harmonic extension 1 + x; exterior: the
    # front values' decaying one, z / r³.
    curves, catcher = run(boundary, point_cloud(inside), walks=512)
    assert not catcher.errors, catcher.error_text()
    check_scores(curves.GetOutput(), lambda x, y, z: 1.0 + x, low=0.5, high=1.7)
    curves, catcher = run(boundary, point_cloud(outside), walks=512)
    assert not catcher.errors, catcher.error_text()
    check_scores(curves.GetOutput(), lambda x, y, z: z / (x * x + y * y + z * z) ** 1.5,
                 low=0.5, high=1.7)


def test_source_term_follows_the_solver_sign():
    # Δu = 4 inside the unit circle with u = 1 on it: u = x² + y².
    boundary = closed_polyline([(math.cos(2 * math.pi * k / 1024), math.sin(2 * math.pi * k / 1024))
                                for k in range(1024)])
    add_point_array(boundary, "FrontColor", lambda x, y, z: 1.0)
    add_point_array(boundary, "BackColor", lambda x, y, z: 1.0)
    rng = random.Random(7)
    points = []
    while len(points) < 100:
        p = (rng.uniform(-0.9, 0.9), rng.uniform(-0.9, 0.9), 0.0)
        if p[0] ** 2 + p[1] ** 2 < 0.81:
            points.append(p)
    curves, catcher = run(boundary, point_cloud(points), walks=512, SourceExpression="4")
    assert not catcher.errors, catcher.error_text()
    check_scores(curves.GetOutput(), lambda x, y, z: x * x + y * y)


def coloured_square():
    """An open square-ish curve with RGB colours: red/blue on one side,
    green on the other."""
    boundary = closed_polyline([(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)])
    add_point_array(boundary, "FrontColor", lambda x, y, z: (1.0, 0.2, 0.5 + x), components=3)
    add_point_array(boundary, "BackColor", lambda x, y, z: (0.0, 1.0, 0.5 - y), components=3)
    return boundary


def test_image_window_zoom_and_pieces_give_the_same_pixels():
    boundary = coloured_square()
    # 9 × 9 pixels over [-1, 1]²: spacing 0.25, exactly representable.
    full, catcher = run(boundary, walks=64, ImageWindow=(-1.0, 1.0, -1.0, 1.0),
                        ImageResolution=(9, 9))
    assert not catcher.errors, catcher.error_text()
    image = full.GetOutput()
    assert isinstance(image, vtkImageData)
    assert image.GetDimensions() == (9, 9, 1)
    assert image.GetSpacing()[:2] == (0.25, 0.25)
    assert full.GetLastNumberOfWalks() == 81 * 64
    colour = image.GetPointData().GetArray("FrontColor")
    assert colour.GetNumberOfComponents() == 3

    def pixel(img, x, y):
        i = img.FindPoint(x, y, 0.0)
        assert i >= 0
        assert img.GetPoint(i)[:2] == (x, y)
        return img.GetPointData().GetArray("FrontColor").GetTuple3(i)

    # A zoomed window on the same grid: the same numbers at the same points.
    zoom, catcher = run(boundary, walks=64, ImageWindow=(0.0, 0.5, -0.25, 0.25),
                        ImageResolution=(3, 3))
    assert not catcher.errors, catcher.error_text()
    assert zoom.GetLastNumberOfWalks() == 9 * 64
    for x in (0.0, 0.25, 0.5):
        for y in (-0.25, 0.0, 0.25):
            assert pixel(zoom.GetOutput(), x, y) == pixel(image, x, y)

    # A piece of the extent: only its pixels are computed.
    piece = gridfree.vtkWalkOnSpheresDiffusionCurves()
    piece.SetBoundaryData(boundary)
    piece.SetInputArrayToProcess(0, 0, 0, 0, "FrontColor")
    piece.SetInputArrayToProcess(1, 0, 0, 0, "BackColor")
    piece.SetWalksPerPoint(64)
    piece.SetImageWindow(-1.0, 1.0, -1.0, 1.0)
    piece.SetImageResolution(9, 9)
    piece.UpdateExtent((2, 4, 5, 8, 0, 0))
    part = piece.GetOutput()
    assert part.GetExtent() == (2, 4, 5, 8, 0, 0)
    assert piece.GetLastNumberOfWalks() == 3 * 4 * 64
    for i in range(part.GetNumberOfPoints()):
        x, y, _ = part.GetPoint(i)
        assert part.GetPointData().GetArray("FrontColor").GetTuple3(i) == pixel(image, x, y)


def test_rgb_copy_and_thread_independence():
    boundary = coloured_square()
    one, _ = run(boundary, walks=32, ImageResolution=(12, 10), NumberOfThreads=1,
                 ColorRange=(0.0, 1.0))
    two, catcher = run(boundary, walks=32, ImageResolution=(12, 10), NumberOfThreads=2,
                       ColorRange=(0.0, 1.0))
    assert not catcher.errors, catcher.error_text()
    a, b = one.GetOutput().GetPointData(), two.GetOutput().GetPointData()
    rgb = b.GetArray("FrontColor_RGB")
    assert rgb.GetDataTypeAsString() == "unsigned char" and rgb.GetNumberOfComponents() == 3
    colour = b.GetArray("FrontColor")
    assert b.GetScalars().GetName() == "FrontColor"
    for i in range(colour.GetNumberOfTuples()):
        assert a.GetArray("FrontColor").GetTuple3(i) == colour.GetTuple3(i)
        for c in range(3):
            expected = round(255 * min(1.0, max(0.0, colour.GetComponent(i, c))))
            assert abs(rgb.GetComponent(i, c) - expected) <= 0.5
    field = two.GetOutput().GetFieldData()
    assert field.GetArray("TotalWalks").GetValue(0) == 12 * 10 * 32
    # The default window is the curve's box enlarged by 5%.
    assert two.GetOutput().GetOrigin()[:2] == (-0.55, -0.55)


def test_bad_input_is_reported():
    boundary = coloured_square()
    _, catcher = run(boundary, back="Missing")
    assert "back colour array" in catcher.error_text()
    _, catcher = run(boundary, front="Missing")
    assert "front colour array" in catcher.error_text()
    # Colours with different numbers of components.
    add_point_array(boundary, "Grey", lambda x, y, z: 0.5)
    _, catcher = run(boundary, back="Grey")
    assert "number of components" in catcher.error_text()
    # A surface needs a probe.
    sphere = sphere_boundary(lambda x, y, z: z, name="FrontColor", resolution=16)
    add_point_array(sphere, "BackColor", lambda x, y, z: 0.0)
    _, catcher = run(sphere)
    assert "needs a Probe" in catcher.error_text()
    # An empty window.
    _, catcher = run(boundary, ImageWindow=(1.0, 0.0, 0.0, 1.0))
    assert "is empty" in catcher.error_text()
