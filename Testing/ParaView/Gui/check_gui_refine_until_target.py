"""Checks the solve saved by refine_until_target.xml: every point's standard
error is at most the target (0.005), Refine Until Target took more than the
first round's 128 walks where needed, and the numbers equal one Python solve
with the final maximum and the same target, which they are only if each
round kept the points that had reached the target and continued the others
exactly.

    PYTHONPATH=BUILD/lib/python3.11/site-packages python3 check_gui_refine_until_target.py \
        gui_refine.vtp WALKS"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from vtkmodules.vtkIOXML import vtkXMLPolyDataReader  # noqa: E402

from gui_scene import solver_on_the_scene  # noqa: E402

TARGET = 0.005
walks = int(sys.argv[2])

reader = vtkXMLPolyDataReader()
reader.SetFileName(sys.argv[1])
reader.Update()
saved = reader.GetOutput()
gui = saved.GetPointData().GetArray("g")
gui_variance = saved.GetPointData().GetArray("g_Variance")
gui_count = saved.GetPointData().GetArray("WalkCount")
assert gui is not None and gui_variance is not None and gui_count is not None
n = gui.GetNumberOfTuples()
assert n == 49, n
worst_error = max(math.sqrt(gui_variance.GetValue(i)) for i in range(n))
assert worst_error <= TARGET, worst_error
counts = [int(gui_count.GetValue(i)) for i in range(n)]
assert max(counts) > 128 and max(counts) <= walks, (max(counts), walks)

solver = solver_on_the_scene()
solver.SetTargetStandardError(TARGET)
solver.SetWalksPerPoint(walks)
solver.Update()
assert solver.GetLastPointsShortOfTarget() == 0
out = solver.GetOutput().GetPointData()
python = out.GetArray("g")
python_count = out.GetArray("WalkCount")
worst = max(abs(gui.GetValue(i) - python.GetValue(i)) for i in range(n))
assert worst == 0.0, worst
assert all(counts[i] == python_count.GetValue(i) for i in range(n))
print("ok: Refine Until Target in the GUI reached the target 0.005 at every point "
      "(largest standard error %.4f, %d to %d walks per point, at most %d) and equals "
      "one Python solve with that maximum" % (worst_error, min(counts), max(counts), walks))
