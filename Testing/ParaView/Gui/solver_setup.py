"""Run by `paraview --script` before the event playbacks of Testing/ParaView/Gui:
what a user has loaded before choosing the solver, a surface carrying the
boundary values (g = x*y on the unit sphere), a plane to solve on and a
volume for a source term (a Wavelet, f = RTData), all applied and shown, with
the surface selected in the Pipeline Browser."""
import paraview.simple as pvs

sphere = pvs.Sphere(registrationName="Sphere", Radius=1.0, ThetaResolution=48,
                    PhiResolution=48)
surface = pvs.Calculator(registrationName="Surface", Input=sphere, ResultArrayName="g",
                         Function="coordsX*coordsY")
pvs.Show(surface)
plane = pvs.Plane(registrationName="Plane", Origin=[-0.4, -0.4, 0.0], Point1=[0.4, -0.4, 0.0],
                  Point2=[-0.4, 0.4, 0.0], XResolution=6, YResolution=6)
pvs.Show(plane)
heat = pvs.Wavelet(registrationName="Heat")
pvs.Show(heat)
pvs.Render()
pvs.SetActiveSource(surface)
