"""Bad input gives a clear VTK error (or warning), never a crash."""
import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

import gridfree  # noqa: E402
from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkPoints, vtkStringArray  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkDataObject, vtkPolyData  # noqa: E402
from vtkmodules.vtkFiltersSources import vtkPlaneSource  # noqa: E402

from gridfree_testing import MessageCatcher, sphere_boundary  # noqa: E402

POINTS = vtkDataObject.FIELD_ASSOCIATION_POINTS


def run(boundary=None, probe=None, array="T"):
    solver = gridfree.vtkWalkOnSpheresSolver()
    catcher = MessageCatcher(solver, solver.GetExecutive())
    if boundary is not None:
        solver.SetBoundaryData(boundary)
    if probe is None:
        source = vtkPlaneSource()
        source.SetResolution(3, 3)
        source.Update()
        probe = source.GetOutput()
    solver.SetProbeData(probe)
    if array is not None:
        solver.SetInputArrayToProcess(0, 0, 0, POINTS, array)
    solver.SetWalksPerPoint(8)
    solver.Update()
    return solver, catcher


def test_no_boundary_input():
    # The Boundary port is optional (an implicit boundary can replace it), so
    # the solver itself says what is missing.
    _, catcher = run(boundary=None)
    assert "No Boundary input" in catcher.error_text()
    assert "ImplicitBoundary" in catcher.error_text()


def test_empty_boundary():
    _, catcher = run(boundary=vtkPolyData())
    assert "boundary is empty" in catcher.error_text()


def test_boundary_without_surfaces_or_lines():
    points = vtkPoints()
    points.InsertNextPoint(0, 0, 0)
    boundary = vtkPolyData()
    boundary.SetPoints(points)
    boundary.AllocateEstimate(1, 1)
    boundary.InsertNextCell(1, 1, [0])  # a vertex
    _, catcher = run(boundary=boundary)
    assert "neither surfaces" in catcher.error_text()


def test_missing_array():
    _, catcher = run(boundary=sphere_boundary(resolution=16), array="Missing")
    assert "no point or cell array named 'Missing'" in catcher.error_text()


def test_no_array_selected_and_no_scalars():
    _, catcher = run(boundary=sphere_boundary(resolution=16), array=None)
    assert "No boundary values" in catcher.error_text()


def test_active_scalars_are_the_default():
    boundary = sphere_boundary(resolution=16)
    boundary.GetPointData().SetActiveScalars("T")
    solver, catcher = run(boundary=boundary, array=None)
    assert catcher.errors == []
    assert solver.GetOutput().GetPointData().GetArray("T") is not None


def test_non_numeric_array():
    boundary = sphere_boundary(resolution=16)
    labels = vtkStringArray()
    labels.SetName("Labels")
    labels.SetNumberOfValues(boundary.GetNumberOfPoints())
    boundary.GetPointData().AddArray(labels)
    _, catcher = run(boundary=boundary, array="Labels")
    assert "not a numeric array" in catcher.error_text()


def test_nan_boundary_values():
    boundary = sphere_boundary(resolution=16)
    boundary.GetPointData().GetArray("T").SetValue(5, float("nan"))
    boundary.GetPointData().GetArray("T").SetValue(6, float("inf"))
    _, catcher = run(boundary=boundary)
    assert "2 NaN or infinite values" in catcher.error_text()


def test_lines_not_in_one_plane():
    points = vtkPoints()
    for p in [(0, 0, 0), (1, 0, 0), (1, 1, 1)]:
        points.InsertNextPoint(*p)
    boundary = vtkPolyData()
    boundary.SetPoints(points)
    boundary.AllocateEstimate(1, 3)
    boundary.InsertNextCell(4, 3, [0, 1, 2])  # VTK_POLY_LINE
    values = vtkDoubleArray()
    values.SetName("T")
    values.SetNumberOfTuples(3)
    values.Fill(1.0)
    boundary.GetPointData().AddArray(values)
    _, catcher = run(boundary=boundary)
    assert "one z-plane" in catcher.error_text()


def test_probe_with_zero_points():
    solver, catcher = run(boundary=sphere_boundary(resolution=16), probe=vtkPolyData())
    assert catcher.errors == []
    assert "no points" in catcher.warning_text()
    assert solver.GetOutput().GetNumberOfPoints() == 0


def test_bad_property_values_are_clamped():
    solver = gridfree.vtkWalkOnSpheresSolver()
    solver.SetWalksPerPoint(0)
    assert solver.GetWalksPerPoint() == 2
    solver.SetEpsilon(-1.0)
    assert solver.GetEpsilon() == 0.0
    solver.SetNumberOfThreads(-3)
    assert solver.GetNumberOfThreads() == 0


def test_nan_boundary_coordinates():
    boundary = sphere_boundary(resolution=16)
    boundary.GetPoints().SetPoint(3, float("nan"), 0.0, 0.0)
    _, catcher = run(boundary=boundary)
    assert "NaN or infinite coordinates" in catcher.error_text()
