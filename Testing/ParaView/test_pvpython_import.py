"""pvpython: `import gridfree` works next to the loaded plugin (one library,
one VTK), and the class is usable both directly and through paraview.simple."""
import sys

import gridfree
import paraview.simple as pvs
from vtkmodules.vtkFiltersSources import vtkPlaneSource, vtkSphereSource

assert hasattr(pvs, "WalkOnSpheresSolver"), "plugin not loaded"

solver = gridfree.vtkWalkOnSpheresSolver()
sphere = vtkSphereSource()
sphere.SetRadius(1.0)
sphere.Update()
boundary = sphere.GetOutput()
boundary.GetPointData().SetActiveScalars("Normals")  # 3 components: solve all three
plane = vtkPlaneSource()
plane.SetResolution(2, 2)
solver.SetBoundaryData(boundary)
solver.SetProbeConnection(plane.GetOutputPort())
solver.SetWalksPerPoint(16)
solver.Update()
# The plane keeps its own Normals; the solution is Normals_Solution.
out = solver.GetOutput().GetPointData().GetArray("Normals_Solution")
assert out is not None and out.GetNumberOfComponents() == 3 and out.GetNumberOfTuples() == 9

# The server-side object of the plugin's proxy is the same class.
proxy = pvs.WalkOnSpheresSolver(Boundary=pvs.Sphere(), Probe=pvs.Plane())
assert proxy.GetClientSideObject().IsA("vtkWalkOnSpheresSolver")
assert isinstance(proxy.GetClientSideObject(), gridfree.vtkWalkOnSpheresSolver)
print("ok:", sys.version.split()[0], gridfree.vtkWalkOnSpheresSolver.__module__)
