"""pvbatch: Poisson on the CT skin mesh with the CT volume itself as the source
term, chosen as in the GUI (Source input + Source Array), on a slice probe.

With u = 0 on the skin and f = CT intensity / 1000 >= 0, the solution of
Δu = f is <= 0 everywhere (maximum principle), strictly negative inside the
head, and the Laplace solve with the same inputs gives 0."""
import math
import os
import sys

import paraview.simple as pvs
from paraview import servermanager

if not hasattr(pvs, "WalkOnSpheresSolver"):
    sys.exit("GridFree plugin not loaded (PV_PLUGIN_PATH)")

data = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "..", "Data")
volume = pvs.OpenDataFile(os.path.join(data, "headsq_headCT.mhd"))
density = pvs.Calculator(Input=volume, ResultArrayName="f", Function="MetaImage/1000")
skin = pvs.XMLPolyDataReader(FileName=[os.path.join(data, "headsq_skin_iso500_closed.vtp")])
boundary = pvs.Calculator(Input=skin, ResultArrayName="T", Function="0")
probe = pvs.Plane(Origin=[20, 20, 70], Point1=[180, 20, 70], Point2=[20, 180, 70],
                  XResolution=12, YResolution=12)

solver = pvs.WalkOnSpheresSolver(Boundary=boundary, Probe=probe, Source=density)
solver.BoundaryValues = ["POINTS", "T"]
solver.Equation = "Poisson"
solver.SourceArray = ["POINTS", "f"]
solver.SourceSampling = "Multiple Importance"
solver.WalksPerPoint = 64
solver.Seed = 3
solver.UpdatePipeline()

result = servermanager.Fetch(solver)
t = result.GetPointData().GetArray("T")
var = result.GetPointData().GetArray("T_Variance")
assert t is not None and var is not None
negative = 0
for i in range(result.GetNumberOfPoints()):
    value, sigma = t.GetTuple1(i), math.sqrt(var.GetTuple1(i))
    assert math.isfinite(value), i
    assert value <= 5.0 * sigma + 1e-12, (i, value, sigma)  # maximum principle
    negative += value < -5.0 * sigma
assert negative > 20, negative  # the head's interior sees the source
assert solver.FieldData["TotalWalks"].GetRange()[0] == 64 * 169

# The source enters only the Poisson-type equations.
solver.Equation = "Laplace"
solver.UpdatePipeline()
laplace = servermanager.Fetch(solver).GetPointData().GetArray("T")
assert all(laplace.GetTuple1(i) == 0.0 for i in range(laplace.GetNumberOfTuples()))
print("ok: CT-sourced Poisson on the CT mesh, %d of %d slice points below zero"
      % (negative, result.GetNumberOfPoints()))
