"""GridFree: grid-free Monte Carlo PDE solvers (walk on spheres) for VTK.

Usage::

    import gridfree
    solver = gridfree.vtkWalkOnSpheresSolver()
    solver.SetInputConnection(0, boundary.GetOutputPort())  # vtkPolyData with values
    solver.SetInputConnection(1, probe.GetOutputPort())     # any vtkDataSet
"""
from .GridFreeFilters import *  # noqa: F401,F403

__all__ = [name for name in dir() if name.startswith("vtk")]
