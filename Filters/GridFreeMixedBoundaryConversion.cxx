#include "GridFreeMixedBoundaryConversion.h"

#include "vtkDataArray.h"
#include "vtkPolyData.h"

#include <gridfree/execution/ParallelExecution.h>
#include <gridfree/geometry/WeldVertices.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <utility>
#include <vector>

namespace gridfree
{
namespace
{
// The condition code `v` read from the condition array, or -1 when it is
// not exactly 0, 1, 2 or 3.
int ConditionCode(double v)
{
  return (v == 0.0 || v == 1.0 || v == 2.0 || v == 3.0) ? static_cast<int>(v) : -1;
}

std::string Describe(double v)
{
  std::ostringstream text;
  text << v;
  return text.str();
}

// The cells or points holding a number that cannot be used: how many, and
// the first.
struct BadNumbers
{
  long long Count = 0;
  vtkIdType First = -1;
  double FirstValue = 0.0;
  void Add(vtkIdType id, double value)
  {
    if (this->Count++ == 0)
    {
      this->First = id;
      this->FirstValue = value;
    }
  }
  // " (and N more …)" when there are others.
  std::string More(const char* what) const
  {
    return this->Count > 1
      ? " (and at " + std::to_string(this->Count - 1) + " more " + what + ")"
      : std::string();
  }
};
} // namespace

template <int DIM>
bool ConvertMixedBoundary(vtkPolyData* boundary, const MixedBoundaryArrays& arrays,
  std::shared_ptr<const BoundaryValueFunction<DIM>> valueFunction, MixedBoundary<DIM>& out,
  BoundaryConversionReport& report, MixedBoundaryCounts& counts, std::string& reason,
  const std::function<void(double)>& whileBuilding)
{
  using Primitive = typename Boundary<DIM>::Primitive;
  counts = MixedBoundaryCounts();
  if (!arrays.Conditions || arrays.Conditions->GetNumberOfComponents() != 1)
  {
    reason = arrays.Conditions ? "the boundary condition array has " +
        std::to_string(arrays.Conditions->GetNumberOfComponents()) +
        " components; it needs one (0 Dirichlet, 1 Neumann, 2 Robin)"
                               : "no boundary condition array";
    return false;
  }
  if (!valueFunction && !arrays.Values)
  {
    reason = "no boundary values";
    return false;
  }
  const int nc = valueFunction ? valueFunction->Components() : arrays.Values->GetNumberOfComponents();
  if (arrays.Flux && arrays.Flux->GetNumberOfComponents() != nc)
  {
    reason = "the Neumann flux array has " + std::to_string(arrays.Flux->GetNumberOfComponents()) +
      " components, the boundary values " + std::to_string(nc) + ": they must match";
    return false;
  }
  if (arrays.Robin && arrays.Robin->GetNumberOfComponents() != 1)
  {
    reason = "the Robin coefficient array has " +
      std::to_string(arrays.Robin->GetNumberOfComponents()) + " components; it needs one";
    return false;
  }

  BoundaryCells<DIM> cells;
  if (!CollectBoundaryCells<DIM>(boundary, cells, report, reason))
  {
    return false;
  }
  const std::size_t np = cells.Primitives.size();

  // Each primitive's condition and Robin coefficient, from its cell or its
  // points (by the input's point ids, before any welding).
  std::vector<BoundaryCondition> conditions(np);
  std::vector<double> mu(np, 0.0);
  BadNumbers badRobin;
  for (std::size_t p = 0; p < np; ++p)
  {
    const vtkIdType cell = cells.SourceCell[p];
    int code = 3;
    for (int k = 0; k < (arrays.ConditionsOnCells ? 1 : DIM); ++k)
    {
      const vtkIdType id = arrays.ConditionsOnCells ? cell : cells.Primitives[p][k];
      const double v = arrays.Conditions->GetComponent(id, 0);
      const int c = ConditionCode(v);
      if (c < 0)
      {
        reason = "the boundary condition array holds " + Describe(v) + " at " +
          (arrays.ConditionsOnCells ? "cell " : "point ") + std::to_string(id) +
          "; it may hold only 0 (Dirichlet), 1 (Neumann), 2 (Robin) and 3 (insulating sheet)";
        return false;
      }
      code = std::min(code, c); // per point: the smallest condition wins
    }
    conditions[p] = static_cast<BoundaryCondition>(code);
    if (code == 0)
    {
      ++counts.Dirichlet;
      continue;
    }
    if (code == 1)
    {
      ++counts.Neumann;
      continue;
    }
    if (code == 3)
    {
      ++counts.Sheets;
      continue;
    }
    ++counts.Robin;
    if (!arrays.Robin)
    {
      reason = "cell " + std::to_string(cell) +
        " has the Robin condition (2), but no Robin coefficient array is selected";
      return false;
    }
    double m = 0.0;
    if (arrays.RobinOnCells)
    {
      m = arrays.Robin->GetComponent(cell, 0);
    }
    else
    {
      for (int k = 0; k < DIM; ++k)
      {
        m += arrays.Robin->GetComponent(cells.Primitives[p][k], 0) / DIM;
      }
    }
    if (!(m >= 0.0) || !std::isfinite(m))
    {
      badRobin.Add(cell, m);
    }
    mu[p] = m;
  }
  if (badRobin.Count > 0)
  {
    reason = "the Robin coefficient of cell " + std::to_string(badRobin.First) + " is " +
      Describe(badRobin.FirstValue) + badRobin.More("Robin cells") +
      "; it must be finite and >= 0 (0 is the Neumann condition)";
    return false;
  }
  // The flux where it is used (the Neumann and Robin cells, or their
  // points): finite, or an error naming the first cell or point.
  if (arrays.Flux)
  {
    BadNumbers badFlux;
    std::vector<unsigned char> seen(arrays.FluxOnCells ? 0 : cells.Vertices.size(), 0);
    for (std::size_t p = 0; p < np; ++p)
    {
      if (conditions[p] == BoundaryCondition::Dirichlet ||
        conditions[p] == BoundaryCondition::InsulatingSheet)
      {
        continue; // the flux is not read there
      }
      for (int k = 0; k < (arrays.FluxOnCells ? 1 : DIM); ++k)
      {
        const vtkIdType id = arrays.FluxOnCells ? cells.SourceCell[p] : cells.Primitives[p][k];
        if (!arrays.FluxOnCells)
        {
          if (seen[static_cast<std::size_t>(id)])
          {
            continue;
          }
          seen[static_cast<std::size_t>(id)] = 1;
        }
        for (int c = 0; c < nc; ++c)
        {
          const double h = arrays.Flux->GetComponent(id, c);
          if (!std::isfinite(h))
          {
            badFlux.Add(id, h);
            break;
          }
          counts.LargestFlux = std::max(counts.LargestFlux, std::abs(h));
        }
      }
    }
    if (badFlux.Count > 0)
    {
      const char* where = arrays.FluxOnCells ? "cell " : "point ";
      reason = "the Neumann flux is " + Describe(badFlux.FirstValue) + " at " + where +
        std::to_string(badFlux.First) +
        badFlux.More(arrays.FluxOnCells ? "Neumann and Robin cells" : "points of Neumann and Robin cells") +
        "; it must be finite where it is used (a fill value for missing data?)";
      return false;
    }
  }
  // The largest boundary value and the boundary's size, for the caller's
  // check of a flux out of all proportion.
  if (arrays.Values && !valueFunction)
  {
    for (vtkIdType t = 0; t < arrays.Values->GetNumberOfTuples(); ++t)
    {
      for (int c = 0; c < nc; ++c)
      {
        const double g = std::abs(arrays.Values->GetComponent(t, c));
        counts.LargestValue = std::isfinite(g) ? std::max(counts.LargestValue, g) : counts.LargestValue;
      }
    }
  }
  {
    Vec<DIM> lo = Vec<DIM>::Constant(std::numeric_limits<double>::infinity());
    Vec<DIM> hi = -lo;
    for (const Vec<DIM>& v : cells.Vertices)
    {
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
    counts.Size = cells.Vertices.empty() ? 0.0 : (hi - lo).norm();
  }

  // Cell values (g and h) per primitive, read now while the source cells
  // are known.
  auto perPrimitive = [&](vtkDataArray* array) {
    std::vector<double> flat(np * static_cast<std::size_t>(nc));
    for (std::size_t p = 0; p < np; ++p)
    {
      for (int c = 0; c < nc; ++c)
      {
        flat[p * nc + c] = array->GetComponent(cells.SourceCell[p], c);
      }
    }
    return flat;
  };
  const bool gOnPoints = !valueFunction && !arrays.ValuesOnCells;
  const bool hOnPoints = arrays.Flux && !arrays.FluxOnCells;
  std::vector<double> gCells, hCells;
  if (!valueFunction && arrays.ValuesOnCells)
  {
    gCells = perPrimitive(arrays.Values);
  }
  if (arrays.Flux && arrays.FluxOnCells)
  {
    hCells = perPrimitive(arrays.Flux);
  }
  // Point values side by side (g, then h): welding the vertices of a soup
  // merges copies only where both agree.
  const int width = (gOnPoints ? nc : 0) + (hOnPoints ? nc : 0);
  std::vector<double> table;
  if (width > 0)
  {
    const std::size_t nv = cells.Vertices.size();
    table.resize(nv * static_cast<std::size_t>(width));
    for (std::size_t v = 0; v < nv; ++v)
    {
      int column = 0;
      for (vtkDataArray* array : { gOnPoints ? arrays.Values : nullptr, hOnPoints ? arrays.Flux : nullptr })
      {
        for (int c = 0; array && c < nc; ++c)
        {
          table[v * width + column++] = array->GetComponent(static_cast<vtkIdType>(v), c);
        }
      }
    }
  }

  auto work = [&]() {
    WeldIdenticalVertices<DIM>(cells.Vertices, cells.Primitives, width > 0 ? &table : nullptr, width);
    MeshPart<DIM> d, r;
    SplitByCondition<DIM>(cells.Vertices, cells.Primitives, conditions, d, r);
    // The values of one part: from the point table (column `offset`), or
    // per primitive from `onCells`, or zero.
    auto values = [&](const MeshPart<DIM>& part, bool onPoints, int offset,
                    const std::vector<double>& onCells, ValueAssociation& association) {
      std::vector<double> flat;
      if (onPoints)
      {
        association = ValueAssociation::Points;
        flat.resize(part.Vertices.size() * static_cast<std::size_t>(nc));
        for (std::size_t v = 0; v < part.Vertices.size(); ++v)
        {
          const auto row = static_cast<std::size_t>(part.VertexOrigin[v]) * width;
          std::copy_n(&table[row + offset], nc, &flat[v * nc]);
        }
        return flat;
      }
      association = ValueAssociation::Cells;
      flat.assign(part.Primitives.size() * static_cast<std::size_t>(nc), 0.0);
      if (!onCells.empty())
      {
        for (std::size_t p = 0; p < part.Primitives.size(); ++p)
        {
          const auto whole = static_cast<std::size_t>(part.Original[p]);
          std::copy_n(&onCells[whole * nc], nc, &flat[p * nc]);
        }
      }
      return flat;
    };
    std::shared_ptr<Boundary<DIM>> dirichlet, reflecting;
    if (!d.Primitives.empty())
    {
      dirichlet = std::make_shared<Boundary<DIM>>();
      if (valueFunction)
      {
        dirichlet->SetMesh(std::move(d.Vertices), std::move(d.Primitives), valueFunction);
      }
      else
      {
        ValueAssociation association;
        std::vector<double> g = values(d, gOnPoints, 0, gCells, association);
        dirichlet->Set(std::move(d.Vertices), std::move(d.Primitives), association, nc, std::move(g));
      }
    }
    std::vector<double> partMu;
    std::vector<std::uint8_t> sheets;
    if (!r.Primitives.empty())
    {
      if (counts.Sheets > 0)
      {
        sheets.reserve(r.Primitives.size());
        for (std::int64_t whole : r.Original)
        {
          sheets.push_back(
            conditions[static_cast<std::size_t>(whole)] == BoundaryCondition::InsulatingSheet);
        }
      }
      ValueAssociation association;
      std::vector<double> h = values(r, hOnPoints, gOnPoints ? nc : 0, hCells, association);
      if (counts.Robin > 0)
      {
        partMu.reserve(r.Primitives.size());
        for (std::int64_t whole : r.Original)
        {
          partMu.push_back(mu[static_cast<std::size_t>(whole)]);
        }
      }
      reflecting = std::make_shared<Boundary<DIM>>();
      reflecting->Set(std::move(r.Vertices), std::move(r.Primitives), association, nc, std::move(h));
    }
    out.Set(dirichlet, reflecting, std::move(partMu), true, std::move(sheets));
  };
  if (whileBuilding)
  {
    RunWhileReporting(work, whileBuilding);
  }
  else
  {
    work();
  }
  return true;
}

template bool ConvertMixedBoundary<2>(vtkPolyData*, const MixedBoundaryArrays&,
  std::shared_ptr<const BoundaryValueFunction<2>>, MixedBoundary<2>&, BoundaryConversionReport&,
  MixedBoundaryCounts&, std::string&, const std::function<void(double)>&);
template bool ConvertMixedBoundary<3>(vtkPolyData*, const MixedBoundaryArrays&,
  std::shared_ptr<const BoundaryValueFunction<3>>, MixedBoundary<3>&, BoundaryConversionReport&,
  MixedBoundaryCounts&, std::string&, const std::function<void(double)>&);
} // namespace gridfree
