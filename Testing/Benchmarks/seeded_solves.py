"""What the error-bar benchmarks share: a probe of chosen points, and one
solve of it with a given walk count and seed."""
import paraview.simple as pvs
from paraview import servermanager
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkPolyData


def point_probe(dataset, ids):
    """A pipeline source of the points `ids` of `dataset` (a vtkPolyData of
    points only)."""
    points = vtkPoints()
    for i in ids:
        points.InsertNextPoint(dataset.GetPoint(i))
    cloud = vtkPolyData()
    cloud.SetPoints(points)
    producer = pvs.PVTrivialProducer()
    producer.GetClientSideObject().SetOutput(cloud)
    return producer


def solve(solver, walks, seed, name):
    """(value, variance, reliable) at each probe point of `solver` after a
    solve with `walks` walks per point and `seed`; `name` is the solution
    array's."""
    solver.WalksPerPoint = walks
    solver.Seed = seed
    solver.UpdatePipeline()
    a = servermanager.Fetch(solver).GetPointData()
    value, variance = a.GetArray(name), a.GetArray(name + "_Variance")
    reliable = a.GetArray(name + "_VarianceReliable")
    return [(value.GetValue(k), variance.GetValue(k), reliable.GetValue(k))
            for k in range(value.GetNumberOfTuples())]
