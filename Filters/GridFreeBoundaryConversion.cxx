#include "GridFreeBoundaryConversion.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkDataArray.h"
#include "vtkIdList.h"
#include "vtkNew.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolygon.h"

#include <cmath>

namespace gridfree
{
int DetectBoundaryDimension(vtkPolyData* boundary, std::string& reason)
{
  if (!boundary || boundary->GetNumberOfPoints() == 0 || boundary->GetNumberOfCells() == 0)
  {
    reason = "the boundary is empty (no points or no cells)";
    return 0;
  }
  if (boundary->GetNumberOfPolys() > 0 || boundary->GetNumberOfStrips() > 0)
  {
    return 3;
  }
  if (boundary->GetNumberOfLines() == 0)
  {
    reason = "the boundary has neither surfaces (polygons, triangle strips) nor lines";
    return 0;
  }
  // A 2D problem lives in the plane z = const of its lines.
  double bounds[6];
  boundary->GetBounds(bounds);
  const double extent = std::max({ bounds[1] - bounds[0], bounds[3] - bounds[2], 1e-300 });
  if (bounds[5] - bounds[4] > 1e-9 * extent)
  {
    reason = "a boundary made of lines defines a 2D problem and must lie in one z-plane, "
             "but its z ranges over [" +
      std::to_string(bounds[4]) + ", " + std::to_string(bounds[5]) + "]";
    return 0;
  }
  return 2;
}

namespace
{
// Copies the value tuples (all components) into a flat double vector.
std::vector<double> FlattenValues(vtkDataArray* values, vtkIdType tuples)
{
  const int nc = values->GetNumberOfComponents();
  std::vector<double> flat(static_cast<std::size_t>(tuples) * nc);
  for (vtkIdType t = 0; t < tuples; ++t)
  {
    for (int c = 0; c < nc; ++c)
    {
      flat[static_cast<std::size_t>(t) * nc + c] = values->GetComponent(t, c);
    }
  }
  return flat;
}

template <int DIM>
std::vector<Vec<DIM>> ConvertPoints(vtkPoints* points)
{
  std::vector<Vec<DIM>> vertices(static_cast<std::size_t>(points->GetNumberOfPoints()));
  double p[3];
  for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i)
  {
    points->GetPoint(i, p);
    for (int k = 0; k < DIM; ++k)
    {
      vertices[i][k] = p[k];
    }
  }
  return vertices;
}
} // namespace

template <int DIM>
bool ConvertBoundary(vtkPolyData* boundary, vtkDataArray* values, bool cellData,
  Boundary<DIM>& out, BoundaryConversionReport& report, std::string& reason,
  std::shared_ptr<const BoundaryValueFunction<DIM>> valueFunction)
{
  using Primitive = typename Boundary<DIM>::Primitive;
  std::vector<Primitive> primitives;
  std::vector<vtkIdType> sourceCell; // the input cell each primitive came from

  // vtkPolyData numbers cells verts, lines, polys, strips in that order.
  const vtkIdType firstLine = boundary->GetNumberOfVerts();
  const vtkIdType firstPoly = firstLine + boundary->GetNumberOfLines();
  const vtkIdType firstStrip = firstPoly + boundary->GetNumberOfPolys();

  if constexpr (DIM == 2)
  {
    // Every polyline contributes its consecutive segments.
    auto it = vtk::TakeSmartPointer(boundary->GetLines()->NewIterator());
    vtkIdType cellId = firstLine;
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++cellId)
    {
      vtkIdType n;
      const vtkIdType* ids;
      it->GetCurrentCell(n, ids);
      if (n < 2)
      {
        ++report.SkippedCells;
        continue;
      }
      for (vtkIdType k = 0; k + 1 < n; ++k)
      {
        Primitive p;
        p[0] = ids[k];
        p[1] = ids[k + 1];
        primitives.push_back(p);
        sourceCell.push_back(cellId);
      }
    }
    report.IgnoredLowerDimensionalCells = boundary->GetNumberOfVerts();
  }
  else
  {
    vtkNew<vtkPolygon> polygon;
    vtkNew<vtkIdList> triangles;
    auto polys = vtk::TakeSmartPointer(boundary->GetPolys()->NewIterator());
    vtkIdType cellId = firstPoly;
    for (polys->GoToFirstCell(); !polys->IsDoneWithTraversal(); polys->GoToNextCell(), ++cellId)
    {
      vtkIdType n;
      const vtkIdType* ids;
      polys->GetCurrentCell(n, ids);
      if (n < 3)
      {
        ++report.SkippedCells;
        continue;
      }
      if (n == 3)
      {
        primitives.push_back(Primitive{ ids[0], ids[1], ids[2] });
        sourceCell.push_back(cellId);
        continue;
      }
      // General polygons (possibly non-convex) by ear clipping; a polygon the
      // triangulator rejects (e.g. all points collinear) falls back to a fan,
      // which still covers the polygon's points for closest-point purposes.
      polygon->Initialize(static_cast<int>(n), ids, boundary->GetPoints());
      triangles->Reset();
      if (polygon->Triangulate(triangles) && triangles->GetNumberOfIds() >= 3)
      {
        for (vtkIdType t = 0; t + 2 < triangles->GetNumberOfIds(); t += 3)
        {
          primitives.push_back(Primitive{ ids[triangles->GetId(t)], ids[triangles->GetId(t + 1)],
            ids[triangles->GetId(t + 2)] });
          sourceCell.push_back(cellId);
        }
      }
      else
      {
        for (vtkIdType k = 1; k + 1 < n; ++k)
        {
          primitives.push_back(Primitive{ ids[0], ids[k], ids[k + 1] });
          sourceCell.push_back(cellId);
        }
      }
    }
    auto strips = vtk::TakeSmartPointer(boundary->GetStrips()->NewIterator());
    cellId = firstStrip;
    for (strips->GoToFirstCell(); !strips->IsDoneWithTraversal(); strips->GoToNextCell(), ++cellId)
    {
      vtkIdType n;
      const vtkIdType* ids;
      strips->GetCurrentCell(n, ids);
      if (n < 3)
      {
        ++report.SkippedCells;
        continue;
      }
      for (vtkIdType k = 0; k + 2 < n; ++k)
      {
        primitives.push_back(Primitive{ ids[k], ids[k + 1], ids[k + 2] });
        sourceCell.push_back(cellId);
      }
    }
    report.IgnoredLowerDimensionalCells = boundary->GetNumberOfVerts() + boundary->GetNumberOfLines();
  }

  if (primitives.empty())
  {
    reason = DIM == 2 ? "the boundary has no line segments" : "the boundary has no triangles";
    return false;
  }

  // A non-finite vertex would make every distance query meaningless.
  std::vector<Vec<DIM>> vertices = ConvertPoints<DIM>(boundary->GetPoints());
  long long nonFinite = 0;
  for (const Primitive& p : primitives)
  {
    for (int k = 0; k < DIM; ++k)
    {
      nonFinite += vertices[p[k]].allFinite() ? 0 : 1;
    }
  }
  if (nonFinite > 0)
  {
    reason = "its cells use points with NaN or infinite coordinates (" +
      std::to_string(nonFinite) + " uses)";
    return false;
  }

  if (valueFunction)
  {
    out.SetMesh(std::move(vertices), std::move(primitives), std::move(valueFunction));
    return true;
  }
  if (!values)
  {
    reason = "no boundary values";
    return false;
  }
  const int nc = values->GetNumberOfComponents();
  std::vector<double> flat;
  if (cellData)
  {
    // One value tuple per primitive, copied from its source cell.
    flat.resize(primitives.size() * nc);
    for (std::size_t p = 0; p < primitives.size(); ++p)
    {
      for (int c = 0; c < nc; ++c)
      {
        flat[p * nc + c] = values->GetComponent(sourceCell[p], c);
      }
    }
  }
  else
  {
    flat = FlattenValues(values, boundary->GetNumberOfPoints());
  }
  out.Set(std::move(vertices), std::move(primitives),
    cellData ? ValueAssociation::Cells : ValueAssociation::Points, nc, std::move(flat));
  return true;
}

template bool ConvertBoundary<2>(vtkPolyData*, vtkDataArray*, bool, Boundary<2>&,
  BoundaryConversionReport&, std::string&, std::shared_ptr<const BoundaryValueFunction<2>>);
template bool ConvertBoundary<3>(vtkPolyData*, vtkDataArray*, bool, Boundary<3>&,
  BoundaryConversionReport&, std::string&, std::shared_ptr<const BoundaryValueFunction<3>>);
} // namespace gridfree
