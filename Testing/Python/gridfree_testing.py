"""Shared helpers of the Python tests: boundaries with known harmonic
solutions, and a catcher for VTK error and warning messages."""
import math

from vtkmodules.util.misc import calldata_type
from vtkmodules.util.vtkConstants import VTK_STRING
from vtkmodules.vtkCommonCore import vtkCommand, vtkDoubleArray, vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.vtkFiltersSources import vtkPlaneSource, vtkRegularPolygonSource, vtkSphereSource


def saddle(x, y, z=0.0):
    return x * x - y * y


def add_point_array(polydata, name, function, components=1):
    array = vtkDoubleArray()
    array.SetName(name)
    array.SetNumberOfComponents(components)
    for i in range(polydata.GetNumberOfPoints()):
        value = function(*polydata.GetPoint(i))
        array.InsertNextTuple(value if components > 1 else (value,))
    polydata.GetPointData().AddArray(array)
    return array


def filled_array(name, tuples, value, components=1):
    """A vtkDoubleArray of `tuples` tuples, every number `value`."""
    array = vtkDoubleArray()
    array.SetName(name)
    array.SetNumberOfComponents(components)
    array.SetNumberOfTuples(tuples)
    array.Fill(value)
    return array


def point_cloud(points):
    """A vtkPolyData of the given points (double coordinates), no cells."""
    cloud = vtkPolyData()
    vtk_points = vtkPoints()
    vtk_points.SetDataTypeToDouble()
    for p in points:
        vtk_points.InsertNextPoint(*p)
    cloud.SetPoints(vtk_points)
    return cloud


def plane_probe(origin, point1, point2, resolution):
    """A vtkPlaneSource's output: (resolution + 1)^2 points."""
    source = vtkPlaneSource()
    source.SetOrigin(*origin)
    source.SetPoint1(*point1)
    source.SetPoint2(*point2)
    source.SetResolution(resolution, resolution)
    source.Update()
    return source.GetOutput()


def closed_polyline(vertices):
    """One closed polyline through the (x, y) vertices, in z = 0 (a 2D
    boundary)."""
    points = vtkPoints()
    for x, y in vertices:
        points.InsertNextPoint(x, y, 0.0)
    lines = vtkCellArray()
    lines.InsertNextCell(len(vertices) + 1)
    for i in range(len(vertices) + 1):
        lines.InsertCellPoint(i % len(vertices))
    curve = vtkPolyData()
    curve.SetPoints(points)
    curve.SetLines(lines)
    return curve


def sphere_boundary(function=saddle, name="T", resolution=128):
    """Unit sphere (triangles) carrying function(x, y, z) as a point array."""
    source = vtkSphereSource()
    source.SetRadius(1.0)
    source.SetThetaResolution(resolution)
    source.SetPhiResolution(resolution)
    source.Update()
    boundary = vtkPolyData()
    boundary.DeepCopy(source.GetOutput())
    add_point_array(boundary, name, function)
    return boundary


def circle_boundary(function, name="T", sides=2048):
    """Unit circle in the plane z = 0 as one closed polyline (a 2D problem)."""
    source = vtkRegularPolygonSource()
    source.SetNumberOfSides(sides)
    source.SetRadius(1.0)
    source.SetCenter(0.0, 0.0, 0.0)
    source.GeneratePolygonOff()
    source.GeneratePolylineOn()
    source.Update()
    boundary = vtkPolyData()
    boundary.DeepCopy(source.GetOutput())
    add_point_array(boundary, name, function)
    return boundary


def z_scores(output, exact, name="T"):
    values = output.GetPointData().GetArray(name)
    variances = output.GetPointData().GetArray(name + "_Variance")
    scores = []
    for i in range(output.GetNumberOfPoints()):
        estimate = values.GetTuple1(i)
        scores.append((estimate - exact(*output.GetPoint(i))) / math.sqrt(variances.GetTuple1(i)))
    return scores


class MessageCatcher:
    """Collects ErrorEvent and WarningEvent texts of VTK objects."""

    def __init__(self, *objects):
        self.errors = []
        self.warnings = []
        for obj in objects:
            obj.AddObserver(vtkCommand.ErrorEvent, self._on_error)
            obj.AddObserver(vtkCommand.WarningEvent, self._on_warning)

    @calldata_type(VTK_STRING)
    def _on_error(self, obj, event, text):
        self.errors.append(text)

    @calldata_type(VTK_STRING)
    def _on_warning(self, obj, event, text):
        self.warnings.append(text)

    def error_text(self):
        return "\n".join(self.errors)

    def warning_text(self):
        return "\n".join(self.warnings)


def update_aborted_at_first_progress(algorithm):
    """Updates `algorithm`, asking it to abort at its first progress report
    (as the GUI's Abort button does), and removes the observer after."""

    def on_progress(obj, event):
        obj.SetAbortExecute(1)

    tag = algorithm.AddObserver(vtkCommand.ProgressEvent, on_progress)
    algorithm.Update()
    algorithm.RemoveObserver(tag)


def bessel_i0(x):
    """I0(x) by its power series (ample for |x| < 5)."""
    term, total = 1.0, 1.0
    for k in range(1, 40):
        term *= (x / (2.0 * k)) ** 2
        total += term
    return total
