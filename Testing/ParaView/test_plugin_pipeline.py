"""pvbatch: the GridFree plugin is loaded, its filter runs in a ParaView
pipeline with the boundary array chosen as in the GUI, and the arrays it
produces are right."""
import math
import sys

import paraview.simple as pvs
from paraview import servermanager

if not hasattr(pvs, "WalkOnSpheresSolver"):
    sys.exit("GridFree plugin not loaded (PV_PLUGIN_PATH)")

sphere = pvs.Sphere(Radius=1.0, ThetaResolution=96, PhiResolution=96)
boundary = pvs.Calculator(Input=sphere, ResultArrayName="T",
                          Function="coordsX*coordsX - coordsY*coordsY")
probe = pvs.Plane(Origin=[-0.5, -0.5, 0.25], Point1=[0.5, -0.5, 0.25],
                  Point2=[-0.5, 0.5, 0.25], XResolution=9, YResolution=9)
solver = pvs.WalkOnSpheresSolver(Boundary=boundary, Probe=probe)
solver.BoundaryValues = ["POINTS", "T"]
solver.WalksPerPoint = 256
solver.Seed = 5
solver.UpdatePipeline()

# Defaults and labels as documented.
proxy = servermanager.ProxyManager().GetPrototypeProxy("filters", "WalkOnSpheresSolver")
assert proxy.GetXMLLabel() == "Walk On Spheres Solver", proxy.GetXMLLabel()
fresh = pvs.WalkOnSpheresSolver(Boundary=boundary, Probe=probe)
assert fresh.WalksPerPoint == 128
assert abs(fresh.Epsilon - 1e-4) < 1e-16
assert fresh.EpsilonIsRelative == 1
assert fresh.NumberOfThreads == 0
pvs.Delete(fresh)

info = solver.GetDataInformation()
assert info.GetNumberOfPoints() == 100, info.GetNumberOfPoints()
names = [solver.PointData.keys()][0]
for name in ("T", "T_Variance", "WalkSteps", "EscapedFraction", "TruncatedFraction", "Normals"):
    assert name in names, (name, names)
assert solver.FieldData["TotalWalks"].GetRange()[0] == 25600

data = servermanager.Fetch(solver)
t = data.GetPointData().GetArray("T")
var = data.GetPointData().GetArray("T_Variance")
worst = 0.0
for i in range(data.GetNumberOfPoints()):
    x, y, _ = data.GetPoint(i)
    z = (t.GetTuple1(i) - (x * x - y * y)) / math.sqrt(var.GetTuple1(i))
    worst = max(worst, abs(z))
assert worst < 5.0, worst
assert data.GetPointData().GetScalars().GetName() == "T"
print("ok: plugin filter ran, max |z| = %.2f" % worst)
