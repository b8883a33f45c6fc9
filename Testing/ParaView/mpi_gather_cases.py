"""Run under `mpirun -np 2 pvbatch --symmetric` (every rank runs the script):
the solver's gather of Boundary and
Source pieces, case by case, on data each rank builds itself. In every case
the distributed solver (vtkPWalkOnSpheresSolver with the global controller,
each rank holding only its own piece) must give, bit for bit, what a serial
solver (vtkWalkOnSpheresSolver) gives on the whole made locally from the same
pieces in rank order:

- a polygonal boundary split into halves;
- a CSG union of two spheres given as a multiblock, each block split;
- an unstructured-grid Poisson source split into halves;
- an image Poisson source split into blocks (its spacing exact to the bit);
- an image source split in blocks that leave a hole: every rank reports the
  error and none waits forever;
- a filter that runs its solver internally, executed on rank 0 alone, must
  not wait for rank 1 (its internal solver is a plain vtkWalkOnSpheresSolver).

Each rank's verdict is reduced over the ranks; rank 0 prints "ok" only when
every rank passed."""
import math
import sys
import traceback

import gridfree
from vtkmodules.vtkCommonCore import vtkCommand, vtkDoubleArray, vtkIdList, vtkIntArray, vtkPoints
from vtkmodules.vtkCommonDataModel import (vtkImageData, vtkMultiBlockDataSet, vtkPolyData,
                                           vtkUnstructuredGrid)
from vtkmodules.vtkFiltersCore import vtkAppendFilter, vtkAppendPolyData
from vtkmodules.vtkFiltersCore import vtkExtractCells
from vtkmodules.vtkFiltersSources import vtkLineSource, vtkSphereSource
from vtkmodules.vtkParallelCore import vtkCommunicator, vtkMultiProcessController
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.vtkConstants import VTK_STRING

controller = vtkMultiProcessController.GetGlobalController()
RANKS = controller.GetNumberOfProcesses()
RANK = controller.GetLocalProcessId()
POINTS = 0  # vtkDataObject.FIELD_ASSOCIATION_POINTS
Solver = gridfree.vtkWalkOnSpheresSolver
DistributedSolver = gridfree.vtkPWalkOnSpheresSolver


def sphere(center, radius):
    """A triangulated sphere with boundary values g = x*y + z."""
    source = vtkSphereSource()
    source.SetCenter(center)
    source.SetRadius(radius)
    source.SetThetaResolution(24)
    source.SetPhiResolution(16)
    source.Update()
    mesh = source.GetOutput()
    g = vtkDoubleArray()
    g.SetName("g")
    for i in range(mesh.GetNumberOfPoints()):
        x, y, z = mesh.GetPoint(i)
        g.InsertNextValue(x * y + z)
    mesh.GetPointData().AddArray(g)
    return mesh


def poly_piece(mesh, rank):
    """Cells [rank*n/R, (rank+1)*n/R) of a polygonal mesh, with their points."""
    n = mesh.GetNumberOfCells()
    ids = vtkIdList()
    for c in range(rank * n // RANKS, (rank + 1) * n // RANKS):
        ids.InsertNextId(c)
    piece = vtkPolyData()
    piece.Allocate(ids.GetNumberOfIds())
    piece.GetPointData().CopyAllocate(mesh.GetPointData())
    piece.GetCellData().CopyAllocate(mesh.GetCellData())
    piece.CopyCells(mesh, ids)
    return piece


def grid_piece(grid, rank):
    n = grid.GetNumberOfCells()
    extract = vtkExtractCells()
    extract.SetInputData(grid)
    ids = vtkIdList()
    for c in range(rank * n // RANKS, (rank + 1) * n // RANKS):
        ids.InsertNextId(c)
    extract.SetCellList(ids)
    extract.Update()
    return extract.GetOutput()


def append_polys(pieces):
    append = vtkAppendPolyData()
    for piece in pieces:
        append.AddInputData(piece)
    append.Update()
    return append.GetOutput()


def probe():
    """A few points inside the unit ball (every rank solves all of them)."""
    points = vtkPoints()
    for i in range(12):
        t = 0.35 * i / 11
        points.InsertNextPoint(t - 0.2, 0.5 * t, 0.1 - t)
    cloud = vtkPolyData()
    cloud.SetPoints(points)
    return cloud


def solver_on(boundary, source=None, distributed=True):
    # The distributed solver gathers; the plain one solves with what its
    # rank holds (here every rank holds the whole boundary).
    solver = DistributedSolver() if distributed else Solver()
    solver.SetBoundaryData(boundary)
    solver.SetProbeData(probe())
    solver.SetInputArrayToProcess(0, 0, 0, POINTS, "g")
    solver.SetWalksPerPoint(64)
    solver.SetSeed(3)
    solver.SetComputeGradient(True)
    if source is not None:
        solver.SetEquationToPoisson()
        solver.SetSourceData(source)
        solver.SetInputArrayToProcess(2, 2, 0, POINTS, "f")
    return solver


def arrays(solver):
    data = solver.GetOutput().GetPointData()
    out = []
    for name in ("g", "g_Variance", "g_Gradient"):
        array = data.GetArray(name)
        assert array is not None, name
        out.append([array.GetTuple(i) for i in range(array.GetNumberOfTuples())])
    return out


def field(solver, name):
    array = solver.GetOutput().GetFieldData().GetArray(name)
    return None if array is None else array.GetValue(0)


def check_same(distributed, serial, boundary_pieces, source_pieces):
    assert distributed.GetController() is controller
    assert field(distributed, "BoundaryPiecesGathered") == boundary_pieces, \
        field(distributed, "BoundaryPiecesGathered")
    assert field(distributed, "SourcePiecesGathered") == source_pieces, \
        field(distributed, "SourcePiecesGathered")
    assert field(serial, "BoundaryPiecesGathered") is None  # the plain solver never gathers
    mine, reference = arrays(distributed), arrays(serial)
    assert mine == reference, "the distributed solve differs from the serial one"
    assert all(math.isfinite(c) for row in mine[0] for c in row)


def case_polygonal_boundary():
    whole = sphere((0, 0, 0), 1.0)
    pieces = [poly_piece(whole, r) for r in range(RANKS)]
    distributed = solver_on(pieces[RANK])
    distributed.Update()
    serial = solver_on(append_polys(pieces), distributed=False)
    serial.Update()
    check_same(distributed, serial, RANKS, 0)
    return f"{pieces[RANK].GetNumberOfCells()} of {whole.GetNumberOfCells()} triangles held"


def case_csg_multiblock():
    spheres = [sphere((-0.3, 0, 0), 0.8), sphere((0.4, 0, 0), 0.7)]

    def blocks(parts):
        multiblock = vtkMultiBlockDataSet()
        for b, part in enumerate(parts):
            multiblock.SetBlock(b, part)
        return multiblock
    mine = blocks([poly_piece(s, RANK) for s in spheres])
    whole = blocks([append_polys([poly_piece(s, r) for r in range(RANKS)]) for s in spheres])
    distributed = solver_on(mine)
    distributed.SetCsgOperationToUnion()
    distributed.Update()
    serial = solver_on(whole, distributed=False)
    serial.SetCsgOperationToUnion()
    serial.Update()
    check_same(distributed, serial, RANKS, 0)
    return "union of two split spheres"


def case_unstructured_source():
    boundary = sphere((0, 0, 0), 1.0)
    image = vtkImageData()
    image.SetDimensions(9, 9, 9)
    image.SetOrigin(-1, -1, -1)
    image.SetSpacing(0.25, 0.25, 0.25)
    f = vtkDoubleArray()
    f.SetName("f")
    for i in range(image.GetNumberOfPoints()):
        x, y, z = image.GetPoint(i)
        f.InsertNextValue(1.0 + x - 0.5 * y * z)
    image.GetPointData().AddArray(f)
    to_grid = vtkAppendFilter()  # the image's voxels as an unstructured grid
    to_grid.AddInputData(image)
    to_grid.Update()
    grid = vtkUnstructuredGrid()
    grid.DeepCopy(to_grid.GetOutput())
    pieces = [grid_piece(grid, r) for r in range(RANKS)]
    whole = vtkAppendFilter()
    whole.MergePointsOff()
    for piece in pieces:
        whole.AddInputData(piece)
    whole.Update()
    distributed = solver_on(boundary, pieces[RANK])
    distributed.Update()
    serial = solver_on(boundary, whole.GetOutput(), distributed=False)
    serial.Update()
    check_same(distributed, serial, 1, RANKS)
    return f"{pieces[RANK].GetNumberOfCells()} of {grid.GetNumberOfCells()} source cells held"


def heat_image(extent):
    """An image source on a grid whose spacing has no short decimal form."""
    image = vtkImageData()
    image.SetExtent(extent)
    image.SetOrigin(-1.0 / 3, -1, -1)
    image.SetSpacing(2 / 7, 2 / 7, 1 / 3)
    f = vtkDoubleArray()
    f.SetName("f")
    for i in range(image.GetNumberOfPoints()):
        x, y, z = image.GetPoint(i)
        f.InsertNextValue(2.0 + x * y - z)
    image.GetPointData().AddArray(f)
    return image


def case_image_blocks():
    # Rank r holds the x-slab [4r, 4r+4] of a 0..8 image (the slabs share x = 4).
    mine = heat_image([4 * RANK, 4 * RANK + 4, 0, 7, 0, 6])
    distributed = solver_on(sphere((0, 0, 0), 1.0), mine)
    distributed.Update()
    serial = solver_on(sphere((0, 0, 0), 1.0), heat_image([0, 4 * RANKS, 0, 7, 0, 6]),
                       distributed=False)
    serial.Update()
    check_same(distributed, serial, 1, RANKS)
    return f"{mine.GetNumberOfPoints()} source voxels held"


def error_messages(algorithm):
    """The list the algorithm's error messages will be appended to."""
    messages = []

    @calldata_type(VTK_STRING)
    def on_error(caller, event, data):
        messages.append(data)
    algorithm.AddObserver(vtkCommand.ErrorEvent, on_error)
    return messages


def case_image_pieces_with_a_hole():
    # Rank r holds x-slab [4r, 4r+2] of a 0..7 image: x = 3 and x = 7 are missing.
    image = vtkImageData()
    image.SetExtent(4 * RANK, 4 * RANK + 2, 0, 7, 0, 7)
    image.SetOrigin(-1, -1, -1)
    image.SetSpacing(2 / 7, 2 / 7, 2 / 7)
    f = vtkDoubleArray()
    f.SetName("f")
    f.SetNumberOfTuples(image.GetNumberOfPoints())
    f.Fill(1.0)
    image.GetPointData().AddArray(f)
    solver = solver_on(sphere((0, 0, 0), 1.0), image)
    errors = error_messages(solver)
    solver.Update()
    assert any("leave holes" in m for m in errors), errors
    return "every rank refused the holes"


def case_stream_tracer_on_one_rank():
    if RANK != 0:
        return "rank 0 ran it alone"
    line = vtkLineSource()
    line.SetPoint1(-0.2, 0, 0)
    line.SetPoint2(0.2, 0, 0)
    line.SetResolution(1)
    tracer = gridfree.vtkWalkOnSpheresStreamTracer()
    tracer.SetBoundaryData(sphere((0, 0, 0), 1.0))
    tracer.SetSeedsConnection(line.GetOutputPort())
    tracer.SetInputArrayToProcess(0, 0, 0, POINTS, "g")
    tracer.SetWalksPerPoint(16)
    tracer.SetMaximumNumberOfSteps(5)
    # It builds its problem from its own whole inputs and never gathers: one
    # rank runs it while the others do not take part.
    tracer.Update()
    assert tracer.GetOutput().GetNumberOfPoints() > 0
    return "ran on rank 0 alone"


passed = 1
for case in (case_polygonal_boundary, case_csg_multiblock, case_unstructured_source,
             case_image_blocks, case_image_pieces_with_a_hole, case_stream_tracer_on_one_rank):
    try:
        print(f"rank {RANK}: {case.__name__}: {case()}", flush=True)
    except Exception:  # report, and let the other ranks finish the case
        traceback.print_exc()
        passed = 0
verdicts = vtkIntArray()
verdicts.SetNumberOfTuples(1)
total = vtkIntArray()
verdicts.SetValue(0, passed)
controller.AllReduce(verdicts, total, vtkCommunicator.SUM_OP)
if RANKS == 2 and total.GetValue(0) == RANKS and RANK == 0:
    print(f"ok: {RANKS} ranks gathered polygonal, CSG, unstructured and image pieces, "
          "refused holes, and ran an internal solver on one rank")
sys.stdout.flush()
