"""What the application example scripts share: 2D outlines as polylines,
VTK data handed to a ParaView pipeline, and pictures saved with a retry.
Imported from the scripts' own folder (pvbatch puts it on the path)."""
import os
import sys

import paraview.simple as pvs
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData


def closed_polyline(vertices):
    """One closed polyline through the (x, y) vertices, in z = 0."""
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


def producer(data):
    """A ParaView source that outputs `data` (pvbatch's built-in session)."""
    source = pvs.PVTrivialProducer()
    source.GetClientSideObject().SetOutput(data)
    return source


def save(layout, path, size):
    # An X server that is slow to come up under load can lose the first render.
    for _ in range(2):
        if pvs.SaveScreenshot(path, layout, ImageResolution=size) and os.path.getsize(path) > 0:
            print(f"wrote {path}")
            return
    sys.exit(f"could not write {path}")
