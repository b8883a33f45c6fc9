"""Run by `paraview --script` before two_selected.xml: the scene of
solver_setup.py with both the surface and the plane selected in the Pipeline
Browser (as with a Ctrl-click), the way a user picks a boundary and a probe
before choosing the solver."""
import os

import paraview.simple as pvs
from paraview import servermanager

here = os.environ["GRIDFREE_GUI_TEST_DIR"]
with open(os.path.join(here, "solver_setup.py"), encoding="utf-8") as f:
    exec(compile(f.read(), "solver_setup.py", "exec"))

selection = servermanager.vtkSMProxyManager.GetProxyManager() \
    .GetActiveSessionProxyManager().GetSelectionModel("ActiveSources")
CLEAR_AND_SELECT, SELECT = 3, 2
selection.Select(pvs.FindSource("Surface").SMProxy, CLEAR_AND_SELECT)
selection.Select(pvs.FindSource("Plane").SMProxy, SELECT)
