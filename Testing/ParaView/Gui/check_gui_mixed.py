"""Checks the solve saved by mixed_conditions.xml: it is a walk-on-stars
solve (its field data has BackFaceHits and OutsidePoints, which only mixed
solves report), no probe point is outside or NaN, and the values stay
within those of the Dirichlet part, as the maximum principle says for a
harmonic function with an insulated part (g = x*y lies in [-0.5, 0.5]).

    python3 check_gui_mixed.py gui_mixed.vtp"""
import math
import sys

from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

reader = vtkXMLPolyDataReader()
reader.SetFileName(sys.argv[1])
reader.Update()
out = reader.GetOutput()
fd = out.GetFieldData()
assert fd.GetArray("BackFaceHits") is not None and fd.GetArray("OutsidePoints") is not None, \
    "not a mixed solve"
assert fd.GetArray("OutsidePoints").GetValue(0) == 0
assert fd.GetArray("BackFaceHits").GetValue(0) == 0
g = out.GetPointData().GetArray("g")
values = [g.GetValue(i) for i in range(g.GetNumberOfTuples())]
assert len(values) == 49 and not any(math.isnan(v) for v in values)
assert all(-0.5 - 0.05 <= v <= 0.5 + 0.05 for v in values), (min(values), max(values))
print("ok: Mixed Boundary Conditions by clicks solved with the surface's bc chosen for it "
      "(49 points, values in [%.3f, %.3f])" % (min(values), max(values)))
