"""Bad input gives a clear VTK error (or warning), never a crash."""
import math
import os
import re
import sys
import time

sys.path.insert(0, os.path.dirname(__file__))

import gridfree  # noqa: E402
from vtkmodules.vtkCommonCore import (  # noqa: E402
    vtkBitArray, vtkCommand, vtkDoubleArray, vtkPoints, vtkStringArray)
from vtkmodules.vtkCommonDataModel import vtkDataObject, vtkPolyData  # noqa: E402
from vtkmodules.vtkFiltersSources import vtkPlaneSource  # noqa: E402

from gridfree_testing import (  # noqa: E402
    MessageCatcher, filled_array, point_cloud, sphere_boundary)

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


def test_no_probe_input_is_one_error_of_the_solver():
    # Not the executive's "did not create output ... DATA_TYPE_NAME" nor
    # "Input port 1 ... has 0 connections": the solver says what to connect.
    from gridfree_testing import sphere_boundary
    solver = gridfree.vtkWalkOnSpheresSolver()
    catcher = MessageCatcher(solver, solver.GetExecutive())
    solver.SetBoundaryData(sphere_boundary())
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    solver.Update()
    ours = [e for e in catcher.errors if "returned failure" not in e]
    assert len(ours) == 1 and "No Probe input" in ours[0], catcher.error_text()


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
    boundary.GetPointData().AddArray(filled_array("T", 3, 1.0))
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


def test_enumeration_values_out_of_range_are_errors_that_name_the_choices():
    solver = gridfree.vtkWalkOnSpheresSolver()
    catcher = MessageCatcher(solver)
    solver.SetEquation(7)
    assert solver.GetEquation() == gridfree.vtkWalkOnSpheresSolver.LAPLACE
    assert "SetEquation(7): Equation is one of 0 Laplace, 1 Poisson, 2 screened Poisson, " \
        "3 biharmonic, 4 varying coefficients; it stays Laplace." in catcher.error_text()
    solver.SetSourceSampling(9)
    assert solver.GetSourceSampling() == gridfree.vtkWalkOnSpheresSolver.AUTOMATIC_SOURCE_SAMPLING
    assert "SetSourceSampling(9)" in catcher.error_text()
    for setter in ("SetSourceOperator", "SetBiharmonicStrategy", "SetCsgOperation"):
        getattr(solver, setter)(-1)
        assert setter + "(-1)" in catcher.error_text()
    assert len(catcher.errors) == 5
    solver.SetEquation(gridfree.vtkWalkOnSpheresSolver.POISSON)  # in range: no message
    assert solver.GetEquation() == gridfree.vtkWalkOnSpheresSolver.POISSON
    assert len(catcher.errors) == 5


def test_expression_typo_gives_the_parsers_reason():
    boundary = sphere_boundary(resolution=16)
    solver = gridfree.vtkWalkOnSpheresSolver()
    catcher = MessageCatcher(solver, solver.GetExecutive())
    solver.SetBoundaryData(boundary)
    solver.SetProbeData(point_cloud([(0.1, 0.0, 0.0)]))
    solver.SetBoundaryValueExpression("x*yy")
    solver.Update()
    text = catcher.error_text()
    assert "Cannot use the boundary value expression 'x*yy': " \
        "ERR201 - Undefined symbol: 'yy'." in text, text
    assert "vtkExprTkFunctionParser.cxx" not in text


def test_csg_with_one_operand_says_nothing_is_combined():
    solver = gridfree.vtkWalkOnSpheresSolver()
    catcher = MessageCatcher(solver)
    solver.SetBoundaryData(sphere_boundary(resolution=16))
    solver.SetProbeData(point_cloud([(0.1, 0.0, 0.0)]))
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    solver.SetWalksPerPoint(8)
    solver.SetCsgOperationToUnion()
    solver.Update()
    assert "one operand only (one Boundary surface): nothing is combined" \
        in catcher.warning_text()


def test_one_thread_then_two_leaves_tbb_silent():
    # In a process of its own (TBB sizes its pool of workers once): a solve
    # on one thread, then on two, with no "request for N workers is ignored".
    import subprocess
    script = (
        "import sys; sys.path.insert(0, %r)\n"
        "import gridfree\n"
        "from gridfree_testing import point_cloud, sphere_boundary\n"
        "from vtkmodules.vtkCommonDataModel import vtkDataObject\n"
        "for threads in (1, 2):\n"
        "    s = gridfree.vtkWalkOnSpheresSolver()\n"
        "    s.SetBoundaryData(sphere_boundary(resolution=16))\n"
        "    s.SetProbeData(point_cloud([(0.1, 0.0, 0.0), (0.0, 0.2, 0.0)] * 20))\n"
        "    s.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS, 'T')\n"
        "    s.SetNumberOfThreads(threads)\n"
        "    s.SetWalksPerPoint(64)\n"
        "    s.Update()\n"
        "print('solved')\n" % os.path.dirname(os.path.abspath(__file__)))
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                            timeout=120)
    assert result.returncode == 0 and "solved" in result.stdout, result.stderr
    assert "ignored" not in result.stderr, result.stderr


def test_nan_boundary_coordinates():
    boundary = sphere_boundary(resolution=16)
    boundary.GetPoints().SetPoint(3, float("nan"), 0.0, 0.0)
    _, catcher = run(boundary=boundary)
    assert "NaN or infinite coordinates" in catcher.error_text()


# ---------------------------------------------------------------------------
# Adversarial inputs (each row of Documentation's table of bad inputs).


def solve(boundary, probe, array="T", walks=8, **settings):
    solver = gridfree.vtkWalkOnSpheresSolver()
    catcher = MessageCatcher(solver, solver.GetExecutive())
    solver.SetBoundaryData(boundary)
    solver.SetProbeData(probe)
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, array)
    solver.SetWalksPerPoint(walks)
    for name, value in settings.items():
        getattr(solver, "Set" + name)(value)
    solver.Update()
    return solver, catcher


def small_plane():
    source = vtkPlaneSource()
    source.SetOrigin(-0.4, -0.4, 0.0)
    source.SetPoint1(0.4, -0.4, 0.0)
    source.SetPoint2(-0.4, 0.4, 0.0)
    source.SetResolution(3, 3)
    source.Update()
    return source.GetOutput()


def values_of(data, name="T"):
    array = data.GetPointData().GetArray(name)
    return [array.GetTuple1(i) for i in range(array.GetNumberOfTuples())]


def test_infinite_boundary_coordinates():
    boundary = sphere_boundary(resolution=16)
    boundary.GetPoints().SetPoint(4, 0.0, float("inf"), 0.0)
    _, catcher = run(boundary=boundary)
    assert "NaN or infinite coordinates" in catcher.error_text()


def test_lines_and_vertices_mixed_into_a_surface_are_ignored():
    """A 3D problem: the lines and vertices are reported, not used, and the
    result is that of the surface alone."""
    boundary = sphere_boundary(resolution=16)
    reference, _ = solve(sphere_boundary(resolution=16), small_plane())
    from vtkmodules.vtkCommonDataModel import vtkCellArray
    lines = vtkCellArray()
    lines.InsertNextCell(2, [0, 5])
    vertices = vtkCellArray()
    vertices.InsertNextCell(1, [7])
    boundary.SetLines(lines)
    boundary.SetVerts(vertices)
    solver, catcher = solve(boundary, small_plane())
    assert catcher.errors == []
    assert "Ignored 2 boundary cells of lower dimension" in catcher.warning_text()
    assert values_of(solver.GetOutput()) == values_of(reference.GetOutput())


def test_zero_area_boundary():
    """Only degenerate triangles (collinear points): nothing is left to solve on."""
    points = vtkPoints()
    for p in [(0, 0, 0), (1, 0, 0), (2, 0, 0), (0, 0, 0)]:
        points.InsertNextPoint(*p)
    boundary = vtkPolyData()
    boundary.SetPoints(points)
    boundary.AllocateEstimate(2, 3)
    boundary.InsertNextCell(5, 3, [0, 1, 2])  # collinear
    boundary.InsertNextCell(5, 3, [0, 3, 1])  # repeated point
    boundary.GetPointData().AddArray(filled_array("T", 4, 1.0))
    _, catcher = solve(boundary, small_plane())
    assert "the boundary has no triangles (2 degenerate ones of zero length or area were " \
        "dropped)" in catcher.error_text()


def test_probe_points_on_a_vertex_an_edge_and_a_face():
    """Points exactly on the boundary get the boundary value there (the
    closest point is themselves), with zero variance, in no time."""
    boundary = sphere_boundary(resolution=16)
    t = boundary.GetPointData().GetArray("T")
    cell = boundary.GetCell(40)
    ids = [cell.GetPointId(k) for k in range(3)]
    corners = [boundary.GetPoint(i) for i in ids]
    probe = point_cloud([
        corners[0],
        [(corners[0][k] + corners[1][k]) / 2 for k in range(3)],
        [(corners[0][k] + corners[1][k] + corners[2][k]) / 3 for k in range(3)],
    ])
    expected = [
        t.GetTuple1(ids[0]),
        (t.GetTuple1(ids[0]) + t.GetTuple1(ids[1])) / 2,
        sum(t.GetTuple1(i) for i in ids) / 3,
    ]
    for controls in (False, True):
        solver, catcher = solve(boundary, probe, walks=64, ControlVariates=controls)
        assert catcher.errors == []
        out = solver.GetOutput().GetPointData()
        for i, value in enumerate(expected):
            assert abs(out.GetArray("T").GetTuple1(i) - value) < 1e-12
            assert out.GetArray("T_Variance").GetTuple1(i) == 0.0
            assert out.GetArray("BoundaryDistance").GetTuple1(i) < 1e-12


def test_bit_array_gives_the_values_0_and_1():
    boundary = sphere_boundary(resolution=16)
    bits = vtkBitArray()
    bits.SetName("Upper")
    as_doubles = vtkDoubleArray()
    as_doubles.SetName("UpperAsDoubles")
    for i in range(boundary.GetNumberOfPoints()):
        bit = 1 if boundary.GetPoint(i)[2] > 0 else 0
        bits.InsertNextValue(bit)
        as_doubles.InsertNextValue(bit)
    boundary.GetPointData().AddArray(bits)
    boundary.GetPointData().AddArray(as_doubles)
    from_bits, catcher = solve(boundary, small_plane(), array="Upper")
    from_doubles, _ = solve(boundary, small_plane(), array="UpperAsDoubles")
    assert catcher.errors == []
    assert values_of(from_bits.GetOutput(), "Upper") == values_of(
        from_doubles.GetOutput(), "UpperAsDoubles")


def test_point_array_shorter_than_the_points():
    boundary = sphere_boundary(resolution=16)
    boundary.GetPointData().AddArray(filled_array("Short", 5, 1.0))
    _, catcher = solve(boundary, small_plane(), array="Short")
    assert "has 5 tuples, but the mesh has %d points" % boundary.GetNumberOfPoints() \
        in catcher.error_text()


def test_cell_array_longer_than_the_cells():
    boundary = sphere_boundary(resolution=16)
    boundary.GetCellData().AddArray(filled_array("Long", boundary.GetNumberOfCells() + 3, 1.0))
    solver = gridfree.vtkWalkOnSpheresSolver()
    catcher = MessageCatcher(solver, solver.GetExecutive())
    solver.SetBoundaryData(boundary)
    solver.SetProbeData(small_plane())
    solver.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_CELLS, "Long")
    solver.Update()
    assert "tuples, but the mesh has %d cells" % boundary.GetNumberOfCells() \
        in catcher.error_text()


def test_source_array_shorter_than_its_points():
    source = small_plane()
    source.GetPointData().AddArray(filled_array("f", 2, 1.0))
    solver = gridfree.vtkWalkOnSpheresSolver()
    catcher = MessageCatcher(solver, solver.GetExecutive())
    solver.SetBoundaryData(sphere_boundary(resolution=16))
    solver.SetProbeData(small_plane())
    solver.SetSourceData(source)
    solver.SetEquation(solver.POISSON)
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    solver.SetInputArrayToProcess(2, 2, 0, POINTS, "f")
    solver.Update()
    assert "Cannot use the Source input: the array 'f' has 2 tuples, but the mesh has 16 points" \
        in catcher.error_text()


def test_multiblock_probe_is_solved_block_by_block():
    from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet
    boundary = sphere_boundary(resolution=16)
    first = small_plane()
    second = point_cloud([(0.1, 0.2, 0.3), (-0.3, 0.0, 0.2)])
    blocks = vtkMultiBlockDataSet()
    blocks.SetBlock(0, first)
    blocks.SetBlock(1, second)
    solver, catcher = solve(boundary, blocks)
    assert catcher.errors == []
    out = solver.GetOutputDataObject(0)
    assert out.IsA("vtkMultiBlockDataSet") and out.GetNumberOfBlocks() == 2
    for index, block in enumerate((first, second)):
        alone, _ = solve(boundary, block)
        assert values_of(out.GetBlock(index)) == values_of(alone.GetOutput())


def test_non_finite_probe_points():
    probe = point_cloud([(0.1, 0.0, 0.0), (float("nan"), 0.0, 0.0), (0.0, float("inf"), 0.0),
                         (0.0, 0.2, 0.1)])
    solver, catcher = solve(sphere_boundary(resolution=16), probe)
    assert catcher.errors == []
    assert "2 of 4 probe points have NaN or infinite coordinates" in catcher.warning_text()
    values = values_of(solver.GetOutput())
    assert math.isfinite(values[0]) and math.isfinite(values[3])
    assert math.isnan(values[1]) and math.isnan(values[2])


def test_probe_points_too_far_for_the_walks():
    """Coordinates near the double range overflow the walks' arithmetic: such
    a point is either right (the exterior Laplace solution there is 0) or NaN
    with a warning saying so, and never hangs or burns MaxSteps."""
    probe = point_cloud([(0.1, 0.0, 0.0), (1e300, 0.0, 0.0)])
    for equation in (gridfree.vtkWalkOnSpheresSolver.LAPLACE,
                     gridfree.vtkWalkOnSpheresSolver.SCREENED_POISSON):
        start = time.monotonic()
        solver, catcher = solve(sphere_boundary(resolution=16), probe, Equation=equation,
                                ScreeningCoefficient=1.0)
        assert time.monotonic() - start < 10.0
        values = values_of(solver.GetOutput())
        assert math.isfinite(values[0])
        if equation == gridfree.vtkWalkOnSpheresSolver.LAPLACE:
            assert values[1] == 0.0
        elif math.isnan(values[1]):
            assert "1 of 2 probe points got NaN results" in catcher.warning_text()
        assert max(values_of(solver.GetOutput(), "WalkSteps")) < 100
        assert "MaxSteps" not in catcher.warning_text()


def test_epsilon_larger_than_the_domain():
    solver, catcher = solve(sphere_boundary(resolution=16), small_plane(), Epsilon=0.5)
    assert catcher.errors == []
    assert "at least a tenth of the boundary's diagonal" in catcher.warning_text()
    solver, catcher = solve(sphere_boundary(resolution=16), small_plane(),
                            Epsilon=3.0, EpsilonIsRelative=False)
    assert "at least a tenth" in catcher.warning_text()
    assert all(math.isfinite(v) for v in values_of(solver.GetOutput()))


def test_absurd_walks_per_point_warn_and_abort_works():
    """2^31 - 1 walks on each of 3 points (days of work): the solver says how
    long it would take, and aborting on that warning ends the solve at once,
    although no point is finished: the points it started show the estimate
    of the walks they ran (WalkCount), the others are NaN with WalkCount 0."""
    solver = gridfree.vtkWalkOnSpheresSolver()
    catcher = MessageCatcher(solver, solver.GetExecutive())
    solver.SetBoundaryData(sphere_boundary(resolution=16))
    solver.SetProbeData(point_cloud([(0.1, 0.0, 0.0), (0.0, 0.2, 0.0), (0.0, 0.0, 0.3)]))
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    solver.SetWalksPerPoint(2**31 - 1)
    solver.SetNumberOfThreads(1)

    def on_warning(obj, event):
        obj.SetAbortExecute(1)

    solver.AddObserver(vtkCommand.WarningEvent, on_warning)
    start = time.monotonic()
    solver.Update()
    elapsed = time.monotonic() - start
    assert elapsed < 10.0, elapsed
    assert re.search(r"This solve will take about \d+ (hours|days|years)", catcher.warning_text())
    assert re.search(r"Solve aborted after .*: 0 of 3 probe points have all 2147483647 walks",
                     catcher.warning_text())
    assert solver.GetLastSolveAborted()
    counts = solver.GetOutput().GetPointData().GetArray("WalkCount")
    values = values_of(solver.GetOutput())
    for i, v in enumerate(values):
        walks = counts.GetValue(i)
        assert 0 <= walks < 2**31 - 1
        assert math.isnan(v) == (walks == 0), (v, walks)


def biharmonic_solver(boundary):
    solver = gridfree.vtkWalkOnSpheresSolver()
    catcher = MessageCatcher(solver, solver.GetExecutive())
    solver.SetBoundaryData(boundary)
    solver.SetProbeData(small_plane())
    solver.SetEquation(gridfree.vtkWalkOnSpheresSolver.BIHARMONIC)
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    solver.SetWalksPerPoint(8)
    return solver, catcher


def test_laplacian_array_of_another_association_or_size():
    boundary = sphere_boundary(resolution=16)
    boundary.GetCellData().AddArray(filled_array("HCells", boundary.GetNumberOfCells(), 0.0))
    boundary.GetPointData().AddArray(filled_array("HPair", boundary.GetNumberOfPoints(), 0.0, 2))
    boundary.GetPointData().AddArray(
        filled_array("HNaN", boundary.GetNumberOfPoints(), float("nan")))
    for name, association, fragment in (
            ("HCells", vtkDataObject.FIELD_ASSOCIATION_CELLS, "must have the association"),
            ("HPair", POINTS, "must have the association"),
            ("HNaN", POINTS, "The Laplacian array has %d NaN" % boundary.GetNumberOfPoints())):
        solver, catcher = biharmonic_solver(boundary)
        solver.SetInputArrayToProcess(1, 0, 0, association, name)
        solver.Update()
        assert fragment in catcher.error_text(), name


def poisson_with_source(source, array_name=None):
    solver = gridfree.vtkWalkOnSpheresSolver()
    catcher = MessageCatcher(solver, solver.GetExecutive())
    solver.SetBoundaryData(sphere_boundary(resolution=16))
    solver.SetProbeData(small_plane())
    solver.SetSourceData(source)
    solver.SetEquation(gridfree.vtkWalkOnSpheresSolver.POISSON)
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    if array_name:
        solver.SetInputArrayToProcess(2, 2, 0, POINTS, array_name)
    solver.SetWalksPerPoint(8)
    solver.Update()
    return solver, catcher


def test_source_array_with_wrong_components_or_nan():
    source = small_plane()
    source.GetPointData().AddArray(filled_array("Pair", source.GetNumberOfPoints(), 1.0, 2))
    _, catcher = poisson_with_source(source, "Pair")
    assert "the source array 'Pair' has 2 components; it needs 1 or as many as the boundary " \
        "values (1)" in catcher.error_text()
    source.GetPointData().AddArray(filled_array("NaN", source.GetNumberOfPoints(), float("nan")))
    _, catcher = poisson_with_source(source, "NaN")
    assert "the source array has NaN or infinite values" in catcher.error_text()


def test_polygons_of_a_polydata_source_are_ignored():
    """A vtkPolyData source gives point (vertex) and curve (line) sources;
    its polygons are reported, not used."""
    source = small_plane()  # 9 quads, no vertices or lines
    source.GetPointData().AddArray(filled_array("f", source.GetNumberOfPoints(), 1.0))
    _, catcher = poisson_with_source(source, "f")
    assert catcher.errors == []
    assert "Ignored 9 polygons of the Source input" in catcher.warning_text()


def test_expression_source_in_an_exterior_problem():
    """Walks from outside the boundary reach its exterior, where an expression
    source is cut off: the user is told."""
    solver = gridfree.vtkWalkOnSpheresSolver()
    catcher = MessageCatcher(solver, solver.GetExecutive())
    solver.SetBoundaryData(sphere_boundary(resolution=16))
    solver.SetProbeData(point_cloud([(2.0, 0.0, 0.0), (0.0, -3.0, 0.0)]))
    solver.SetEquation(gridfree.vtkWalkOnSpheresSolver.POISSON)
    solver.SetSourceExpression("1")
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
    solver.SetWalksPerPoint(16)
    solver.Update()
    assert "SourceExpression is taken as zero beyond a sphere" in catcher.warning_text()


def test_csg_operands_of_mixed_dimension_or_components():
    from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet
    from gridfree_testing import circle_boundary
    for second, fragment in (
            (circle_boundary(lambda x, y, z: x, sides=64), "The CSG operands mix 2D and 3D"),
            (sphere_boundary(lambda x, y, z: x, resolution=8), None)):
        blocks = vtkMultiBlockDataSet()
        blocks.SetBlock(0, sphere_boundary(resolution=16))
        if fragment is None:
            second.GetPointData().AddArray(filled_array("T", second.GetNumberOfPoints(), 0.5, 2))
            fragment = "every block needs the same number"
        blocks.SetBlock(1, second)
        solver = gridfree.vtkWalkOnSpheresSolver()
        catcher = MessageCatcher(solver, solver.GetExecutive())
        solver.SetInputData(0, blocks)
        solver.SetProbeData(small_plane())
        solver.SetCsgOperation(gridfree.vtkWalkOnSpheresSolver.CSG_UNION)
        solver.SetInputArrayToProcess(0, 0, 0, POINTS, "T")
        solver.SetWalksPerPoint(8)
        solver.Update()
        assert fragment in catcher.error_text(), catcher.error_text()


def test_zero_or_negative_epsilon():
    """The setter clamps a negative Epsilon to 0, and 0 is an error (a walk
    would never stop)."""
    for epsilon in (0.0, -1.0):
        _, catcher = solve(sphere_boundary(resolution=16), small_plane(), Epsilon=epsilon)
        assert "Epsilon must be positive" in catcher.error_text()
