"""Run by `paraview --script` before Gui/cache_moved_slice.xml: a sphere of
radius 8 carrying g = x*y (harmonic), a Slice of a Wavelet volume through it
at z = 0 as the probe, and the solver with the Sphere Cache estimator,
applied and shown, with the Slice selected (as a user who is about to move
it), or the solver (GRIDFREE_GUI_SELECT=Solver, for cache_refine.xml). An observer on the solver's server-side object appends one line per
execution to the file GRIDFREE_GUI_LOG names: the slice's height and the
cache's field data (CacheWalks held, CacheWalksRun in this execution), which
check_gui_cache.py reads to tell whether the moved slice was answered from
the same cache."""
import os

import paraview.simple as pvs

sphere = pvs.Sphere(registrationName="Sphere", Radius=8.0, ThetaResolution=48,
                    PhiResolution=48)
surface = pvs.Calculator(registrationName="Surface", Input=sphere, ResultArrayName="g",
                         Function="coordsX*coordsY")
volume = pvs.Wavelet(registrationName="Volume")
cut = pvs.Slice(registrationName="Slice", Input=volume)
cut.SliceType = "Plane"
cut.SliceType.Origin = [0.0, 0.0, 0.0]
cut.SliceType.Normal = [0.0, 0.0, 1.0]
surface.UpdatePipeline()
cut.UpdatePipeline()
solver = pvs.WalkOnSpheresSolver(registrationName="Solver", Boundary=surface, Probe=cut)
solver.BoundaryValues = ["POINTS", "g"]
solver.Estimator = "Sphere Cache"
solver.WalksPerSphere = 32
solver.WalksPerPoint = 32

log = os.environ["GRIDFREE_GUI_LOG"]
if os.path.exists(log):
    os.remove(log)


def record(algorithm, event):
    out = algorithm.GetOutputDataObject(0)
    fd = out.GetFieldData()

    def field(name):
        array = fd.GetArray(name)
        return array.GetTuple1(0) if array else -1.0
    z = out.GetPoint(0)[2] if out.GetNumberOfPoints() else float("nan")
    with open(log, "a", encoding="utf-8") as f:
        f.write("z=%g points_from_cache=%d cache_walks=%d cache_walks_run=%d\n"
                % (z, field("PointsFromCache"), field("CacheWalks"), field("CacheWalksRun")))


solver.GetClientSideObject().AddObserver("EndEvent", record)
pvs.Show(solver)
pvs.Render()
# The Slice selected, to move it (cache_moved_slice.xml), or the solver
# with GRIDFREE_GUI_SELECT=Solver, to refine it (cache_refine.xml).
pvs.SetActiveSource(solver if os.environ.get("GRIDFREE_GUI_SELECT") == "Solver" else cut)
