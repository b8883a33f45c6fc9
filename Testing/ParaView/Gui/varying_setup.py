"""Run by `paraview --script` before varying_coefficients.xml: the unit
sphere carrying g = x² + z + 1/2 (not harmonic, so a solve that ignored the
coefficients would miss it), a plane inside it to solve on, and an image of
tissue coefficients: Conductivity α = 2 + x/2 and Heat f = αΔg + ∇α·∇g − g =
4 + 2x − g (for σ = 1), with CT-like values as its active scalars (which
must never become a coefficient by default). All applied and shown, the
surface selected."""
import paraview.simple as pvs
from vtkmodules.vtkCommonCore import vtkDoubleArray
from vtkmodules.vtkCommonDataModel import vtkImageData

sphere = pvs.Sphere(registrationName="Sphere", Radius=1.0, ThetaResolution=48,
                    PhiResolution=48)
surface = pvs.Calculator(registrationName="Surface", Input=sphere, ResultArrayName="g",
                         Function="coordsX*coordsX + coordsZ + 0.5")
pvs.Show(surface)
plane = pvs.Plane(registrationName="Plane", Origin=[-0.4, -0.4, 0.1], Point1=[0.4, -0.4, 0.1],
                  Point2=[-0.4, 0.4, 0.1], XResolution=6, YResolution=6)
pvs.Show(plane)

image = vtkImageData()
image.SetOrigin(-1.5, -1.5, -1.5)
image.SetSpacing(0.1, 0.1, 0.1)
image.SetDimensions(31, 31, 31)
arrays = {}
for name in ("CT", "Conductivity", "Heat"):
    arrays[name] = vtkDoubleArray()
    arrays[name].SetName(name)
    arrays[name].SetNumberOfTuples(image.GetNumberOfPoints())
for i in range(image.GetNumberOfPoints()):
    x, y, z = image.GetPoint(i)
    arrays["CT"].SetValue(i, 1000.0 + 100.0 * x)
    arrays["Conductivity"].SetValue(i, 2.0 + 0.5 * x)
    arrays["Heat"].SetValue(i, 4.0 + 2.0 * x - (x * x + z + 0.5))
for name in ("Conductivity", "Heat"):
    image.GetPointData().AddArray(arrays[name])
image.GetPointData().SetScalars(arrays["CT"])
tissue = pvs.PVTrivialProducer(registrationName="Tissue")
tissue.GetClientSideObject().SetOutput(image)
tissue.UpdatePipeline()
pvs.Show(tissue)
pvs.Render()
pvs.SetActiveSource(surface)
