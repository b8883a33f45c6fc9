"""Checks the solve saved by target_change.xml: the target tightened from
0.02 to 0.01 continued from the first solve's walks (field data WalksRun,
the walks the second solve ran, is less than TotalWalks, and
ResumedWalksPerPoint is positive), every point is at the new target, and
the numbers equal one Python solve with target 0.01, which they are only if
the continued points walked on exactly as a fresh solve's would.

    PYTHONPATH=BUILD/lib/python3.11/site-packages python3 check_gui_target_change.py gui_target.vtp"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from vtkmodules.vtkIOXML import vtkXMLPolyDataReader  # noqa: E402

from gui_scene import solver_on_the_scene  # noqa: E402

TARGET, MOST = 0.01, 4096
reader = vtkXMLPolyDataReader()
reader.SetFileName(sys.argv[1])
reader.Update()
saved = reader.GetOutput()
pd, fd = saved.GetPointData(), saved.GetFieldData()
n = saved.GetNumberOfPoints()
assert n == 49, n
run = fd.GetArray("WalksRun").GetValue(0)
total = fd.GetArray("TotalWalks").GetValue(0)
resumed = fd.GetArray("ResumedWalksPerPoint").GetValue(0)
assert resumed > 0 and run < total, (resumed, run, total)
worst_error = max(math.sqrt(pd.GetArray("g_Variance").GetValue(i)) for i in range(n))
assert worst_error <= TARGET, worst_error

solver = solver_on_the_scene()
solver.SetTargetStandardError(TARGET)
solver.SetWalksPerPoint(MOST)
solver.Update()
python = solver.GetOutput().GetPointData()
for name in ("g", "g_Variance", "WalkCount"):
    worst = max(abs(pd.GetArray(name).GetValue(i) - python.GetArray(name).GetValue(i))
                for i in range(n))
    assert worst == 0.0, (name, worst)
print("ok: the tighter target continued from the first solve (%d of %d walks run now) and "
      "equals one Python solve at 0.01" % (run, total))
