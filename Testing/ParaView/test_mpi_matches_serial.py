"""Distributed runs: `mpirun -np 2 pvbatch` gives bit-identical arrays to a
serial pvbatch run on the same inputs (every probe point's walks depend on
the seed and its coordinates only). Runs solve_ct_slice_pieces.py both ways
and compares every point's arrays, matched by coordinates."""
import os
import subprocess
import sys
import tempfile

from vtkmodules.vtkIOXML import vtkXMLPImageDataReader

HERE = os.path.dirname(os.path.abspath(__file__))
PVBATCH, MPIRUN = sys.argv[1], sys.argv[2]
ARRAYS = ("T", "T_Variance", "T_Gradient", "WalkSteps")


def run(command, output):
    result = subprocess.run(command + [os.path.join(HERE, "solve_ct_slice_pieces.py"), output],
                            capture_output=True, text=True, timeout=600)
    assert result.returncode == 0 and os.path.exists(output), result.stdout + result.stderr
    print(result.stdout.strip().splitlines()[-1])


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


with tempfile.TemporaryDirectory() as folder:
    serial_path = os.path.join(folder, "serial.pvti")
    mpi_path = os.path.join(folder, "mpi.pvti")
    run([PVBATCH], serial_path)
    run([MPIRUN, "--oversubscribe", "-np", "2", PVBATCH], mpi_path)
    pieces = [name for name in os.listdir(os.path.join(folder, "mpi")) if name.endswith(".vti")]
    assert len(pieces) == 2, pieces  # each rank wrote its own piece
    serial, serial_count = point_values(serial_path)
    distributed, distributed_count = point_values(mpi_path)
    assert serial_count == distributed_count == 32 * 28, (serial_count, distributed_count)
    assert serial.keys() == distributed.keys()
    different = [p for p in serial if serial[p] != distributed[p]]
    assert not different, f"{len(different)} points differ, e.g. {different[0]}"
    print(f"ok: 2 ranks, {len(serial)} points, every array bit-identical to the serial run")
