"""pvbatch script of the distributed-run test: the Walk On Spheres Solver on
the CT skin, probed on an image of a slice, saved as a .pvti (one piece per
rank). Run serially and under `mpirun -np N pvbatch`: each rank reads its own
piece of the boundary (and of the source), the solver gathers the whole to
every rank, and each rank solves its own piece of the image. With --connect
the same pipeline runs on a pvserver's ranks.

    solve_ct_slice_pieces.py OUTPUT.pvti [--boundary FILE] [--source FILE]
                             [--walks N] [--connect HOST:PORT]

--boundary: the skin to read (default the bundled .vtp; a .pvtp is read piece
by piece, a legacy .vtk whole by every rank). --source: the Poisson equation
with this CT volume (a .vti, read in blocks) as the source."""
import argparse
import os
import sys

import paraview.simple as pvs

if not hasattr(pvs, "WalkOnSpheresSolver"):
    sys.exit("GridFree plugin not loaded (PV_PLUGIN_PATH)")
data = os.environ["GRIDFREE_DATA"]
parser = argparse.ArgumentParser()
parser.add_argument("output")
parser.add_argument("--boundary", default=os.path.join(data, "headsq_skin_iso500_closed.vtp"))
parser.add_argument("--source")
parser.add_argument("--walks", type=int, default=16)  # more for a timing
parser.add_argument("--connect", metavar="HOST:PORT",
                    help="run the pipeline on this pvserver (its ranks solve)")
args = parser.parse_args()
if args.connect:
    host, port = args.connect.rsplit(":", 1)
    pvs.Connect(host, int(port))

skin = pvs.OpenDataFile(args.boundary)
boundary = pvs.Calculator(Input=skin, ResultArrayName="T",
                          Function="sin(coordsX/20)*cos(coordsY/30) + coordsZ/100")
# An image of 32 x 28 points, 1 mm apart, in the slice z = 70 inside the
# head, split among the ranks by extent.
grid = pvs.FastUniformGrid(WholeExtent=[60, 91, 80, 107, 70, 70])
solver = pvs.WalkOnSpheresSolver(Boundary=boundary, Probe=grid)
solver.BoundaryValues = ["POINTS", "T"]
solver.WalksPerPoint = args.walks
solver.Seed = 7
solver.ComputeGradient = 1
if args.source:
    volume = pvs.OpenDataFile(args.source)
    heat = pvs.Calculator(Input=volume, ResultArrayName="f", Function="-2e-5*MetaImage")  # the volume itself heats
    solver.Equation = "Poisson"
    solver.Source = heat
    solver.SourceArray = ["POINTS", "f"]
solver.UpdatePipeline()
pvs.SaveData(args.output, proxy=solver,
             PointDataArrays=["T", "T_Variance", "T_Gradient", "WalkSteps"])
ranks = pvs.servermanager.ActiveConnection.GetNumberOfDataPartitions()
fields = solver.FieldData
seconds = fields["SolveSeconds"].GetRange()[1]
gathered = "boundary pieces gathered: serial"
if "BoundaryPiecesGathered" in fields.keys():
    gathered = (f"boundary pieces gathered: {fields['BoundaryPiecesGathered'].GetRange()[1]:.0f}"
                f", source pieces gathered: {fields['SourcePiecesGathered'].GetRange()[1]:.0f}")
print(f"wrote {args.output} from {ranks} rank(s), "
      f"{solver.GetDataInformation().GetNumberOfPoints()} points, "
      f"slowest rank's solve {seconds:.2f} s, {gathered}")
