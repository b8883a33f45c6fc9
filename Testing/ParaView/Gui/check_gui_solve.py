"""Checks the solve saved by solver_from_menu.xml: the Plane's 7 x 7 points
solved on the Surface (u = x*y, harmonic, so the exact solution inside the
sphere), with the walks of a 256-walk solve refined once (512 per point,
256 resumed), every point within 5 standard errors of x*y and the variance
agreeing with the observed spread.

    python3 check_gui_solve.py gui_solve.vtp [WALKS RESUMED]

(WALKS and RESUMED per point, 512 and 256 by default: solver_from_menu.xml's
256 walks refined once; two_selected.xml's single solve has 128 and 0.)"""
import math
import sys

from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

reader = vtkXMLPolyDataReader()
reader.SetFileName(sys.argv[1])
reader.Update()
out = reader.GetOutput()
pd, fd = out.GetPointData(), out.GetFieldData()
assert out.GetNumberOfPoints() == 49, out.GetNumberOfPoints()
mean, variance = pd.GetArray("g"), pd.GetArray("g_Variance")
assert mean is not None and variance is not None, [pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays())]
total = fd.GetArray("TotalWalks").GetValue(0)
resumed = fd.GetArray("ResumedWalksPerPoint").GetValue(0)
want_walks, want_resumed = (int(a) for a in sys.argv[2:4]) if len(sys.argv) > 3 else (512, 256)
assert total == 49 * want_walks and resumed == want_resumed, (total, resumed)
z = []
for i in range(out.GetNumberOfPoints()):
    x, y, _ = out.GetPoint(i)
    z.append((mean.GetValue(i) - x * y) / math.sqrt(variance.GetValue(i)))
worst = max(abs(v) for v in z)
mean_z2 = sum(v * v for v in z) / len(z)
assert worst < 5.0, worst
assert 0.5 < mean_z2 < 1.6, mean_z2
print("ok: the GUI's solve: 49 points, %d walks each (%d resumed), max |z| %.2f, mean z^2 %.2f"
      % (want_walks, want_resumed, worst, mean_z2))
