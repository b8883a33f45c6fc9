"""Distributed runs: `mpirun -np 2 pvbatch` gives bit-identical arrays to a
serial pvbatch run on the same inputs (every probe point's walks depend on
the seed and its coordinates only), with the boundary and the source really
split between the ranks and gathered by the solver. Runs
solve_ct_slice_pieces.py both ways on three inputs and compares every
point's arrays, matched by coordinates:

- the skin as a .pvtp of two pieces and the CT volume as a .vti Poisson
  source: each rank reads half the triangles and half the voxels, and the
  solver gathers two pieces of each;
- the skin as one .vtp: rank 0 reads it, rank 1 gets nothing, one piece is
  gathered;
- the skin as a legacy .vtk, which ignores piece requests: both ranks read
  the whole skin, and the copy is counted once;
- the first case again, with pvpython driving a pvserver of two ranks
  (client-server, as the ParaView GUI connects to a cluster)."""
import os
import re
import socket
import subprocess
import sys
import tempfile
import time

from vtkmodules.vtkFiltersParallel import vtkExtractPolyDataPiece
from vtkmodules.vtkIOImage import vtkMetaImageReader
from vtkmodules.vtkIOLegacy import vtkPolyDataWriter
from vtkmodules.vtkIOParallelXML import vtkXMLPPolyDataWriter
from vtkmodules.vtkIOXML import (vtkXMLImageDataWriter, vtkXMLPImageDataReader,
                                 vtkXMLPolyDataReader)

HERE = os.path.dirname(os.path.abspath(__file__))
PVBATCH, MPIRUN, PVPYTHON, PVSERVER = sys.argv[1:5]
DATA = os.environ["GRIDFREE_DATA"]
ARRAYS = ("T", "T_Variance", "T_Gradient", "WalkSteps")


def run(command, output, options):
    """Runs the script; returns its last line (with the gathered counts)."""
    result = subprocess.run(
        command + [os.path.join(HERE, "solve_ct_slice_pieces.py"), output] + options,
        capture_output=True, text=True, timeout=600)
    assert result.returncode == 0 and os.path.exists(output), result.stdout + result.stderr
    last = result.stdout.strip().splitlines()[-1]
    print(last)
    return last


def point_values(path):
    """{coordinates: all arrays' numbers} and the number of points read."""
    reader = vtkXMLPImageDataReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    data = image.GetPointData()
    values = {}
    for i in range(image.GetNumberOfPoints()):
        values[image.GetPoint(i)] = tuple(
            c for name in ARRAYS for c in data.GetArray(name).GetTuple(i))
    return values, image.GetNumberOfPoints()


def write_inputs(folder):
    """The skin as a two-piece .pvtp and as a legacy .vtk; the CT volume as a .vti."""
    skin = vtkXMLPolyDataReader()
    skin.SetFileName(os.path.join(DATA, "headsq_skin_iso500_closed.vtp"))
    split = vtkExtractPolyDataPiece()
    split.SetInputConnection(skin.GetOutputPort())
    split.CreateGhostCellsOff()
    pieces = vtkXMLPPolyDataWriter()
    pieces.SetInputConnection(split.GetOutputPort())
    pieces.SetFileName(os.path.join(folder, "skin.pvtp"))
    pieces.SetNumberOfPieces(2)
    pieces.SetStartPiece(0)
    pieces.SetEndPiece(1)
    assert pieces.Write() == 1
    legacy = vtkPolyDataWriter()
    legacy.SetInputConnection(skin.GetOutputPort())
    legacy.SetFileTypeToBinary()
    legacy.SetFileName(os.path.join(folder, "skin.vtk"))
    assert legacy.Write() == 1
    # (VTK 9.2's MetaImage reader cannot read a block of the volume, which
    # ranks ask for: the XML image reader can.)
    volume = vtkMetaImageReader()
    volume.SetFileName(os.path.join(DATA, "headsq_headCT.mhd"))
    image = vtkXMLImageDataWriter()
    image.SetInputConnection(volume.GetOutputPort())
    image.SetFileName(os.path.join(folder, "headsq_headCT.vti"))
    assert image.Write() == 1


def free_port():
    with socket.socket() as s:
        s.bind(("localhost", 0))
        return s.getsockname()[1]


def run_on_pvserver(output, options):
    """Starts `mpirun -np 2 pvserver`, runs the script in pvpython connected to it."""
    port = free_port()
    server = subprocess.Popen([MPIRUN, "--oversubscribe", "-np", "2", PVSERVER,
                               f"--server-port={port}"],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        deadline = time.time() + 60
        for line in server.stdout:  # wait until the server listens
            if "Accepting connection" in line or time.time() > deadline:
                break
        return run([PVPYTHON], output, options + ["--connect", f"localhost:{port}"])
    finally:
        try:
            server.wait(timeout=30)  # the server exits when its client leaves
        except subprocess.TimeoutExpired:
            server.kill()


def compare(folder, name, options, boundary_pieces, source_pieces, pvserver=False):
    serial_path = os.path.join(folder, f"{name}_serial.pvti")
    mpi_path = os.path.join(folder, f"{name}_mpi.pvti")
    run([PVBATCH], serial_path, options)
    if pvserver:
        last = run_on_pvserver(mpi_path, options)
    else:
        last = run([MPIRUN, "--oversubscribe", "-np", "2", PVBATCH], mpi_path, options)
    gathered = re.search(r"boundary pieces gathered: (\d+), source pieces gathered: (\d+)", last)
    assert gathered, last
    assert (int(gathered.group(1)), int(gathered.group(2))) == (boundary_pieces, source_pieces), \
        (name, last)
    pieces = [n for n in os.listdir(os.path.join(folder, f"{name}_mpi")) if n.endswith(".vti")]
    assert len(pieces) == 2, pieces  # each rank wrote its own piece of the probe
    serial, serial_count = point_values(serial_path)
    distributed, distributed_count = point_values(mpi_path)
    assert serial_count == distributed_count == 32 * 28, (serial_count, distributed_count)
    assert serial.keys() == distributed.keys()
    different = [p for p in serial if serial[p] != distributed[p]]
    assert not different, f"{name}: {len(different)} points differ, e.g. {different[0]}"
    print(f"{name}: {len(serial)} points, every array bit-identical to the serial run, "
          f"{boundary_pieces} boundary and {source_pieces} source pieces gathered")


with tempfile.TemporaryDirectory() as folder:
    write_inputs(folder)
    split = ["--boundary", os.path.join(folder, "skin.pvtp"),
             "--source", os.path.join(folder, "headsq_headCT.vti")]
    compare(folder, "split", split, 2, 2)
    compare(folder, "pvserver_split", split, 2, 2, pvserver=True)
    compare(folder, "single_piece", [], 1, 0)
    compare(folder, "every_rank_whole", ["--boundary", os.path.join(folder, "skin.vtk")], 1, 0)
    print("ok: 2 ranks (pvbatch and pvserver), boundary and source gathered, "
          "every array bit-identical")
