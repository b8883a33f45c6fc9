"""Checks the solve saved by source_after_creation.xml against the same
problem solved from Python with the Source Array chosen by hand (RTData of
the Heat volume): same seed, same walks, so the same numbers, which they are
only if the GUI's Source Array followed the Source input connected after the
solver was created.

    PYTHONPATH=BUILD/lib/python3.11/site-packages python3 check_gui_source.py gui_source.vtp"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from vtkmodules.vtkCommonDataModel import vtkDataObject  # noqa: E402
from vtkmodules.vtkImagingCore import vtkRTAnalyticSource  # noqa: E402
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader  # noqa: E402

from gui_scene import solver_on_the_scene  # noqa: E402

reader = vtkXMLPolyDataReader()
reader.SetFileName(sys.argv[1])
reader.Update()
gui = reader.GetOutput().GetPointData().GetArray("g")

solver = solver_on_the_scene()
heat = vtkRTAnalyticSource()
solver.SetSourceConnection(heat.GetOutputPort())
solver.SetInputArrayToProcess(2, 2, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS, "RTData")
solver.SetEquation(1)
solver.Update()
python = solver.GetOutput().GetPointData().GetArray("g")
assert gui is not None and gui.GetNumberOfTuples() == python.GetNumberOfTuples() == 49
worst = max(abs(gui.GetValue(i) - python.GetValue(i)) for i in range(49))
assert worst < 1e-12, worst
print("ok: the GUI's Poisson solve with the Source connected afterwards equals the "
      "Python solve with RTData as Source Array (49 points, largest difference %.1e)" % worst)
