"""Run by `paraview --script` before mixed_conditions.xml: the unit sphere
carrying g = x*y and the boundary condition of each point, bc = 1 (Neumann,
insulated) above z = 0.7 and 0 (Dirichlet) elsewhere, and a plane inside it
to solve on, applied and shown, the boundary selected."""
import paraview.simple as pvs

sphere = pvs.Sphere(registrationName="Sphere", Radius=1.0, ThetaResolution=48,
                    PhiResolution=48)
conditions = pvs.Calculator(registrationName="Conditions", Input=sphere, ResultArrayName="bc",
                            Function="coordsZ > 0.7")
# g last: the active scalars, which array lists offer first.
surface = pvs.Calculator(registrationName="Surface", Input=conditions, ResultArrayName="g",
                         Function="coordsX*coordsY")
pvs.Show(surface)
plane = pvs.Plane(registrationName="Plane", Origin=[-0.4, -0.4, 0.0], Point1=[0.4, -0.4, 0.0],
                  Point2=[-0.4, 0.4, 0.0], XResolution=6, YResolution=6)
pvs.Show(plane)
pvs.Render()
pvs.SetActiveSource(surface)
