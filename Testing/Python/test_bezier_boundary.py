"""2D boundaries of cubic Bézier curves through Python: polylines marked in the
cell array "BezierControlPoints", values interpolated between curve end
points, the error for a wrong control-point count, and the example
Documentation/Examples/bezier_diffusion_curve.py run small."""
import math
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(__file__))

import gridfree  # noqa: E402
from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkIntArray, vtkPoints  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkDataObject, vtkPolyData  # noqa: E402
from vtkmodules.vtkIOXML import vtkXMLImageDataReader  # noqa: E402

from gridfree_testing import MessageCatcher, z_scores  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLE = os.path.join(HERE, "..", "..", "Documentation", "Examples", "bezier_diffusion_curve.py")
POINTS = vtkDataObject.FIELD_ASSOCIATION_POINTS
CELLS = vtkDataObject.FIELD_ASSOCIATION_CELLS
HANDLE_VALUE = 1.0e6  # on the handles, which are off the curve: never used


def bilinear(x, y, z=0.0):
    """Harmonic and linear along every edge of an axis-aligned square."""
    return x * y + 0.3 * x + 0.2


def bezier_square(marker=1, control_points=None):
    """The square [-1, 1]^2 as one closed polyline of four straight cubic
    curves (handles at 1/3 and 2/3 of each edge), point array "T"."""
    corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
    points = vtkPoints()
    points.SetDataTypeToDouble()
    values = vtkDoubleArray()
    values.SetName("T")
    for i, (ax, ay) in enumerate(corners):
        bx, by = corners[(i + 1) % 4]
        points.InsertNextPoint(ax, ay, 0.0)
        values.InsertNextValue(bilinear(ax, ay))
        for s in (1.0 / 3.0, 2.0 / 3.0):
            points.InsertNextPoint(ax + s * (bx - ax), ay + s * (by - ay), 0.0)
            values.InsertNextValue(HANDLE_VALUE)
    ids = control_points if control_points is not None else list(range(12)) + [0]
    lines = vtkCellArray()
    lines.InsertNextCell(len(ids))
    for i in ids:
        lines.InsertCellPoint(i)
    marks = vtkIntArray()
    marks.SetName("BezierControlPoints")
    marks.InsertNextValue(marker)
    boundary = vtkPolyData()
    boundary.SetPoints(points)
    boundary.SetLines(lines)
    boundary.GetCellData().AddArray(marks)
    boundary.GetPointData().AddArray(values)
    return boundary


def probe_grid(count=7, half=0.85):
    points = vtkPoints()
    for i in range(count):
        for j in range(count):
            points.InsertNextPoint(-half + 2 * half * i / (count - 1),
                                   -half + 2 * half * j / (count - 1), 0.0)
    probe = vtkPolyData()
    probe.SetPoints(points)
    return probe


def solve(boundary, association=POINTS, array="T", walks=256, seed=3):
    solver = gridfree.vtkWalkOnSpheresSolver()
    catcher = MessageCatcher(solver, solver.GetExecutive())
    solver.SetBoundaryData(boundary)
    solver.SetProbeData(probe_grid())
    solver.SetInputArrayToProcess(0, 0, 0, association, array)
    solver.SetWalksPerPoint(walks)
    solver.SetSeed(seed)
    solver.Update()
    return solver, catcher


def test_straight_bezier_square_gives_the_harmonic_function():
    solver, catcher = solve(bezier_square())
    assert catcher.errors == []
    assert catcher.warnings == []
    assert solver.GetLastDimension() == 2
    scores = z_scores(solver.GetOutput(), bilinear)
    assert max(abs(z) for z in scores) < 5.0, scores
    mean_z2 = sum(z * z for z in scores) / len(scores)
    assert 0.5 < mean_z2 < 1.6, mean_z2


def test_unmarked_polyline_uses_handles_as_corners():
    # The same points as a plain polyline (marker 0): the "handles" are then
    # ordinary points on the edges, with their absurd values, so the solution
    # must be far from the Bézier one.
    solver, catcher = solve(bezier_square(marker=0), walks=16)
    assert catcher.errors == []
    values = solver.GetOutput().GetPointData().GetArray("T")
    assert max(abs(values.GetTuple1(i)) for i in range(values.GetNumberOfTuples())) > 1e3


def test_cell_values_are_constant_per_polyline():
    boundary = bezier_square()
    constant = vtkDoubleArray()
    constant.SetName("C")
    constant.InsertNextValue(2.5)
    boundary.GetCellData().AddArray(constant)
    solver, catcher = solve(boundary, association=CELLS, array="C", walks=8)
    assert catcher.errors == []
    values = solver.GetOutput().GetPointData().GetArray("C")
    for i in range(values.GetNumberOfTuples()):
        assert values.GetTuple1(i) == 2.5


def test_wrong_control_point_count_is_an_error():
    # 5 control points: not 3k + 1.
    _, catcher = solve(bezier_square(control_points=[0, 1, 2, 3, 4]), walks=4)
    text = catcher.error_text()
    assert "cell 0 is marked as a Bézier curve" in text, text
    assert "has 5 points" in text, text


def test_marker_array_of_the_wrong_kind_is_an_error():
    """BezierControlPoints must be one numeric component per cell."""
    from vtkmodules.vtkCommonCore import vtkStringArray
    for kind in ("two components", "string", "point data"):
        boundary = bezier_square()
        boundary.GetCellData().RemoveArray("BezierControlPoints")
        if kind == "two components":
            marks = vtkIntArray()
            marks.SetNumberOfComponents(2)
            marks.InsertNextTuple2(1, 1)
        elif kind == "string":
            marks = vtkStringArray()
            marks.InsertNextValue("yes")
        else:
            marks = vtkIntArray()
            for _ in range(boundary.GetNumberOfPoints()):
                marks.InsertNextValue(1)
        marks.SetName("BezierControlPoints")
        if kind == "point data":
            boundary.GetPointData().AddArray(marks)
        else:
            boundary.GetCellData().AddArray(marks)
        _, catcher = solve(boundary, walks=4)
        expected = "must be cell data" if kind == "point data" else \
            "must be numeric with one component and one value per cell"
        assert expected in catcher.error_text(), (kind, catcher.error_text())


def test_example_writes_an_image(tmp_path):
    output = os.path.join(str(tmp_path), "diffusion_curve.vti")
    run = subprocess.run(
        [sys.executable, EXAMPLE, "--resolution", "24", "--walks", "16", "--output", output],
        capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "points: 576" in run.stdout, run.stdout
    reader = vtkXMLImageDataReader()
    reader.SetFileName(output)
    reader.Update()
    color = reader.GetOutput().GetPointData().GetArray("Color")
    assert color is not None and color.GetNumberOfComponents() == 3
    # The exact colours lie in [0, 1] (maximum principle); the estimates only
    # by Monte Carlo noise outside it.
    for i in range(color.GetNumberOfTuples()):
        for c in range(3):
            v = color.GetComponent(i, c)
            assert math.isfinite(v) and -0.25 <= v <= 1.25, (i, c, v)
