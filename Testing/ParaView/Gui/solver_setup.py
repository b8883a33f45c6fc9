"""Run by `paraview --script` before the event playback of solver_from_menu.xml:
what a user has loaded before choosing the solver, a surface carrying the
boundary values (g = x*y on the unit sphere) and a plane to solve on, both applied
and shown, with the surface selected in the Pipeline Browser."""
import paraview.simple as pvs

sphere = pvs.Sphere(registrationName="Sphere", Radius=1.0, ThetaResolution=48,
                    PhiResolution=48)
surface = pvs.Calculator(registrationName="Surface", Input=sphere, ResultArrayName="g",
                         Function="coordsX*coordsY")
pvs.Show(surface)
plane = pvs.Plane(registrationName="Plane", Origin=[-0.4, -0.4, 0.0], Point1=[0.4, -0.4, 0.0],
                  Point2=[-0.4, 0.4, 0.0], XResolution=6, YResolution=6)
pvs.Show(plane)
pvs.Render()
pvs.SetActiveSource(surface)
