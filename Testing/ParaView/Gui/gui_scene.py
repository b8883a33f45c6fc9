"""The scene of solver_setup.py rebuilt in plain VTK, for the checks that
compare a GUI solve with the same solve from Python: a solver with the unit
sphere carrying g = x*y as Boundary (its array g selected) and the Plane's
7 x 7 points as Probe."""
import gridfree
from vtkmodules.vtkCommonDataModel import vtkDataObject
from vtkmodules.vtkFiltersCore import vtkArrayCalculator
from vtkmodules.vtkFiltersSources import vtkPlaneSource, vtkSphereSource


def solver_on_the_scene():
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
    solver.SetInputArrayToProcess(0, 0, 0, vtkDataObject.FIELD_ASSOCIATION_POINTS, "g")
    # The inputs stay alive with the solver (VTK holds the connections).
    return solver
