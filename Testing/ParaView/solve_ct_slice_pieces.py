"""pvbatch script of the distributed-run test: the Walk On Spheres Solver on
the CT skin, probed on an image of a slice, saved as a .pvti (one piece per
rank). Run serially and under `mpirun -np N pvbatch`: every rank reads the
whole boundary and solves its own piece of the image."""
import os
import sys

import paraview.simple as pvs
from vtkmodules.vtkParallelCore import vtkMultiProcessController

if not hasattr(pvs, "WalkOnSpheresSolver"):
    sys.exit("GridFree plugin not loaded (PV_PLUGIN_PATH)")
output = sys.argv[1]
walks = int(sys.argv[2]) if len(sys.argv) > 2 else 16  # more for a timing
skin = pvs.XMLPolyDataReader(FileName=[os.path.join(os.environ["GRIDFREE_DATA"],
                                                    "headsq_skin_iso500_closed.vtp")])
boundary = pvs.Calculator(Input=skin, ResultArrayName="T",
                          Function="sin(coordsX/20)*cos(coordsY/30) + coordsZ/100")
# An image of 32 x 28 points, 1 mm apart, in the slice z = 70 inside the
# head, split among the ranks by extent.
grid = pvs.FastUniformGrid(WholeExtent=[60, 91, 80, 107, 70, 70])
solver = pvs.WalkOnSpheresSolver(Boundary=boundary, Probe=grid)
solver.BoundaryValues = ["POINTS", "T"]
solver.WalksPerPoint = walks
solver.Seed = 7
solver.ComputeGradient = 1
solver.UpdatePipeline()
pvs.SaveData(output, proxy=solver,
             PointDataArrays=["T", "T_Variance", "T_Gradient", "WalkSteps"])
ranks = vtkMultiProcessController.GetGlobalController().GetNumberOfProcesses()
seconds = solver.FieldData["SolveSeconds"].GetRange()[1]
print(f"wrote {output} from {ranks} rank(s), "
      f"{solver.GetDataInformation().GetNumberOfPoints()} points, "
      f"slowest rank's solve {seconds:.2f} s")
