#include "GridFreeBoundaryConversion.h"

#include <gridfree/boundary/BezierBoundaryValues.h>
#include <gridfree/execution/ParallelExecution.h>
#include <gridfree/geometry/BezierCurves.h>
#include <gridfree/geometry/WeldVertices.h>

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkIdList.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolygon.h"

#include <algorithm>
#include <cmath>

namespace gridfree
{
namespace
{
// The first cell (in vtkPolyData's cell numbering) that refers to a point id
// outside [0, points): such a file would make every later step read beyond
// the point array. Returns false and a reason naming the cell.
bool AllPointIdsValid(vtkPolyData* boundary, std::string& reason)
{
  const vtkIdType points = boundary->GetNumberOfPoints();
  vtkIdType cellId = 0;
  for (vtkCellArray* cells :
    { boundary->GetVerts(), boundary->GetLines(), boundary->GetPolys(), boundary->GetStrips() })
  {
    if (!cells)
    {
      continue;
    }
    auto it = vtk::TakeSmartPointer(cells->NewIterator());
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++cellId)
    {
      vtkIdType n;
      const vtkIdType* ids;
      it->GetCurrentCell(n, ids);
      for (vtkIdType k = 0; k < n; ++k)
      {
        if (ids[k] < 0 || ids[k] >= points)
        {
          reason = "cell " + std::to_string(cellId) + " refers to point " +
            std::to_string(ids[k]) + ", but the boundary has " + std::to_string(points) +
            " points";
          return false;
        }
      }
    }
  }
  return true;
}
} // namespace

int DetectBoundaryDimension(vtkPolyData* boundary, std::string& reason)
{
  if (!boundary || boundary->GetNumberOfPoints() == 0 || boundary->GetNumberOfCells() == 0)
  {
    reason = "the boundary is empty (no points or no cells)";
    return 0;
  }
  // Before anything reads points through cells (GetBounds does).
  if (!AllPointIdsValid(boundary, reason))
  {
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

// A straight segment or one cubic Bézier curve of a 2D boundary, by point ids.
struct LinePiece
{
  vtkIdType Ids[4]; // a segment repeats its end id in the unused slots
  bool Curve;        // four control points; otherwise a segment Ids[0]–Ids[1]
  vtkIdType Cell;    // the input cell it came from
};

// Reads the cell array that marks Bézier polylines. `flags` stays null when
// there is none; a malformed one is an error rather than silently straight
// lines, since the user evidently meant curves.
bool FindBezierFlags(vtkPolyData* boundary, vtkDataArray*& flags, std::string& reason)
{
  flags = nullptr;
  const std::string name = BezierControlPointsArrayName;
  vtkAbstractArray* any = boundary->GetCellData()->GetAbstractArray(name.c_str());
  if (!any)
  {
    if (boundary->GetPointData()->GetAbstractArray(name.c_str()))
    {
      reason = "'" + name +
        "' is a point array, but it marks whole polylines as Bézier curves and must be cell data";
      return false;
    }
    return true;
  }
  flags = vtkDataArray::SafeDownCast(any);
  if (!flags || flags->GetNumberOfComponents() != 1 ||
    flags->GetNumberOfTuples() != boundary->GetNumberOfCells())
  {
    reason = "the cell array '" + name +
      "' must be numeric with one component and one value per cell (nonzero: the polyline "
      "lists Bézier control points)";
    flags = nullptr;
    return false;
  }
  return true;
}

// The polylines of a 2D boundary as straight segments and Bézier curves, in
// cell order.
bool CollectLinePieces(vtkPolyData* boundary, vtkDataArray* flags, std::vector<LinePiece>& pieces,
  BoundaryConversionReport& report, std::string& reason)
{
  auto it = vtk::TakeSmartPointer(boundary->GetLines()->NewIterator());
  vtkIdType cellId = boundary->GetNumberOfVerts(); // lines follow the vertices
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++cellId)
  {
    vtkIdType n;
    const vtkIdType* ids;
    it->GetCurrentCell(n, ids);
    const double flag = flags ? flags->GetComponent(cellId, 0) : 0.0;
    if (flag != 0.0)
    {
      if (!std::isfinite(flag))
      {
        reason = "the cell array '" + std::string(BezierControlPointsArrayName) +
          "' has a NaN or infinite value at cell " + std::to_string(cellId);
        return false;
      }
      if (n < 4 || (n - 1) % 3 != 0)
      {
        reason = "cell " + std::to_string(cellId) + " is marked as a Bézier curve in '" +
          BezierControlPointsArrayName + "' but has " + std::to_string(n) +
          " points; a piecewise cubic Bézier curve needs 3k + 1 control points (4, 7, 10, ...)";
        return false;
      }
      for (vtkIdType k = 0; k + 3 < n; k += 3)
      {
        pieces.push_back(LinePiece{ { ids[k], ids[k + 1], ids[k + 2], ids[k + 3] }, true, cellId });
      }
      continue;
    }
    if (n < 2)
    {
      ++report.SkippedCells;
      continue;
    }
    for (vtkIdType k = 0; k + 1 < n; ++k)
    {
      pieces.push_back(LinePiece{ { ids[k], ids[k + 1], ids[k + 1], ids[k + 1] }, false, cellId });
    }
  }
  return true;
}

// The Bézier path of a 2D boundary: every piece becomes a cubic curve, and
// the values become a function of (curve, t).
bool ConvertBezierBoundary(vtkDataArray* values, bool cellData,
  const std::vector<Vec2>& vertices, const std::vector<LinePiece>& pieces, Boundary<2>& out,
  std::string& reason, std::shared_ptr<const BoundaryValueFunction<2>> valueFunction)
{
  std::vector<CubicBezier> curves;
  curves.reserve(pieces.size());
  for (const LinePiece& piece : pieces)
  {
    CubicBezier c;
    if (piece.Curve)
    {
      for (int k = 0; k < 4; ++k)
      {
        c.P[k] = vertices[piece.Ids[k]];
      }
    }
    else
    {
      // Inner control points at 1/3 and 2/3 of the chord make B(t) = a + t (b − a):
      // the segment itself, with t linear along it, so point values are
      // interpolated exactly as on a mesh segment.
      const Vec2& a = vertices[piece.Ids[0]];
      const Vec2& b = vertices[piece.Ids[1]];
      c.P[0] = a;
      c.P[1] = (2.0 * a + b) / 3.0;
      c.P[2] = (a + 2.0 * b) / 3.0;
      c.P[3] = b;
    }
    curves.push_back(c);
  }
  auto geometry = std::make_shared<BezierBoundaryGeometry>(std::move(curves));

  if (!valueFunction)
  {
    if (!values)
    {
      reason = "no boundary values";
      return false;
    }
    const int nc = values->GetNumberOfComponents();
    std::vector<double> table;
    if (cellData)
    {
      table.resize(pieces.size() * nc);
      for (std::size_t p = 0; p < pieces.size(); ++p)
      {
        for (int c = 0; c < nc; ++c)
        {
          table[p * nc + c] = values->GetComponent(pieces[p].Cell, c);
        }
      }
    }
    else
    {
      // A curve's end points: P0 and P3, or the segment's two points. The
      // handles' values are never read: the handles are not on the curve.
      table.resize(2 * pieces.size() * nc);
      for (std::size_t p = 0; p < pieces.size(); ++p)
      {
        const vtkIdType ends[2] = { pieces[p].Ids[0], pieces[p].Ids[pieces[p].Curve ? 3 : 1] };
        for (int e = 0; e < 2; ++e)
        {
          for (int c = 0; c < nc; ++c)
          {
            table[(2 * p + e) * nc + c] = values->GetComponent(ends[e], c);
          }
        }
      }
    }
    valueFunction = std::make_shared<BezierBoundaryValues>(pieces.size(),
      cellData ? ValueAssociation::Cells : ValueAssociation::Points, nc, std::move(table));
  }
  out.SetGeometry(std::move(geometry), std::move(valueFunction));
  return true;
}

// Uses of points with NaN or infinite coordinates by the given point ids.
template <int DIM, typename Id>
long long CountNonFiniteUses(const std::vector<Vec<DIM>>& vertices, const Id* ids, int n)
{
  long long count = 0;
  for (int k = 0; k < n; ++k)
  {
    count += vertices[ids[k]].allFinite() ? 0 : 1;
  }
  return count;
}

// Degenerate primitives cover no length or area: a segment whose points
// coincide, a triangle whose edges are parallel (exactly, in double; then it
// is a segment or a point up to rounding), a curve whose control points all
// coincide. Such a set has zero capacity (a point in 2D, a segment in 3D):
// Brownian motion never hits it, so the exact solution does not depend on it,
// while its closest-point weights are ill-defined (0/0). Dropping it is
// therefore the right thing, not an approximation.
bool IsDegenerateTriangle(const std::vector<Vec3>& vertices, const Boundary<3>::Primitive& p)
{
  const Vec3 e1 = vertices[p[1]] - vertices[p[0]];
  const Vec3 e2 = vertices[p[2]] - vertices[p[0]];
  return e1.cross(e2) == Vec3::Zero();
}

bool IsDegenerate(const std::vector<Vec2>& vertices, const LinePiece& piece)
{
  const Vec2& a = vertices[piece.Ids[0]];
  if (!piece.Curve)
  {
    return a == vertices[piece.Ids[1]];
  }
  // A curve with any two distinct control points has positive length: the
  // curve is a polynomial of degree ≤ 3 that is constant only when all its
  // Bernstein coefficients (the control points) are equal.
  for (int k = 1; k < 4; ++k)
  {
    if (!(vertices[piece.Ids[k]] == a))
    {
      return false;
    }
  }
  return true;
}

std::string DegenerateNote(long long degenerate)
{
  return degenerate > 0
    ? " (" + std::to_string(degenerate) + " degenerate ones of zero length or area were dropped)"
    : std::string();
}

// The cells of the right kind as primitives (polygons and strips
// triangulated; lines as segments), each with the input cell it came from,
// without degenerate ones. A 2D boundary with Bézier polylines fills
// `curves` instead (an error when it is null).
template <int DIM>
bool CollectCells(vtkPolyData* boundary, BoundaryCells<DIM>& cells,
  BoundaryConversionReport& report, std::string& reason, std::vector<LinePiece>* curves)
{
  using Primitive = typename Boundary<DIM>::Primitive;
  if (!AllPointIdsValid(boundary, reason))
  {
    return false;
  }
  std::vector<Primitive>& primitives = cells.Primitives;
  std::vector<vtkIdType>& sourceCell = cells.SourceCell;
  std::vector<Vec<DIM>>& vertices = cells.Vertices;
  vertices = ConvertPoints<DIM>(boundary->GetPoints());
  primitives.clear();
  sourceCell.clear();
  const char* const nothingLeft =
    DIM == 2 ? "the boundary has no line segments" : "the boundary has no triangles";

  // vtkPolyData numbers cells verts, lines, polys, strips in that order.
  const vtkIdType firstPoly = boundary->GetNumberOfVerts() + boundary->GetNumberOfLines();
  const vtkIdType firstStrip = firstPoly + boundary->GetNumberOfPolys();

  if constexpr (DIM == 2)
  {
    report.IgnoredLowerDimensionalCells = boundary->GetNumberOfVerts();
    vtkDataArray* flags = nullptr;
    std::vector<LinePiece> pieces;
    if (!FindBezierFlags(boundary, flags, reason) ||
      !CollectLinePieces(boundary, flags, pieces, report, reason))
    {
      return false;
    }
    if (pieces.empty())
    {
      reason = nothingLeft;
      return false;
    }
    // A non-finite vertex (a handle included) would make every distance
    // query meaningless.
    long long nonFinite = 0;
    bool anyCurve = false;
    for (const LinePiece& piece : pieces)
    {
      nonFinite += CountNonFiniteUses<2>(vertices, piece.Ids, piece.Curve ? 4 : 2);
      anyCurve = anyCurve || piece.Curve;
    }
    if (nonFinite > 0)
    {
      reason = "its cells use points with NaN or infinite coordinates (" +
        std::to_string(nonFinite) + " uses)";
      return false;
    }
    const auto kept = std::remove_if(pieces.begin(), pieces.end(),
      [&](const LinePiece& piece) { return IsDegenerate(vertices, piece); });
    report.DegenerateCells = static_cast<long long>(pieces.end() - kept);
    pieces.erase(kept, pieces.end());
    if (pieces.empty())
    {
      reason = nothingLeft + DegenerateNote(report.DegenerateCells);
      return false;
    }
    if (anyCurve)
    {
      if (!curves)
      {
        reason = "it has Bézier curves (cell array " + std::string(BezierControlPointsArrayName) +
          "), and only straight segments are taken here";
        return false;
      }
      *curves = std::move(pieces);
      return true;
    }
    for (const LinePiece& piece : pieces)
    {
      Primitive p;
      p[0] = piece.Ids[0];
      p[1] = piece.Ids[1];
      primitives.push_back(p);
      sourceCell.push_back(piece.Cell);
    }
  }
  else
  {
    // One triangle per polygon at least (exactly, for the usual triangle
    // mesh): reserving it avoids the doubling growth's spare capacity, a
    // third of these arrays' size on the largest inputs.
    primitives.reserve(static_cast<std::size_t>(boundary->GetNumberOfPolys()));
    sourceCell.reserve(static_cast<std::size_t>(boundary->GetNumberOfPolys()));
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
      // triangulator rejects (e.g. a non-planar one) falls back to a fan,
      // which still covers the polygon's points for closest-point purposes.
      // Degenerate fan triangles (collinear points) are dropped below.
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

    if (primitives.empty())
    {
      reason = nothingLeft;
      return false;
    }
    // A non-finite vertex would make every distance query meaningless.
    long long nonFinite = 0;
    for (const Primitive& p : primitives)
    {
      nonFinite += CountNonFiniteUses<3>(vertices, p.data(), 3);
    }
    if (nonFinite > 0)
    {
      reason = "its cells use points with NaN or infinite coordinates (" +
        std::to_string(nonFinite) + " uses)";
      return false;
    }
    // Drop degenerate triangles, keeping each survivor's source cell.
    std::size_t kept = 0;
    for (std::size_t p = 0; p < primitives.size(); ++p)
    {
      if (!IsDegenerateTriangle(vertices, primitives[p]))
      {
        primitives[kept] = primitives[p];
        sourceCell[kept] = sourceCell[p];
        ++kept;
      }
    }
    report.DegenerateCells = static_cast<long long>(primitives.size() - kept);
    primitives.resize(kept);
    sourceCell.resize(kept);
    if (primitives.empty())
    {
      reason = nothingLeft + DegenerateNote(report.DegenerateCells);
      return false;
    }
  }

  return true;
}
} // namespace

const char* const BezierControlPointsArrayName = "BezierControlPoints";

template <int DIM>
bool CollectBoundaryCells(vtkPolyData* boundary, BoundaryCells<DIM>& cells,
  BoundaryConversionReport& report, std::string& reason)
{
  return CollectCells<DIM>(boundary, cells, report, reason, nullptr);
}

template <int DIM>
bool ConvertBoundary(vtkPolyData* boundary, vtkDataArray* values, bool cellData,
  Boundary<DIM>& out, BoundaryConversionReport& report, std::string& reason,
  std::shared_ptr<const BoundaryValueFunction<DIM>> valueFunction,
  const std::function<void(double)>& whileBuilding)
{
  using Primitive = typename Boundary<DIM>::Primitive;
  // The VTK-free end of the conversion, on a thread of its own when the
  // caller reports progress meanwhile.
  auto build = [&whileBuilding](const std::function<void()>& work) {
    if (whileBuilding)
    {
      RunWhileReporting(work, whileBuilding);
    }
    else
    {
      work();
    }
  };
  BoundaryCells<DIM> cells;
  std::vector<LinePiece> curves;
  if (!CollectCells<DIM>(boundary, cells, report, reason, &curves))
  {
    return false;
  }
  std::vector<Vec<DIM>>& vertices = cells.Vertices;
  std::vector<Primitive>& primitives = cells.Primitives;
  std::vector<vtkIdType>& sourceCell = cells.SourceCell;
  if constexpr (DIM == 2)
  {
    if (!curves.empty())
    {
      return ConvertBezierBoundary(
        values, cellData, vertices, curves, out, reason, std::move(valueFunction));
    }
  }

  // Only cell data needs each primitive's source cell; free it before the
  // hierarchy is built, when memory peaks.
  if (!cellData || valueFunction)
  {
    sourceCell = std::vector<vtkIdType>();
  }
  primitives.shrink_to_fit();
  if (valueFunction)
  {
    build([&]() {
      WeldIdenticalVertices<DIM>(vertices, primitives);
      out.SetMesh(std::move(vertices), std::move(primitives), std::move(valueFunction));
    });
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
    sourceCell = std::vector<vtkIdType>();
  }
  else
  {
    flat = FlattenValues(values, boundary->GetNumberOfPoints());
  }
  // A soup stores each vertex about six times: merge the copies (equal
  // coordinates and values, so nothing a walk sees changes) before the
  // hierarchy is built.
  build([&]() {
    WeldIdenticalVertices<DIM>(vertices, primitives, cellData ? nullptr : &flat, nc);
    out.Set(std::move(vertices), std::move(primitives),
      cellData ? ValueAssociation::Cells : ValueAssociation::Points, nc, std::move(flat));
  });
  return true;
}

template bool CollectBoundaryCells<2>(
  vtkPolyData*, BoundaryCells<2>&, BoundaryConversionReport&, std::string&);
template bool CollectBoundaryCells<3>(
  vtkPolyData*, BoundaryCells<3>&, BoundaryConversionReport&, std::string&);
template bool ConvertBoundary<2>(vtkPolyData*, vtkDataArray*, bool, Boundary<2>&,
  BoundaryConversionReport&, std::string&, std::shared_ptr<const BoundaryValueFunction<2>>,
  const std::function<void(double)>&);
template bool ConvertBoundary<3>(vtkPolyData*, vtkDataArray*, bool, Boundary<3>&,
  BoundaryConversionReport&, std::string&, std::shared_ptr<const BoundaryValueFunction<3>>,
  const std::function<void(double)>&);
} // namespace gridfree
