"""Checks the solve saved by source_after_creation.xml against the same
problem solved from Python with the Source Array chosen by hand (RTData of
the Heat volume): same seed, same walks, so the same numbers, which they are
only if the GUI's Source Array followed the Source input connected after the
solver was created.

    PYTHONPATH=BUILD/lib/python3.11/site-packages python3 check_gui_source.py gui_source.vtp"""
import sys

import gridfree
from vtkmodules.vtkCommonDataModel import vtkDataObject
from vtkmodules.vtkFiltersCore import vtkArrayCalculator
from vtkmodules.vtkFiltersSources import vtkPlaneSource, vtkSphereSource
from vtkmodules.vtkImagingCore import vtkRTAnalyticSource
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

reader = vtkXMLPolyDataReader()
reader.SetFileName(sys.argv[1])
reader.Update()
gui = reader.GetOutput().GetPointData().GetArray("g")

sphere = vtkSphereSource()
sphere.SetRadius(1.0)
sphere.SetThetaResolution(48)
sphere.SetPhiResolution(48)
surface = vtkArrayCalculator()
surface.SetInputConnection(sphere.GetOutputPort())
surface.AddCoordinateScalarVariable("coordsX", 0)
surface.AddCoordinateScalarVariable("coordsY", 1)
surface.SetFunction("coordsX*coordsY")
surface.SetResultArrayName("g")
plane = vtkPlaneSource()
plane.SetOrigin(-0.4, -0.4, 0.0)
plane.SetPoint1(0.4, -0.4, 0.0)
plane.SetPoint2(-0.4, 0.4, 0.0)
plane.SetResolution(6, 6)
solver = gridfree.vtkWalkOnSpheresSolver()
solver.SetBoundaryConnection(surface.GetOutputPort())
solver.SetProbeConnection(plane.GetOutputPort())
heat = vtkRTAnalyticSource()
solver.SetSourceConnection(heat.GetOutputPort())
solver.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS, "g")
solver.SetInputArrayToProcess(2, 2, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS, "RTData")
solver.SetEquation(1)
solver.Update()
python = solver.GetOutput().GetPointData().GetArray("g")
assert gui is not None and gui.GetNumberOfTuples() == python.GetNumberOfTuples() == 49
worst = max(abs(gui.GetValue(i) - python.GetValue(i)) for i in range(49))
assert worst < 1e-12, worst
print("ok: the GUI's Poisson solve with the Source connected afterwards equals the "
      "Python solve with RTData as Source Array (49 points, largest difference %.1e)" % worst)
