"""Run by `paraview --script` before mark_conditions.xml: the unit sphere
carrying g = x*y and no condition array, and a plane inside it to solve
on, applied and shown, the sphere's surface selected."""
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
