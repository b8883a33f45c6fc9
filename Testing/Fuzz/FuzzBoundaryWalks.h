// Fuzz body: arbitrary bytes -> a boundary soup (2D segments or 3D
// triangles), boundary values and probe points, run through the core's BVH
// (Build, Validate, Distance, ClosestPoint, DistanceLowerBound, Intersect,
// Occluded) and a few short walks (Boundary + WalkOnSpheresEstimator).
//
// No libFuzzer dependency: the libFuzzer entry point (FuzzBoundaryWalks.cxx)
// and the GoogleTest replay of past findings (Testing/Core/problem/
// TestFuzzRegressions.cxx) both call gridfree::fuzz::RunBoundaryWalks.
// A broken invariant calls Fail(), which prints the reason and aborts, so
// libFuzzer records the input as a crash.
//
// The contract (see Documentation/draft-fuzzing.md): the VTK filter rejects
// NaN/inf coordinates of referenced points and NaN/inf boundary values, and
// drops exactly degenerate cells, before the core sees them; it passes any
// finite coordinates (huge, tiny, subnormal), duplicate cells, near-degenerate
// cells and any probe point. Flag bit 1 of the first byte selects
//  * contract inputs (bit clear): the soup is cleaned the way the filter does
//    it (cells using a non-finite point or exactly degenerate are dropped,
//    indices taken modulo the vertex count, non-finite values replaced by 0);
//    every invariant below must hold;
//  * raw inputs (bit set): everything goes to the core unfiltered (NaN/inf
//    coordinates and values, out-of-range and repeated indices, degenerate
//    cells). Bvh::Build may throw std::out_of_range and Boundary::Set
//    std::invalid_argument; otherwise the core must neither crash, hang nor
//    trip a sanitizer, but no numerical invariant is checked.
//
// Input layout (missing bytes read as 0):
//   byte 0   flags: bit 0 2D (else 3D), bit 1 raw, bit 2 cell values (else
//            point values), bit 3 two components, bits 4-5 equation (Laplace,
//            Laplace with exact steps, biharmonic, screened Poisson), bit 6
//            exterior Russian roulette (else exact return), bit 7 nested
//            biharmonic walks
//   byte 1   vertex count (0..255)
//   byte 2   primitive count (0..255)
//   byte 3   probe count (low 4 bits)
//   byte 4   epsilon selector
//   then the vertices (DIM numbers each), the primitives (DIM indices each),
//   the values (one per component per tuple), the probes (3 numbers each).
//   A number is one selector byte s: s < 0xc0 a grid value (s - 96) / 8;
//   0xc0..0xdf a special value (0, +-1e300, +-1e-300, subnormals, DBL_MAX,
//   NaN, +-inf, ...); 0xe0..0xef the next byte's grid value times a power of
//   ten (1e-320 .. 1e307); 0xf0..0xff the next 8 bytes as a raw double.
//   An index is one byte b: b < 250 the index b; 250..255 special (-1, the
//   vertex count, INT64_MAX, INT64_MIN, 8 raw bytes, count + 1000).
#ifndef GRIDFREE_TESTING_FUZZ_FUZZBOUNDARYWALKS_H
#define GRIDFREE_TESTING_FUZZ_FUZZBOUNDARYWALKS_H

#include <gridfree/boundary/Boundary.h>
#include <gridfree/geometry/Bvh.h>
#include <gridfree/statistics/RunningStatistics.h>
#include <gridfree/estimators/WalkOnSpheres.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

namespace gridfree
{
namespace fuzz
{
/// Reads numbers and indices from the input; past its end everything is 0.
class ByteReader
{
public:
  ByteReader(const std::uint8_t* data, std::size_t size)
    : Data(data)
    , Size(size)
  {
  }

  std::uint8_t Byte() { return this->Pos < this->Size ? this->Data[this->Pos++] : 0; }

  template <class T>
  T Raw()
  {
    unsigned char bytes[sizeof(T)] = {};
    for (auto& b : bytes)
    {
      b = this->Byte();
    }
    T v;
    std::memcpy(&v, bytes, sizeof(T));
    return v;
  }

  double Number()
  {
    const std::uint8_t s = this->Byte();
    if (s < 0xc0)
    {
      return (static_cast<int>(s) - 96) / 8.0;
    }
    if (s < 0xe0)
    {
      constexpr double inf = std::numeric_limits<double>::infinity();
      static const double specials[32] = { 0.0, -0.0, 1.0, -1.0, 1e300, -1e300, 1e-300,
        -1e-300, std::numeric_limits<double>::denorm_min(),
        -std::numeric_limits<double>::denorm_min(), DBL_MIN, 1e-310, DBL_MAX, -DBL_MAX, 1e18,
        -1e18, 1e150, 1e-150, 1e154, 1e-20, 1e20, 1.0 + DBL_EPSILON, 1.0 - DBL_EPSILON / 2,
        3.4e38, 3.5e38, 1e-45, std::numeric_limits<double>::quiet_NaN(), inf, -inf,
        -std::numeric_limits<double>::quiet_NaN(), 1e8, 0.1 };
      return specials[s - 0xc0];
    }
    if (s < 0xf0)
    {
      static const int exponents[16] = { -320, -300, -200, -100, -30, -10, -5, 5, 10, 30, 100,
        200, 300, 307, -307, 0 };
      const double grid = (static_cast<int>(this->Byte()) - 128) / 8.0;
      return grid * std::pow(10.0, exponents[s - 0xe0]);
    }
    return this->Raw<double>();
  }

  std::int64_t Index(std::int64_t count)
  {
    const std::uint8_t b = this->Byte();
    switch (b)
    {
      case 250:
        return -1;
      case 251:
        return count;
      case 252:
        return std::numeric_limits<std::int64_t>::max();
      case 253:
        return std::numeric_limits<std::int64_t>::min();
      case 254:
        return this->Raw<std::int64_t>();
      case 255:
        return count + 1000;
      default:
        return b;
    }
  }

private:
  const std::uint8_t* Data;
  std::size_t Size;
  std::size_t Pos = 0;
};

[[noreturn]] inline void Fail(const char* what, double a = 0.0, double b = 0.0)
{
  std::fprintf(stderr, "FuzzBoundaryWalks: invariant broken: %s (%.17g, %.17g)\n", what, a, b);
  std::fflush(stderr);
  std::abort();
}

inline void Check(bool ok, const char* what, double a = 0.0, double b = 0.0)
{
  if (!ok)
  {
    Fail(what, a, b);
  }
}

/// Largest magnitude of the finite numbers whose squares, products and sums
/// of a few of them stay finite and normal in double: inputs within
/// [kTiny, kHuge] (or 0) are "moderate", and only there must a finite walk
/// give a finite estimate.
constexpr double kHuge = 1e100;
constexpr double kTiny = 1e-100;
/// Coordinates up to this magnitude fit the float boxes of the BVH nodes.
constexpr double kFloatRange = 1e38;

inline bool Moderate(double v)
{
  const double a = std::abs(v);
  return a == 0.0 || (a >= kTiny && a <= kHuge);
}

template <int DIM>
bool Moderate(const Vec<DIM>& v)
{
  for (int k = 0; k < DIM; ++k)
  {
    if (!Moderate(v[k]))
    {
      return false;
    }
  }
  return true;
}

/// The filter's cleaning (GridFreeBoundaryConversion.cxx): drops exactly
/// degenerate primitives. Segments: equal end points; triangles: zero cross
/// product of the edges.
inline bool IsDegenerate(const std::vector<Vec<2>>& v, const std::array<std::int64_t, 2>& p)
{
  return v[p[0]] == v[p[1]];
}

inline bool IsDegenerate(const std::vector<Vec<3>>& v, const std::array<std::int64_t, 3>& p)
{
  const Vec3 e1 = v[p[1]] - v[p[0]];
  const Vec3 e2 = v[p[2]] - v[p[0]];
  return e1.cross(e2) == Vec3::Zero();
}

template <int DIM>
void RunDimension(ByteReader& in, std::uint8_t flags)
{
  using Primitive = typename Bvh<DIM>::Primitive;
  const bool raw = flags & 2;
  const bool cellValues = flags & 4;
  const int equation = (flags >> 4) & 3;
  const bool biharmonic = equation == 2;
  const int components = biharmonic ? 2 : ((flags & 8) ? 2 : 1);

  const int numVertices = in.Byte();
  const int numPrimitives = in.Byte();
  const int numProbes = in.Byte() & 15;
  const std::uint8_t epsilonSelector = in.Byte();

  std::vector<Vec<DIM>> vertices(static_cast<std::size_t>(numVertices));
  for (auto& v : vertices)
  {
    for (int k = 0; k < DIM; ++k)
    {
      v[k] = in.Number();
    }
  }
  std::vector<Primitive> primitives;
  primitives.reserve(static_cast<std::size_t>(numPrimitives));
  for (int i = 0; i < numPrimitives; ++i)
  {
    Primitive p;
    for (int k = 0; k < DIM; ++k)
    {
      p[k] = in.Index(numVertices);
    }
    primitives.push_back(p);
  }

  if (!raw)
  {
    // What the filter lets through: in-range indices (modulo here, so that
    // the input stays useful), no primitive using a non-finite point, no
    // exactly degenerate primitive.
    std::vector<Primitive> kept;
    for (Primitive p : primitives)
    {
      if (numVertices == 0)
      {
        break;
      }
      bool finite = true;
      for (auto& id : p)
      {
        id = static_cast<std::int64_t>(static_cast<std::uint64_t>(id) % numVertices);
        finite = finite && vertices[id].allFinite();
      }
      if (finite && !IsDegenerate(vertices, p))
      {
        kept.push_back(p);
      }
    }
    primitives.swap(kept);
  }

  const std::size_t tuples = cellValues ? primitives.size() : vertices.size();
  std::vector<double> values(tuples * static_cast<std::size_t>(components));
  for (double& v : values)
  {
    v = in.Number();
    if (!raw && !std::isfinite(v))
    {
      v = 0.0;
    }
  }

  std::vector<Vec<DIM>> probes(static_cast<std::size_t>(numProbes));
  std::vector<std::array<double, 3>> probeXYZ(static_cast<std::size_t>(numProbes));
  for (int i = 0; i < numProbes; ++i)
  {
    for (int k = 0; k < 3; ++k)
    {
      probeXYZ[i][k] = in.Number();
    }
    for (int k = 0; k < DIM; ++k)
    {
      probes[i][k] = probeXYZ[i][k];
    }
  }

  // Is the whole input moderate (all referenced coordinates, values)?
  bool moderateBoundary = true;
  for (const Primitive& p : primitives)
  {
    for (const auto id : p)
    {
      if (id >= 0 && id < numVertices)
      {
        moderateBoundary = moderateBoundary && Moderate<DIM>(vertices[id]);
      }
    }
  }
  bool floatBoundary = true;
  for (const Primitive& p : primitives)
  {
    for (const auto id : p)
    {
      if (id >= 0 && id < numVertices)
      {
        floatBoundary = floatBoundary && vertices[id].cwiseAbs().maxCoeff() <= kFloatRange;
      }
    }
  }
  bool moderateValues = true;
  for (const double v : values)
  {
    moderateValues = moderateValues && Moderate(v);
  }

  //----------------------------------------------------------------------------
  // BVH alone.
  Bvh<DIM> bvh;
  try
  {
    bvh.Build(vertices, primitives);
  }
  catch (const std::out_of_range&)
  {
    Check(raw, "Bvh::Build threw std::out_of_range for in-range indices");
    return; // documented for a missing vertex; Boundary::Set rejects it too
  }
  Check(bvh.NumberOfPrimitives() == primitives.size(), "primitive count");
  if (!raw)
  {
    // Nodes store float boxes: beyond the float range (~3.4e38) bounds
    // decode to NaN, which the queries treat as "always visit" (no pruning,
    // as documented in Bvh.h) but Validate() cannot confirm.
    if (floatBoundary)
    {
      Check(bvh.Validate(), "Bvh::Validate");
    }
  }

  for (std::size_t i = 0; i < probes.size(); ++i)
  {
    const Vec<DIM>& x = probes[i];
    const double d = bvh.Distance(x);
    const auto cp = bvh.ClosestPoint(x);
    bool exact = false;
    const double relaxation = 0.2;
    const double lower = bvh.DistanceLowerBound(x, relaxation, 0.0, exact);
    bool exact2 = false;
    const double lowerExactNear = bvh.DistanceLowerBound(x, relaxation, 1.0, exact2);

    // A ray from the probe towards the next probe, and one to its closest point.
    const Vec<DIM>& y = probes[(i + 1) % probes.size()];
    const Vec<DIM> direction = y - x;
    const auto hit = bvh.Intersect(x, direction, 1.0, 0.0);
    const bool occluded = bvh.Occluded(x, direction, 1.0, 0.0);
    const auto hitAll = bvh.Intersect(x, cp.point - x);

    if (raw || primitives.empty())
    {
      if (primitives.empty())
      {
        Check(std::isinf(d) && !hit.Hit() && !occluded && cp.primitive < 0, "empty hierarchy");
      }
      continue;
    }
    const bool finiteQuery = x.allFinite();
    if (!finiteQuery)
    {
      continue; // the filter gives non-finite probes NaN samples, not queries
    }
    // Invariants for contract inputs and finite queries.
    Check(cp.primitive >= 0 && cp.primitive < static_cast<std::int64_t>(primitives.size()),
      "ClosestPoint primitive index", static_cast<double>(cp.primitive));
    // Beyond ~1e154 squared distances overflow: Distance() is then inf and
    // the closest point's distance inf or NaN.
    Check(cp.distance == d || (std::isinf(d) && std::isnan(cp.distance)),
      "ClosestPoint distance == Distance", cp.distance, d);
    Check(!(lower > d), "DistanceLowerBound <= Distance", lower, d);
    Check(!(lowerExactNear > d), "DistanceLowerBound (exact near) <= Distance", lowerExactNear, d);
    if (exact)
    {
      Check(lower == d || (std::isnan(lower) && std::isnan(d)),
        "exact DistanceLowerBound == Distance", lower, d);
    }
    const bool moderateQuery = moderateBoundary && Moderate<DIM>(x);
    if (moderateQuery)
    {
      Check(std::isfinite(d), "finite distance", d);
      Check(lower >= d / (1.0 + relaxation) * (1.0 - 1e-9), "DistanceLowerBound too small",
        lower, d);
      Check(cp.point.allFinite() && cp.barycentric.allFinite(), "finite closest point");
      const double gap = (cp.point - x).norm();
      Check(std::abs(gap - d) <= 1e-9 * (d + x.norm() + cp.point.norm()),
        "closest point within distance of the query", gap, d);
      double wsum = cp.barycentric.sum();
      Check(std::abs(wsum - 1.0) <= 1e-9, "barycentric weights sum to 1", wsum);
    }
    Check(occluded == hit.Hit(), "Occluded == Intersect().Hit()", occluded, hit.Hit());
    for (const auto* h : { &hit, &hitAll })
    {
      if (h->Hit())
      {
        Check(h->primitive < static_cast<std::int64_t>(primitives.size()), "hit primitive");
        Check(h->t >= 0.0, "hit t >= tMin", h->t);
        if (moderateQuery && Moderate<DIM>(y))
        {
          Check(std::isfinite(h->t) && h->barycentric.allFinite(), "finite hit", h->t);
        }
      }
    }
    if (hit.Hit())
    {
      Check(hit.t <= 1.0, "hit t <= tMax", hit.t);
    }
  }

  //----------------------------------------------------------------------------
  // Walks through Boundary + WalkOnSpheresEstimator, as the filter runs them.
  Boundary<DIM> boundary;
  try
  {
    boundary.Set(vertices, primitives,
      cellValues ? ValueAssociation::Cells : ValueAssociation::Points, components, values);
  }
  catch (const std::invalid_argument&)
  {
    Check(raw, "Boundary::Set threw std::invalid_argument for a contract input");
    return;
  }
  catch (const std::out_of_range&)
  {
    Check(raw, "Boundary::Set threw std::out_of_range for a contract input");
    return;
  }
  if (boundary.Empty() || probes.empty())
  {
    return; // the filter refuses an empty boundary
  }
  if (equation == 1)
  {
    boundary.SetStepRelaxation(0.0);
  }

  WalkSettings settings;
  settings.MaxSteps = 24;
  settings.Problem = biharmonic ? Equation::Biharmonic
                                : (equation == 3 ? Equation::ScreenedPoisson : Equation::Laplace);
  settings.ScreeningCoefficient = 1.0 + (epsilonSelector >> 4);
  settings.Exterior =
    (flags & 64) ? ExteriorStrategy::RussianRoulette : ExteriorStrategy::ExactReturn;
  settings.Biharmonic =
    (flags & 128) ? BiharmonicStrategy::Nested : BiharmonicStrategy::TreeWalking;
  settings.NestedWalks = 2;
  static const double relative[4] = { 1e-4, 1e-2, 1e-8, 0.3 };
  static const double absolute[4] = { 1e-3, 1e-300, 1.0, 1e300 };
  const double diagonal = boundary.Diagonal();
  settings.Epsilon = (epsilonSelector & 4) ? absolute[epsilonSelector & 3]
                                           : relative[epsilonSelector & 3] * diagonal;
  if (!(settings.Epsilon > 0.0))
  {
    if (!raw)
    {
      return; // the filter rejects a non-positive epsilon
    }
    settings.Epsilon = (epsilonSelector & 8) ? 0.0 : std::numeric_limits<double>::quiet_NaN();
  }

  WalkOnSpheresEstimator<DIM> estimator(boundary, settings);
  // Walks are the slow part (a soup of coincident primitives defeats the
  // hierarchy): 2 walks from each of the first 4 probes.
  const int walks = 2;
  for (std::size_t i = 0; i < std::min<std::size_t>(probes.size(), 4); ++i)
  {
    RunningStatistics stats(estimator.OutputComponents());
    WalkCounters counters;
    estimator.EstimatePoint(probeXYZ[i].data(), 7, 0, walks, stats, counters);
    Check(counters.Walks == static_cast<std::uint64_t>(walks), "walk count");
    if (raw || !probes[i].allFinite())
    {
      continue;
    }
    Check(stats.SampleCount() == static_cast<std::size_t>(walks), "sample count");
    // Finite inputs give a finite estimate. Moderate inputs only: values up
    // to DBL_MAX overflow when interpolated or averaged, and coordinates
    // beyond ~1e150 overflow squared distances.
    if (moderateBoundary && moderateValues && Moderate<DIM>(probes[i]) &&
      std::isfinite(settings.Epsilon))
    {
      for (int c = 0; c < estimator.OutputComponents(); ++c)
      {
        Check(std::isfinite(stats.GetMean(c)), "finite walk estimate", stats.GetMean(c));
      }
    }
  }
}

/// The fuzz body: returns 0 (libFuzzer's convention); a finding aborts.
inline int RunBoundaryWalks(const std::uint8_t* data, std::size_t size)
{
  ByteReader in(data, size);
  const std::uint8_t flags = in.Byte();
  if (flags & 1)
  {
    RunDimension<2>(in, flags);
  }
  else
  {
    RunDimension<3>(in, flags);
  }
  return 0;
}
} // namespace fuzz
} // namespace gridfree

#endif
