"""Run by `paraview --script` before abort_keep_resume.xml: the scene of a
user who solved once and follows the solution's gradient with ParaView's own
Stream Tracer. The unit sphere carries g = x*y (the Boundary), a triangulated
10 x 10 plane inside it is the Probe, the solver has run with 32 walks per
point and the gradient on, and Stream Tracer With Custom Source traces
g_Gradient on the solve from every 7th of its points (surface streamlines,
as on a slice). All shown, the solver selected. Each filter's input is
updated before the filter is created, so that the array lists of the panel
hold the arrays the script selects."""
import paraview.simple as pvs

sphere = pvs.Sphere(registrationName="Sphere", Radius=1.0, ThetaResolution=48,
                    PhiResolution=48)
surface = pvs.Calculator(registrationName="Surface", Input=sphere, ResultArrayName="g",
                         Function="coordsX*coordsY")
plane = pvs.Plane(registrationName="Plane", Origin=[-0.6, -0.6, 0.0], Point1=[0.6, -0.6, 0.0],
                  Point2=[-0.6, 0.6, 0.0], XResolution=9, YResolution=9)
probe = pvs.Triangulate(registrationName="Probe", Input=plane)
surface.UpdatePipeline()
probe.UpdatePipeline()
solver = pvs.WalkOnSpheresSolver(registrationName="Solver", Boundary=surface, Probe=probe)
solver.BoundaryValues = ["POINTS", "g"]
solver.ComputeGradient = 1
solver.WalksPerPoint = 32
pvs.Show(solver)
solver.UpdatePipeline()
seeds = pvs.MaskPoints(registrationName="Seeds", Input=solver, OnRatio=7,
                       GenerateVertices=1, SingleVertexPerCell=1)
tracer = pvs.StreamTracerWithCustomSource(registrationName="Streamlines", Input=solver,
                                          SeedSource=seeds)
tracer.Vectors = ["POINTS", "g_Gradient"]
tracer.SurfaceStreamlines = 1
tracer.IntegrationDirection = "BOTH"
pvs.Show(tracer)
pvs.Render()
pvs.SetActiveSource(solver)
