"""Run inside the ParaView GUI (`paraview --script=gui_ct_workflow.py --exit`
under xvfb): the CT workflow as a user opens it, through the GUI's own
Python, then a dragged slice re-applied.

Executes Documentation/Examples/ct_workflow.py as ParaView runs a macro or a
--script (no command-line arguments, no __file__: the data folder comes from
GRIDFREE_DATA), then checks that the pipeline is in the Pipeline Browser
with the Slice selected (its plane widget ready to drag), that the view
shows the solver's output, and that moving the Slice and updating gives the
solver's points the new height. Prints a line the test matches."""
import os

import paraview.simple as pvs
from paraview import servermanager

script = os.path.join(os.environ["GRIDFREE_SOURCE_DIR"], "Documentation", "Examples",
                      "ct_workflow.py")
with open(script, encoding="utf-8") as f:
    exec(compile(f.read(), script, "exec"), {"__name__": "__main__"})

names = {key[0] for key in pvs.GetSources()}
for expected in ("CT volume", "Skin (boundary)", "Slice (the probe)", "Walk On Spheres Solver",
                 "Streamlines of T_Gradient", "Arrows of T_Gradient"):
    assert expected in names, (expected, sorted(names))
active = pvs.GetActiveSource()
assert active.GetXMLName() == "Cut", active.GetXMLName()  # the Slice filter
solver = pvs.FindSource("Walk On Spheres Solver")
view = pvs.GetActiveView()
assert pvs.GetDisplayProperties(solver, view).Visibility == 1

# Drag the plane to z = 40 and apply.
active.SliceType.Origin = [active.SliceType.Origin[0], active.SliceType.Origin[1], 40.0]
pvs.Render(view)
bounds = solver.GetDataInformation().GetBounds()
assert abs(bounds[4] - 40.0) < 1e-9 and abs(bounds[5] - 40.0) < 1e-9, bounds
moved = servermanager.Fetch(solver)
assert moved.GetPointData().GetArray("T_Gradient") is not None
print("ok: CT workflow in the GUI: %d sources, the slice moved to z = 40 with %d solved points"
      % (len(names), moved.GetNumberOfPoints()))
