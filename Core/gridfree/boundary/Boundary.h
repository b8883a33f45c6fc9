// A Dirichlet boundary: its geometry and the values g prescribed on it. This
// is the only thing a walk needs to know about geometry.
//
// Geometry is either a mesh of simplices (segments in 2D, triangles in 3D)
// behind the BVH, the fast path called without any indirection, or any other
// BoundaryGeometry (implicit surfaces, CSG, Bézier curves). Values are either
// a table on the mesh (per vertex, interpolated, or per primitive) or a
// BoundaryValueFunction of the boundary point.
//
// Values may be two-sided (diffusion curves and surfaces, paper Sec. 6.4):
// every tuple then holds the front side's numbers followed by the back
// side's, and a walk that ends at x takes the side x lies on, seen from the
// closest point along the oriented normal (Normal()).
#ifndef GRIDFREE_BOUNDARY_BOUNDARY_H
#define GRIDFREE_BOUNDARY_BOUNDARY_H

#include <gridfree/boundary/BoundaryValues.h>
#include <gridfree/geometry/BoundaryGeometry.h>
#include <gridfree/geometry/Bvh.h>
#include <gridfree/geometry/DistanceBoundGrid.h>
#include <gridfree/geometry/SidePseudonormals.h>
#include <gridfree/math/Vector.h>
#include <gridfree/sources/PolynomialShift.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace gridfree
{
// Where boundary values live: on vertices (interpolated with the closest
// point's barycentric weights) or on primitives (constant per primitive).
enum class ValueAssociation
{
  Points,
  Cells
};

template <int DIM>
class Boundary
{
public:
  using Primitive = typename Bvh<DIM>::Primitive;

  // A mesh with a value table: vertices and primitives describe the
  // geometry; values holds `components` numbers per vertex (Points) or per
  // primitive (Cells).
  void Set(std::vector<Vec<DIM>> vertices, std::vector<Primitive> primitives,
    ValueAssociation association, int components, std::vector<double> values)
  {
    const std::size_t tuples =
      association == ValueAssociation::Points ? vertices.size() : primitives.size();
    if (components < 1 || values.size() != tuples * static_cast<std::size_t>(components))
    {
      throw std::invalid_argument("boundary values: expected " + std::to_string(tuples) + " x " +
        std::to_string(components) + " numbers, got " + std::to_string(values.size()));
    }
    this->SetMeshGeometry(std::move(vertices), std::move(primitives));
    this->Association = association;
    this->NumberOfComponents = components;
    this->Values = std::move(values);
  }

  // A mesh whose values come from a function of the boundary point.
  void SetMesh(std::vector<Vec<DIM>> vertices, std::vector<Primitive> primitives,
    std::shared_ptr<const BoundaryValueFunction<DIM>> values)
  {
    if (!values)
    {
      throw std::invalid_argument("boundary values: no value function");
    }
    this->SetMeshGeometry(std::move(vertices), std::move(primitives));
    this->NumberOfComponents = values->Components();
    this->ValueFunction = std::move(values);
  }

  // Any other geometry with values from a function. `region` bounds the
  // problem when the geometry itself is unbounded (a plane): walks beyond it
  // are treated as outside a boundary that lies within it.
  void SetGeometry(std::shared_ptr<const BoundaryGeometry<DIM>> geometry,
    std::shared_ptr<const BoundaryValueFunction<DIM>> values,
    const BoundingBox<DIM>& region = BoundingBox<DIM>())
  {
    if (!geometry || !values)
    {
      throw std::invalid_argument("boundary: no geometry or no value function");
    }
    BoundingBox<DIM> box = geometry->Bounds();
    const bool finite = !box.IsEmpty() && box.Min.allFinite() && box.Max.allFinite();
    if (!finite)
    {
      if (region.IsEmpty() || !region.Min.allFinite() || !region.Max.allFinite())
      {
        throw std::invalid_argument("boundary: an unbounded geometry needs a finite region");
      }
      box = region;
    }
    this->Clear();
    this->Shape = std::move(geometry);
    this->NumberOfComponents = values->Components();
    this->ValueFunction = std::move(values);
    this->Min = box.Min;
    this->Max = box.Max;
  }

  // Two-sided values: the values set hold 2·K numbers per tuple, K for the
  // front (the side the normal points to: left of a segment's direction,
  // the side a triangle's vertices turn counter-clockwise on) then K for
  // the back, and Components() is K. Call after setting the values.
  void SetTwoSided(bool twoSided)
  {
    if (twoSided && this->NumberOfComponents % 2 != 0)
    {
      throw std::invalid_argument("two-sided boundary values need an even number of components "
                                  "(front then back), got " +
        std::to_string(this->NumberOfComponents));
    }
    this->TwoSided = twoSided;
    this->FunctionRanges = std::make_shared<SampledRanges>();
    this->Pseudonormals = SidePseudonormals<DIM>();
    if (twoSided && !this->Shape)
    {
      this->Pseudonormals.Build(this->Vertices, this->Primitives);
    }
  }
  bool IsTwoSided() const { return this->TwoSided; }

  // Values read as g − P at the closest point, P evaluated there exactly
  // (PolynomialShift.h: the walks then estimate w = u − P); one-sided
  // values of one component only. Null removes the shift.
  void SetValueShift(std::shared_ptr<const PolynomialShift<DIM>> shift)
  {
    if (shift && (this->TwoSided || this->NumberOfComponents != 1))
    {
      throw std::invalid_argument("a polynomial shift takes one-sided values of one component");
    }
    this->Shift = std::move(shift);
    this->FunctionRanges = std::make_shared<SampledRanges>();
  }
  const PolynomialShift<DIM>* GetValueShift() const { return this->Shift.get(); }

  bool Empty() const { return !this->Shape && this->Primitives.empty(); }
  // Numbers per boundary value (one side's, for two-sided values).
  int Components() const
  {
    return this->TwoSided ? this->NumberOfComponents / 2 : this->NumberOfComponents;
  }
  // Mesh primitives, or the parts of another geometry.
  std::size_t NumberOfPrimitives() const
  {
    return this->Shape ? static_cast<std::size_t>(this->Shape->NumberOfParts())
                       : this->Primitives.size();
  }
  bool IsMesh() const { return !this->Shape; }
  // Whether every boundary value is the same (a value table whose tuples,
  // both sides included, are all equal); false for values from a function,
  // which may vary.
  bool ConstantValues() const
  {
    if (this->ValueFunction || this->Values.empty() || this->Shift)
    {
      return false;
    }
    const std::size_t nc = static_cast<std::size_t>(this->Components());
    for (std::size_t i = 0; i < this->Values.size(); ++i)
    {
      if (!(this->Values[i] == this->Values[i % nc]))
      {
        return false;
      }
    }
    return true;
  }
  // The lowest and highest value of component c a walk can read from a
  // value table (linear interpolation on a primitive stays between its
  // vertices' values; both sides of two-sided values); false for values
  // from a function, or without a table.
  bool ValueBounds(int c, double& lowest, double& highest) const
  {
    if (this->ValueFunction || this->Values.empty() || this->Shift)
    {
      return false;
    }
    const std::size_t stored = static_cast<std::size_t>(this->NumberOfComponents);
    const std::size_t own = static_cast<std::size_t>(this->Components());
    lowest = std::numeric_limits<double>::infinity();
    highest = -lowest;
    for (std::size_t i = 0; i < this->Values.size(); ++i)
    {
      if ((i % stored) % own == static_cast<std::size_t>(c))
      {
        lowest = std::min(lowest, this->Values[i]);
        highest = std::max(highest, this->Values[i]);
      }
    }
    return lowest <= highest;
  }
  // The lowest and highest value of every component a walk reads, for the
  // error bars' reliability signs (ErrorBarReliability.h): a value table's
  // exact range (ValueBounds), or, for values from a function on a mesh
  // (an expression, an image probed at the boundary), the range of the
  // values at every vertex and every primitive's centroid; on another
  // geometry (implicit, CSG, Bézier curves), at GeometrySamples' points. Those samples
  // are not a bound (a function may peak between them), so nothing that
  // must be exact (whether a flux is zero) reads them; for the signs a
  // range a little short of the truth only makes an unseen walk look a
  // little nearer. False for shifted values, where a sample is not finite
  // and where none was found. A function's samples are taken once per
  // boundary (the first call; later calls, from the problems a filter
  // builds on each update, read them).
  bool ValueRanges(std::vector<double>& lowest, std::vector<double>& highest) const
  {
    const std::size_t own = static_cast<std::size_t>(this->Components());
    lowest.assign(own, 0.0);
    highest.assign(own, 0.0);
    if (!this->ValueFunction)
    {
      for (std::size_t c = 0; c < own; ++c)
      {
        if (!this->ValueBounds(static_cast<int>(c), lowest[c], highest[c]))
        {
          return false;
        }
      }
      return true;
    }
    if (this->Shift || (!this->Shape && this->Primitives.empty()))
    {
      return false;
    }
    if (!this->FunctionRanges) // a boundary moved from
    {
      return this->SampleFunction(lowest, highest);
    }
    SampledRanges& cache = *this->FunctionRanges;
    std::call_once(cache.Once, [&]() { cache.Known = this->SampleFunction(cache.Low, cache.High); });
    lowest = cache.Low;
    highest = cache.High;
    return cache.Known;
  }
  // Boundary points of a geometry that is not a mesh (empty for a mesh),
  // which has no vertices to read: the closest points of the centres of a
  // lattice over the box (kRangeLatticeCells per axis) that lie within a
  // cell's diagonal of the boundary, a band that every part of the boundary
  // wider than a cell crosses. A projection that did not reach the boundary
  // (an implicit function's Newton steps, far from a surface whose function
  // is no distance) is left out. Taken once per geometry; ValueRanges, the
  // screened guide and the peak guide read them.
  const std::vector<ClosestPointResult<DIM>>& GeometrySamples() const
  {
    static const std::vector<ClosestPointResult<DIM>> none;
    if (!this->Shape || !this->GeometryHits)
    {
      return none;
    }
    SampledHits& cache = *this->GeometryHits;
    std::call_once(cache.Once, [&]() { cache.Hits = this->ProjectLattice(); });
    return cache.Hits;
  }

  // A mesh primitive's centroid as a closest point on it (where the guides
  // and ValueRanges read the values).
  ClosestPointResult<DIM> PrimitiveCentroid(std::size_t i) const
  {
    const Primitive& p = this->Primitives[i];
    ClosestPointResult<DIM> hit;
    hit.point = Vec<DIM>::Zero();
    for (int k = 0; k < DIM; ++k)
    {
      hit.point += this->Vertices[static_cast<std::size_t>(p[k])] / DIM;
    }
    hit.primitive = static_cast<std::int64_t>(i);
    hit.barycentric = Vec<DIM>::Constant(1.0 / DIM);
    hit.distance = 0.0;
    return hit;
  }

  // Whether x lies inside a boundary that is not a mesh, as its geometry
  // tells (BoundaryGeometry::Encloses); false for a mesh, whose inside
  // InsideClosedMesh asks by ray parity.
  bool GeometryEncloses(const Vec<DIM>& x) const { return this->Shape && this->Shape->Encloses(x); }

  // The mesh as given (empty for another geometry): a CSG operand builds its
  // signed distance from them.
  const std::vector<Vec<DIM>>& MeshVertices() const { return this->Vertices; }
  const std::vector<Primitive>& MeshPrimitives() const { return this->Primitives; }
  const Bvh<DIM>& Hierarchy() const { return this->Tree; }
  const Vec<DIM>& BoundsMin() const { return this->Min; }
  const Vec<DIM>& BoundsMax() const { return this->Max; }
  Vec<DIM> Center() const { return 0.5 * (this->Min + this->Max); }
  double Diagonal() const { return (this->Max - this->Min).norm(); }

  // Radius of the largest empty ball around x (paper Sec. 5.1).
  // A conservative bound for other geometries (never above the truth).
  double Distance(const Vec<DIM>& x) const
  {
    return this->Shape ? this->Shape->Distance(x) : this->Tree.Distance(x);
  }

  // The radius of a walk's next ball around x: any ball inside the domain
  // keeps the estimator's expectation (paper Sec. 2.2: the mean-value
  // property holds on every ball), so far from a mesh this may be a cheaper
  // lower bound of the distance, at least 1 / (1 + StepRelaxation) of it
  // (Bvh::DistanceLowerBound), or a bound cached on a grid that guarantees
  // as much (SetBoundGrid). It is exact whenever it is below `epsilon`,
  // so the decision to stop a walk is the same as with the exact distance.
  //
  // A walk passes its StepHint to every StepRadius and to its final
  // ClosestPoint: each query then starts from the primitive nearest to the
  // walk's previous position, and a walk that stops needs no further search
  // for its closest point (Bvh::NearestHint). Without one, each query starts
  // afresh.
  using StepHint = typename Bvh<DIM>::NearestHint;
  double StepRadius(const Vec<DIM>& x, double epsilon, StepHint* hint = nullptr) const
  {
    if (this->Shape)
    {
      // Exact unless the geometry caches bounds (CSG of meshes).
      return this->StepRelaxation > 0.0 && this->UseBoundGrid
        ? this->Shape->StepRadius(x, this->StepRelaxation, epsilon)
        : this->Shape->Distance(x);
    }
    StepHint none;
    StepHint& h = hint ? *hint : none;
    if (!(this->StepRelaxation > 0.0))
    {
      return std::sqrt(this->Tree.SquaredDistance(x, h));
    }
    if (this->UseBoundGrid)
    {
      // Far from the mesh a cached bound usually suffices, with the same
      // guarantee (no search, and the hint is left as it was); it is never
      // used below epsilon.
      const double cached = this->BoundGrid.StepBound(x, this->StepRelaxation);
      if (cached >= epsilon)
      {
        return cached;
      }
    }
    bool exact = false;
    const double bound =
      this->Tree.DistanceLowerBound(x, this->StepRelaxation, this->RelaxAbove, exact, &h);
    return exact || bound >= epsilon ? bound : std::sqrt(this->Tree.SquaredDistance(x, h));
  }

  // How much smaller than the distance a step may be (default 0.2: balls of
  // at least 1/1.2 of the largest radius); 0 asks for exact distances (and
  // leaves the bound grid unused). The hierarchy relaxes only farther from
  // a mesh than about one primitive size, where exact queries get expensive.
  void SetStepRelaxation(double relaxation) { this->StepRelaxation = std::max(0.0, relaxation); }
  double GetStepRelaxation() const { return this->StepRelaxation; }

  // Whether steps far from a mesh may take their radius from distance
  // bounds cached on a grid (default on), when those bounds guarantee the
  // same 1/(1 + StepRelaxation) of the distance without a search. The grid
  // is filled when the mesh is set (DistanceBoundGrid.h). Geometries whose
  // distance searches a hierarchy keep their own (MeshSignedDistance, as a
  // CSG operand) and relax their steps only when this is on; analytic ones
  // always take exact radii.
  void SetBoundGrid(bool use) { this->UseBoundGrid = use; }
  bool GetBoundGrid() const { return this->UseBoundGrid; }
  const DistanceBoundGrid<DIM>& StepBoundGrid() const { return this->BoundGrid; }

  ClosestPointResult<DIM> ClosestPoint(const Vec<DIM>& x) const
  {
    return this->Shape ? this->Shape->ClosestPoint(x) : this->Tree.ClosestPoint(x);
  }

  // ClosestPoint for a walk that carries a StepHint (see StepRadius).
  ClosestPointResult<DIM> ClosestPoint(const Vec<DIM>& x, StepHint& hint) const
  {
    return this->Shape ? this->Shape->ClosestPoint(x) : this->Tree.ClosestPoint(x, hint);
  }

  // Unit normal at a closest point (zero where there is none). Only used to
  // pick a side for points exactly on the boundary.
  Vec<DIM> Normal(const ClosestPointResult<DIM>& hit) const
  {
    if (this->Shape)
    {
      return this->Shape->Normal(hit);
    }
    return hit.primitive >= 0 ? this->PrimitiveNormal(hit.primitive) : Vec<DIM>::Zero();
  }

  // Unit normal of a primitive (segment: its left normal; triangle: the
  // right-handed normal of its vertex order); zero for a degenerate one.
  // Only used to pick a side for points exactly on the boundary.
  Vec<DIM> PrimitiveNormal(std::int64_t primitive) const
  {
    return SimplexUnitNormal<DIM>(
      this->Vertices, this->Primitives[static_cast<std::size_t>(primitive)]);
  }

  // Which side of the boundary x lies on, seen from its closest point `hit`:
  // +1 where the oriented normal points to x (front), −1 on the other side
  // (back), 0 on the boundary itself or where the normal is undefined (a
  // degenerate primitive, or x beyond the end of an open curve, level
  // with it).
  int Side(const Vec<DIM>& x, const ClosestPointResult<DIM>& hit) const
  {
    if (hit.primitive < 0)
    {
      return 0;
    }
    // On a mesh, the pseudonormal of the closest point's edge or vertex
    // (SidePseudonormals: a primitive's own normal can point the wrong way
    // past a sharp turn).
    const Vec<DIM> n = this->Shape || this->Pseudonormals.Empty()
      ? this->Normal(hit)
      : this->Pseudonormals.At(this->Vertices, this->Primitives, hit.primitive, hit.barycentric);
    const double d = (x - hit.point).dot(n);
    return d > 0.0 ? 1 : (d < 0.0 ? -1 : 0);
  }

  // The boundary value a walk ending at x takes from its closest point
  // `hit`: g(hit), or for two-sided values the side x lies on (Side), the
  // mean of both sides where no side is defined. Writes Components().
  void Evaluate(const Vec<DIM>& x, const ClosestPointResult<DIM>& hit, double* out) const
  {
    if (!this->TwoSided)
    {
      this->EvaluateStored(hit, out);
      return;
    }
    this->EvaluateSide(this->Side(x, hit), hit, out);
  }

  // The boundary value at a closest point, without a side: g(hit), or for
  // two-sided values the mean of both sides (the value on the boundary
  // itself). Writes Components().
  void Evaluate(const ClosestPointResult<DIM>& hit, double* out) const
  {
    if (!this->TwoSided)
    {
      this->EvaluateStored(hit, out);
      return;
    }
    this->EvaluateSide(0, hit, out);
  }

private:
  // A function's range at every vertex and primitive centroid, or at
  // GeometrySamples' points (ValueRanges); false where a sample is not
  // finite or where there is none.
  bool SampleFunction(std::vector<double>& lowest, std::vector<double>& highest) const
  {
    const std::size_t own = static_cast<std::size_t>(this->Components());
    lowest.assign(own, std::numeric_limits<double>::infinity());
    highest.assign(own, -std::numeric_limits<double>::infinity());
    std::vector<double> value(static_cast<std::size_t>(this->NumberOfComponents));
    bool finite = true;
    auto take = [&](const ClosestPointResult<DIM>& hit) {
      this->EvaluateStored(hit, value.data());
      for (std::size_t i = 0; i < value.size(); ++i)
      {
        const std::size_t c = i % own;
        finite = finite && std::isfinite(value[i]);
        lowest[c] = std::min(lowest[c], value[i]);
        highest[c] = std::max(highest[c], value[i]);
      }
    };
    if (this->Shape)
    {
      for (const ClosestPointResult<DIM>& hit : this->GeometrySamples())
      {
        take(hit);
      }
      return finite && own > 0 && lowest[0] <= highest[0];
    }
    // Each vertex once, read through the first primitive that holds it.
    std::vector<char> seen(this->Vertices.size(), 0);
    for (std::size_t i = 0; i < this->Primitives.size() && finite; ++i)
    {
      const Primitive& p = this->Primitives[i];
      ClosestPointResult<DIM> hit = this->PrimitiveCentroid(i);
      take(hit);
      for (int k = 0; k < DIM; ++k)
      {
        const std::size_t v = static_cast<std::size_t>(p[k]);
        if (!seen[v])
        {
          seen[v] = 1;
          hit.point = this->Vertices[v];
          hit.barycentric = Vec<DIM>::Unit(k);
          take(hit);
        }
      }
    }
    return finite;
  }

  // GeometrySamples' points, in the lattice's order.
  std::vector<ClosestPointResult<DIM>> ProjectLattice() const
  {
    constexpr int n = kRangeLatticeCells;
    const Vec<DIM> cell = (this->Max - this->Min) / n;
    const double reach = cell.norm();
    const double onBoundary = 1e-6 * std::max(this->Diagonal(), 1e-300);
    long long count = 1;
    for (int k = 0; k < DIM; ++k)
    {
      count *= n;
    }
    std::vector<ClosestPointResult<DIM>> hits;
    for (long long index = 0; index < count; ++index)
    {
      Vec<DIM> x;
      long long rest = index;
      for (int k = 0; k < DIM; ++k)
      {
        x[k] = this->Min[k] + (static_cast<double>(rest % n) + 0.5) * cell[k];
        rest /= n;
      }
      if (!(this->Shape->Distance(x) <= reach))
      {
        continue;
      }
      const ClosestPointResult<DIM> hit = this->Shape->ClosestPoint(x);
      if (hit.primitive >= 0 && hit.point.allFinite() &&
        this->Shape->Distance(hit.point) <= onBoundary)
      {
        hits.push_back(hit);
      }
    }
    return hits;
  }

  // One side's values (side +1 front, −1 back, 0 their mean) of a
  // two-sided boundary, from a per-thread buffer of both that grows once.
  void EvaluateSide(int side, const ClosestPointResult<DIM>& hit, double* out) const
  {
    thread_local std::vector<double> both;
    both.resize(static_cast<std::size_t>(this->NumberOfComponents));
    this->EvaluateStored(hit, both.data());
    const int k = this->NumberOfComponents / 2;
    for (int c = 0; c < k; ++c)
    {
      out[c] = side > 0 ? both[c] : (side < 0 ? both[k + c] : 0.5 * (both[c] + both[k + c]));
    }
  }

  // Every stored number at a closest point: barycentric interpolation of
  // point data, or the primitive's own value for cell data.
  void EvaluateStored(const ClosestPointResult<DIM>& hit, double* out) const
  {
    this->EvaluateUnshifted(hit, out);
    if (this->Shift && hit.primitive >= 0)
    {
      out[0] -= this->Shift->Value(hit.point);
    }
  }

  void EvaluateUnshifted(const ClosestPointResult<DIM>& hit, double* out) const
  {
    if (this->ValueFunction)
    {
      this->ValueFunction->Evaluate(hit, out);
      return;
    }
    const int nc = this->NumberOfComponents;
    if (hit.primitive < 0)
    {
      // No closest primitive (a NaN query, e.g. a walk whose distances
      // overflowed): no value, rather than reading before the table.
      for (int c = 0; c < nc; ++c)
      {
        out[c] = std::numeric_limits<double>::quiet_NaN();
      }
      return;
    }
    if (this->Association == ValueAssociation::Cells)
    {
      const double* v = &this->Values[static_cast<std::size_t>(hit.primitive) * nc];
      for (int c = 0; c < nc; ++c)
      {
        out[c] = v[c];
      }
      return;
    }
    const Primitive& p = this->Primitives[static_cast<std::size_t>(hit.primitive)];
    for (int c = 0; c < nc; ++c)
    {
      out[c] = 0.0;
    }
    for (int k = 0; k < DIM; ++k)
    {
      const double w = hit.barycentric[k];
      const double* v = &this->Values[static_cast<std::size_t>(p[k]) * nc];
      for (int c = 0; c < nc; ++c)
      {
        out[c] += w * v[c];
      }
    }
  }

  void Clear()
  {
    this->Vertices.clear();
    this->Primitives.clear();
    this->Values.clear();
    this->Association = ValueAssociation::Points;
    this->ValueFunction.reset();
    this->Shape.reset();
    this->Shift.reset();
    this->TwoSided = false;
    this->FunctionRanges = std::make_shared<SampledRanges>();
    this->GeometryHits = std::make_shared<SampledHits>();
    this->Tree = Bvh<DIM>();
    this->BoundGrid = DistanceBoundGrid<DIM>();
  }

  void SetMeshGeometry(std::vector<Vec<DIM>> vertices, std::vector<Primitive> primitives)
  {
    for (const Primitive& p : primitives)
    {
      for (int k = 0; k < DIM; ++k)
      {
        if (p[k] < 0 || static_cast<std::size_t>(p[k]) >= vertices.size())
        {
          throw std::invalid_argument("boundary primitive refers to a missing vertex");
        }
      }
    }
    this->Clear();
    this->Vertices = std::move(vertices);
    this->Primitives = std::move(primitives);
    this->ComputeBounds();
    this->Tree.Build(this->Vertices, this->Primitives);
    // Relax steps only farther than about one primitive size: nearer, exact
    // queries are already cheap (measured on a 327k-triangle sphere, where
    // this and a relaxation of 0.2 gave the most walks per second).
    double sum = 0.0;
    std::size_t counted = 0;
    for (const Primitive& p : this->Primitives)
    {
      BoundingBox<DIM> box;
      for (int k = 0; k < DIM; ++k)
      {
        box.Expand(this->Vertices[p[k]]);
      }
      const double diagonal = box.Diagonal();
      if (std::isfinite(diagonal))
      {
        sum += diagonal;
        ++counted;
      }
    }
    this->RelaxAbove = counted ? 1.0 * sum / static_cast<double>(counted) : 0.0;

    // About one grid vertex per two primitives (at least 64, at most
    // kBoundGridVertices): filling it costs about as much as building the
    // hierarchy. Its bounds are relaxed queries within 5% (tighter bounds
    // give larger steps; a relaxed query costs more as the relaxation
    // shrinks).
    const std::size_t gridVertices = std::min(
      std::max<std::size_t>(this->Primitives.size() / 2, 64), kBoundGridVertices);
    BoundingBox<DIM> box(this->Min, this->Max);
    const Bvh<DIM>& tree = this->Tree;
    this->BoundGrid.template Build<typename Bvh<DIM>::NearestHint>(box, gridVertices,
      kBoundGridBoundRelaxation,
      [&tree](const Vec<DIM>& v, typename Bvh<DIM>::NearestHint& hint)
      {
        bool exact = false;
        return tree.DistanceLowerBound(v, kBoundGridBoundRelaxation, 0.0, exact, &hint);
      });
  }

  void ComputeBounds()
  {
    const double inf = std::numeric_limits<double>::infinity();
    this->Min.setConstant(inf);
    this->Max.setConstant(-inf);
    for (const Primitive& p : this->Primitives)
    {
      for (int k = 0; k < DIM; ++k)
      {
        this->Min = this->Min.cwiseMin(this->Vertices[p[k]]);
        this->Max = this->Max.cwiseMax(this->Vertices[p[k]]);
      }
    }
    if (this->Primitives.empty())
    {
      this->Min.setZero();
      this->Max.setZero();
    }
  }

  std::vector<Vec<DIM>> Vertices;
  std::vector<Primitive> Primitives;
  ValueAssociation Association = ValueAssociation::Points;
  // Stored numbers per tuple (both sides' for two-sided values).
  int NumberOfComponents = 1;
  bool TwoSided = false;
  SidePseudonormals<DIM> Pseudonormals; // built for two-sided mesh values
  std::vector<double> Values;
  std::shared_ptr<const BoundaryValueFunction<DIM>> ValueFunction;
  std::shared_ptr<const BoundaryGeometry<DIM>> Shape;
  std::shared_ptr<const PolynomialShift<DIM>> Shift;
  // A value function's sampled range (ValueRanges), taken once; a new one
  // whenever the values or their reading change (copies share it until
  // then).
  struct SampledRanges
  {
    std::once_flag Once;
    bool Known = false;
    std::vector<double> Low, High;
  };
  std::shared_ptr<SampledRanges> FunctionRanges = std::make_shared<SampledRanges>();
  // GeometrySamples, taken once per geometry (copies share them).
  struct SampledHits
  {
    std::once_flag Once;
    std::vector<ClosestPointResult<DIM>> Hits;
  };
  std::shared_ptr<SampledHits> GeometryHits = std::make_shared<SampledHits>();
  // Lattice cells per axis of GeometrySamples: 32³ centres in 3D, 128² in
  // 2D (a few milliseconds for a sphere; a CSG of meshes, a few tens).
  static constexpr int kRangeLatticeCells = DIM == 3 ? 32 : 128;
  static constexpr std::size_t kBoundGridVertices = 300000;
  static constexpr double kBoundGridBoundRelaxation = 0.05;
  double StepRelaxation = 0.2;
  double RelaxAbove = 0.0;
  bool UseBoundGrid = true;
  DistanceBoundGrid<DIM> BoundGrid;
  Vec<DIM> Min = Vec<DIM>::Zero();
  Vec<DIM> Max = Vec<DIM>::Zero();
  Bvh<DIM> Tree;
};

// Values of one boundary sampled at the closest point of another: an
// implicit surface taking g from a mesh that carries it (the mesh need not
// coincide with the surface; each boundary point takes the value of the
// nearest mesh point).
template <int DIM>
class SampledBoundaryValues final : public BoundaryValueFunction<DIM>
{
public:
  explicit SampledBoundaryValues(std::shared_ptr<const Boundary<DIM>> carrier)
    : Carrier(std::move(carrier))
  {
    if (!this->Carrier || this->Carrier->Empty())
    {
      throw std::invalid_argument("sampled boundary values: the carrier is empty");
    }
  }

  int Components() const override { return this->Carrier->Components(); }

  void Evaluate(const ClosestPointResult<DIM>& hit, double* out) const override
  {
    this->Carrier->Evaluate(this->Carrier->ClosestPoint(hit.point), out);
  }

private:
  std::shared_ptr<const Boundary<DIM>> Carrier;
};
} // namespace gridfree

#endif
