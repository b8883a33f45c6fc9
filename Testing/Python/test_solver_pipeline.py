"""vtkWalkOnSpheresSolver in VTK pipelines driven from /usr/bin/python3."""
import math
import os
import sys
import time

sys.path.insert(0, os.path.dirname(__file__))

import gridfree  # noqa: E402
from vtkmodules.vtkCommonCore import vtkCommand, vtkDoubleArray  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkDataObject, vtkImageData  # noqa: E402
from vtkmodules.vtkFiltersSources import vtkPlaneSource  # noqa: E402

from gridfree_testing import (  # noqa: E402
    MessageCatcher, circle_boundary, filled_array, point_cloud, saddle, sphere_boundary,
    z_scores)

POINTS = vtkDataObject.FIELD_ASSOCIATION_POINTS
CELLS = vtkDataObject.FIELD_ASSOCIATION_CELLS


def plane(origin, point1, point2, resolution):
    source = vtkPlaneSource()
    source.SetOrigin(*origin)
    source.SetPoint1(*point1)
    source.SetPoint2(*point2)
    source.SetResolution(resolution, resolution)
    return source


def solver_for(boundary, probe_port=None, probe_data=None, walks=128, array="T", assoc=POINTS):
    solver = gridfree.vtkWalkOnSpheresSolver()
    solver.SetBoundaryData(boundary)
    if probe_port is not None:
        solver.SetProbeConnection(probe_port)
    else:
        solver.SetProbeData(probe_data)
    solver.SetInputArrayToProcess(0, 0, 0, assoc, array)
    solver.SetWalksPerPoint(walks)
    return solver


def assert_accurate_and_calibrated(scores):
    assert len(scores) >= 500
    worst = max(abs(z) for z in scores)
    mean_z2 = sum(z * z for z in scores) / len(scores)
    assert worst < 5.0, worst
    assert 0.7 < mean_z2 < 1.4, mean_z2


def test_plane_probe_3d_accuracy_and_calibration():
    # 24 x 24 = 576 points on a slice through a sphere carrying x^2 - y^2.
    probe = plane((-0.6, -0.6, 0.2), (0.6, -0.6, 0.2), (-0.6, 0.6, 0.2), 23)
    solver = solver_for(sphere_boundary(), probe.GetOutputPort(), walks=256)
    solver.SetSeed(3)
    solver.Update()
    output = solver.GetOutput()
    assert output.IsA("vtkPolyData")
    assert output.GetNumberOfPoints() == 576
    assert output.GetPointData().GetScalars().GetName() == "T"
    # The probe's own arrays pass through.
    assert output.GetPointData().GetArray("Normals") is not None
    assert_accurate_and_calibrated(z_scores(output, saddle))


def test_probe_array_named_like_the_boundary_array_is_kept():
    # The Plane's own Normals chosen as boundary values: the probe's Normals
    # stay, the solution is Normals_Solution, and a warning says so.
    from vtkmodules.vtkFiltersCore import vtkPolyDataNormals
    sphere = sphere_boundary()
    normals = vtkPolyDataNormals()
    normals.SetInputData(sphere)
    normals.Update()
    boundary = normals.GetOutput()
    probe = plane((-0.3, -0.3, 0.1), (0.3, -0.3, 0.1), (-0.3, 0.3, 0.1), 3)
    probe.Update()
    before = [probe.GetOutput().GetPointData().GetArray("Normals").GetTuple3(i) for i in range(16)]
    solver = solver_for(boundary, probe.GetOutputPort(), walks=16, array="Normals")
    messages = MessageCatcher(solver)
    solver.Update()
    pd = solver.GetOutput().GetPointData()
    after = [pd.GetArray("Normals").GetTuple3(i) for i in range(16)]
    assert after == before
    assert pd.GetArray("Normals_Solution").GetNumberOfComponents() == 3
    assert pd.GetArray("Normals_Solution_Variance") is not None
    assert pd.GetScalars().GetName() == "Normals_Solution"
    assert "named 'Normals_Solution'" in messages.warning_text(), messages.warning_text()
    assert not messages.errors


def test_several_boundary_connections_are_one_boundary():
    # Two halves of the sphere on two connections of the Boundary port give
    # the numbers of the same halves grouped in one multiblock; the probe,
    # also connected as a boundary, is the probe only.
    from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet, vtkPlane
    from vtkmodules.vtkFiltersCore import vtkClipPolyData
    halves = []
    for sign in (1.0, -1.0):
        plane_function = vtkPlane()
        plane_function.SetNormal(0.0, 0.0, sign)
        clip = vtkClipPolyData()
        clip.SetInputData(sphere_boundary())
        clip.SetClipFunction(plane_function)
        clip.Update()
        halves.append(clip.GetOutput())
    probe = plane((-0.5, -0.5, 0.3), (0.5, -0.5, 0.3), (-0.5, 0.5, 0.3), 7)
    probe.Update()

    grouped = vtkMultiBlockDataSet()
    grouped.SetNumberOfBlocks(2)
    grouped.SetBlock(0, halves[0])
    grouped.SetBlock(1, halves[1])
    one = solver_for(grouped, probe.GetOutputPort(), walks=64)
    one.Update()

    several = solver_for(halves[0], probe.GetOutputPort(), walks=64)
    several.AddInputDataObject(0, halves[1])
    several.AddInputConnection(0, probe.GetOutputPort())  # the probe: left out
    messages = MessageCatcher(several)
    several.Update()
    assert not messages.errors and not messages.warnings, messages.warning_text()
    a = one.GetOutput().GetPointData().GetArray("T")
    b = several.GetOutput().GetPointData().GetArray("T")
    assert [a.GetValue(i) for i in range(64)] == [b.GetValue(i) for i in range(64)]
    scores = z_scores(several.GetOutput(), saddle)  # 64 points
    assert max(abs(z) for z in scores) < 5.0
    assert 0.5 < sum(z * z for z in scores) / len(scores) < 1.6

    several.RemoveAllBoundaryConnections()
    several.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    assert several.GetNumberOfInputConnections(0) == 0


def test_image_probe_stays_image():
    image = vtkImageData()
    image.SetDimensions(12, 10, 4)
    image.SetOrigin(-0.4, -0.3, -0.2)
    image.SetSpacing(0.07, 0.06, 0.1)
    solver = solver_for(sphere_boundary(), probe_data=image, walks=64)
    solver.Update()
    output = solver.GetOutput()
    assert isinstance(output, vtkImageData)
    assert output.GetDimensions() == (12, 10, 4)
    assert output.GetSpacing() == (0.07, 0.06, 0.1)
    assert output.GetOrigin() == (-0.4, -0.3, -0.2)
    for name in ("T", "T_Variance", "WalkSteps", "EscapedFraction", "TruncatedFraction"):
        array = output.GetPointData().GetArray(name)
        assert array is not None and array.GetNumberOfTuples() == 480, name
    scores = z_scores(output, saddle)
    assert max(abs(z) for z in scores) < 5.0


def test_2d_polyline_boundary_accuracy_and_calibration():
    def exp_cos(x, y, z=0.0):
        return math.exp(x) * math.cos(y)

    probe = plane((-0.6, -0.6, 0.0), (0.6, -0.6, 0.0), (-0.6, 0.6, 0.0), 23)
    solver = solver_for(circle_boundary(exp_cos), probe.GetOutputPort(), walks=256)
    solver.Update()
    assert solver.GetLastDimension() == 2
    assert_accurate_and_calibrated(z_scores(solver.GetOutput(), exp_cos))


def test_cell_data_and_multiple_components():
    boundary = sphere_boundary(resolution=64)
    # Cell data: constant 2.5 everywhere, so u = 2.5 exactly, with zero variance.
    cells = vtkDoubleArray()
    cells.SetName("C")
    cells.SetNumberOfTuples(boundary.GetNumberOfCells())
    cells.Fill(2.5)
    boundary.GetCellData().AddArray(cells)
    # Three components: (1, x^2 - y^2, 2 (x^2 - y^2)).
    vectors = vtkDoubleArray()
    vectors.SetName("V")
    vectors.SetNumberOfComponents(3)
    for i in range(boundary.GetNumberOfPoints()):
        s = saddle(*boundary.GetPoint(i))
        vectors.InsertNextTuple((1.0, s, 2.0 * s))
    boundary.GetPointData().AddArray(vectors)
    probe = plane((-0.5, -0.5, 0.0), (0.5, -0.5, 0.0), (-0.5, 0.5, 0.0), 4)

    solver = solver_for(boundary, probe.GetOutputPort(), walks=32, array="C", assoc=CELLS)
    solver.Update()
    out = solver.GetOutput().GetPointData()
    assert out.GetArray("C").GetRange() == (2.5, 2.5)
    assert out.GetArray("C_Variance").GetRange() == (0.0, 0.0)

    solver = solver_for(boundary, probe.GetOutputPort(), walks=32, array="V")
    solver.Update()
    out = solver.GetOutput().GetPointData()
    v, var = out.GetArray("V"), out.GetArray("V_Variance")
    assert v.GetNumberOfComponents() == 3 and var.GetNumberOfComponents() == 3
    for i in range(v.GetNumberOfTuples()):
        one, s, twice = v.GetTuple3(i)
        assert abs(one - 1.0) < 1e-12
        assert abs(twice - 2.0 * s) < 1e-12  # same walks for every component
        assert abs(var.GetComponent(i, 2) - 4.0 * var.GetComponent(i, 1)) < 1e-12


def test_same_numbers_for_any_thread_count():
    boundary = sphere_boundary(resolution=48)
    probe = plane((-0.5, -0.5, 0.1), (0.5, -0.5, 0.1), (-0.5, 0.5, 0.1), 15)
    results = []
    for threads in (1, 2, 0):
        solver = solver_for(boundary, probe.GetOutputPort(), walks=16)
        solver.SetNumberOfThreads(threads)
        solver.SetSeed(11)
        solver.Update()
        array = solver.GetOutput().GetPointData().GetArray("T")
        results.append([array.GetTuple1(i) for i in range(array.GetNumberOfTuples())])
    assert results[0] == results[1] == results[2]
    # A different seed gives different numbers.
    solver = solver_for(boundary, probe.GetOutputPort(), walks=16)
    solver.SetSeed(12)
    solver.Update()
    array = solver.GetOutput().GetPointData().GetArray("T")
    assert [array.GetTuple1(i) for i in range(array.GetNumberOfTuples())] != results[0]


def test_progress_is_reported_and_abort_is_prompt():
    boundary = sphere_boundary(resolution=48)
    probe = plane((-0.5, -0.5, 0.0), (0.5, -0.5, 0.0), (-0.5, 0.5, 0.0), 99)
    solver = solver_for(boundary, probe.GetOutputPort(), walks=4096)  # ~40M walks: minutes
    catcher = MessageCatcher(solver)
    progress = []

    def on_progress(obj, event):
        progress.append(obj.GetProgress())
        if len(progress) == 3:
            obj.SetAbortExecute(1)

    solver.AddObserver(vtkCommand.ProgressEvent, on_progress)
    start = time.monotonic()
    solver.Update()
    elapsed = time.monotonic() - start
    assert len(progress) >= 3
    assert elapsed < 3.0, elapsed  # three progress reports + at most one second
    assert "aborted" in catcher.warning_text()
    # A fresh solve aborted: the points not reached have no walks, NaN.
    values = solver.GetOutput().GetPointData().GetArray("T")
    assert any(math.isnan(values.GetTuple1(i)) for i in range(values.GetNumberOfTuples()))


def test_progress_goes_on_while_a_large_boundary_is_built():
    # 2.9M triangles: building the hierarchy and the distance bounds takes
    # seconds, during which progress (and with it ParaView's window, which
    # processes events only in progress reports) must go on. One point, two
    # walks: the solve itself reports nothing before it ends.
    from vtkmodules.vtkFiltersSources import vtkSphereSource
    sphere = vtkSphereSource()
    sphere.SetThetaResolution(1200)
    sphere.SetPhiResolution(1200)
    sphere.Update()
    boundary = sphere.GetOutput()
    boundary.GetPointData().AddArray(filled_array("T", boundary.GetNumberOfPoints(), 1.0))
    solver = solver_for(boundary, probe_data=point_cloud([(0.1, 0.0, 0.0)]), walks=2)
    building = []

    def on_progress(obj, event):
        if 0.0 < obj.GetProgress() <= 0.02:
            building.append(obj.GetProgress())

    solver.AddObserver(vtkCommand.ProgressEvent, on_progress)
    solver.Update()
    assert solver.GetLastBoundaryBuilt()
    assert len(building) >= 2, building  # reports every tenth of a second
    assert building == sorted(building)


def test_polygons_and_strips_are_triangulated():
    """A cube made of quads, and the same cube as triangle strips: a linear g
    is reproduced exactly by the boundary interpolation, so only Monte Carlo
    error remains."""
    from vtkmodules.vtkFiltersCore import vtkStripper, vtkTriangleFilter
    from vtkmodules.vtkFiltersSources import vtkCubeSource
    from gridfree_testing import add_point_array
    from vtkmodules.vtkCommonDataModel import vtkPolyData

    def linear(x, y, z=0.0):
        return 1.0 + x + 2.0 * y - 3.0 * z

    cube = vtkCubeSource()
    cube.SetXLength(2.0)
    cube.SetYLength(2.0)
    cube.SetZLength(2.0)
    cube.Update()
    quads = vtkPolyData()
    quads.DeepCopy(cube.GetOutput())
    assert quads.GetCell(0).GetNumberOfPoints() == 4
    add_point_array(quads, "T", linear)

    triangles = vtkTriangleFilter()
    triangles.SetInputData(quads)
    strips = vtkStripper()
    strips.SetInputConnection(triangles.GetOutputPort())
    strips.Update()
    stripped = strips.GetOutput()
    assert stripped.GetNumberOfStrips() > 0

    probe = plane((-0.7, -0.7, 0.3), (0.7, -0.7, 0.3), (-0.7, 0.7, 0.3), 6)
    for boundary in (quads, stripped):
        solver = solver_for(boundary, probe.GetOutputPort(), walks=256)
        solver.Update()
        scores = z_scores(solver.GetOutput(), linear)
        assert max(abs(z) for z in scores) < 5.0
