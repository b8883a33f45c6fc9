// Concentrated source terms: point sources and polyline curve sources.
//
// A source term f made of Dirac deltas is never hit by sampling the ball
// uniformly, so each walk step samples it explicitly inside its empty ball
// B(x, R) (importance sampling, paper Sec. 4.2.2):
//
// * a point source of strength s at z contributes s G(x, z) when |z - x| < R;
// * a curve source gamma with strength s (linear along each segment)
//   contributes s(z) G(x, z) / p(z), where z is drawn on gamma inside B with
//   density p (w.r.t. arc length) proportional to 1/|z - x|, which cancels
//   G's pole in 3D. This is an unbiased, one-sample estimate of the integral
//   of s G over gamma inside B.
//
// This file only does the geometry and the sampling; the caller supplies the
// Green's function. Both source sets are indexed by a BallQueryTree, so a
// query costs O(log n + hits). Queries are const and, once a per-thread
// Scratch has grown to its working size, allocation free.
#ifndef GRIDFREE_SOURCES_CONCENTRATED_SOURCES_H
#define GRIDFREE_SOURCES_CONCENTRATED_SOURCES_H

#include <gridfree/geometry/BallQueryTree.h>
#include <gridfree/geometry/BoundingBox.h>
#include <gridfree/sampling/Random.h>
#include <gridfree/math/Vector.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace gridfree
{
namespace detail
{
inline void CheckComponents(int components, const char* what)
{
  if (components < 1)
  {
    throw std::invalid_argument(std::string(what) + ": components must be at least 1");
  }
}

inline void CheckFinite(const std::vector<double>& values, const char* what)
{
  for (const double v : values)
  {
    if (!std::isfinite(v))
    {
      throw std::invalid_argument(std::string(what) + ": non-finite strength");
    }
  }
}

template <int DIM>
void CheckFinite(const std::vector<Vec<DIM>>& points, const char* what)
{
  for (const Vec<DIM>& p : points)
  {
    if (!p.allFinite())
    {
      throw std::invalid_argument(std::string(what) + ": non-finite coordinate");
    }
  }
}

/// Parameter interval [t0, t1] of the segment a + t d (t in [0, 1], length
/// |d| = length > 0) inside the open ball B(x, sqrt(radius2)). Returns false
/// if the intersection is empty or a single point (tangent).
///
/// The quadratic |a - x + t d|^2 = radius2 is solved in its geometric form:
/// its roots are tc -/+ sqrt(radius2 - h^2) / |d|, with tc the parameter of
/// the line's closest point to x and h that distance. Computing h from the
/// perpendicular vector avoids the cancellation of b^2 - a c when the segment
/// starts far from a small ball.
template <int DIM>
inline bool ClipSegmentToBall(const Vec<DIM>& a, const Vec<DIM>& d, double length,
  const Vec<DIM>& x, double radius2, double& t0, double& t1)
{
  const Vec<DIM> f = a - x;
  const double tc = -f.dot(d) / (length * length);
  const double h2 = (f + tc * d).squaredNorm();
  const double w2 = radius2 - h2;
  if (!(w2 > 0.0))
  {
    return false;
  }
  const double half = std::sqrt(w2) / length;
  t0 = std::max(0.0, tc - half);
  t1 = std::min(1.0, tc + half);
  return t1 > t0;
}
} // namespace detail

//------------------------------------------------------------------------------
/// Point sources with `components` strength values each.
template <int DIM>
class PointSources
{
public:
  /// Replaces the sources. `strengths` holds `components` numbers per source,
  /// source-major. Throws std::invalid_argument on a size mismatch,
  /// components < 1 or non-finite input; the old content is then kept.
  void Set(std::vector<Vec<DIM>> positions, int components, std::vector<double> strengths)
  {
    const char* what = "gridfree::PointSources";
    detail::CheckComponents(components, what);
    if (strengths.size() != positions.size() * static_cast<std::size_t>(components))
    {
      throw std::invalid_argument("gridfree::PointSources: strengths size is not "
                                  "components * number of positions");
    }
    detail::CheckFinite<DIM>(positions, what);
    detail::CheckFinite(strengths, what);

    BallQueryTree<DIM> tree(positions, positions);
    this->Tree = std::move(tree);
    this->Positions = std::move(positions);
    this->Strengths = std::move(strengths);
    this->NumberOfComponents = components;
  }

  bool Empty() const { return this->Positions.empty(); }
  int Components() const { return this->NumberOfComponents; }
  std::size_t Size() const { return this->Positions.size(); }

  /// Bounds of the positions; a zero box at the origin when empty.
  Vec<DIM> BoundsMin() const { return this->Empty() ? Vec<DIM>::Zero() : this->Tree.Bounds().Min; }
  Vec<DIM> BoundsMax() const { return this->Empty() ? Vec<DIM>::Zero() : this->Tree.Bounds().Max; }

  /// Calls visit(const Vec<DIM>& z, const double* strength) for every source
  /// strictly inside the ball: |z - x| < radius. `strength` points to
  /// Components() numbers. A source on the sphere is excluded because the
  /// Green's function of the ball vanishes there anyway.
  template <class Visit>
  void ForEachInBall(const Vec<DIM>& x, double radius, Visit&& visit) const
  {
    const double radius2 = radius * radius;
    const std::size_t nc = static_cast<std::size_t>(this->NumberOfComponents);
    this->Tree.ForEachOverlappingBall(x, radius, [&](std::size_t i) {
      const Vec<DIM>& z = this->Positions[i];
      if ((z - x).squaredNorm() < radius2)
      {
        visit(z, this->Strengths.data() + i * nc);
      }
    });
  }

private:
  std::vector<Vec<DIM>> Positions;
  std::vector<double> Strengths;
  int NumberOfComponents = 1;
  BallQueryTree<DIM> Tree;
};

//------------------------------------------------------------------------------
/// A piece a + t d, t in [t0, t1], of a segment seen from x in the coordinate
/// u = asinh(l/h): l is arc length along the segment's line from x's foot on
/// it and h the line's distance from x (at least `floor`, so that a point on
/// the line keeps the integrals finite). dl = h cosh(u) du = r du with r the
/// distance from x, so u uniform on [U0, U1] samples the piece with density
/// ∝ 1/r, the Green's function's singularity in 3D, and Width() = ∫ dl/r.
template <int DIM>
struct NearLinePiece
{
  double Length = 0.0; // |d|
  double Foot = 0.0;   // the foot, in arc length from a
  double H = 0.0;
  double U0 = 0.0, U1 = 0.0;
  double T0 = 0.0, T1 = 0.0;

  NearLinePiece(const Vec<DIM>& a, const Vec<DIM>& d, double t0, double t1, const Vec<DIM>& x,
    double floor)
    : Length(d.norm())
    , T0(t0)
    , T1(t1)
  {
    const Vec<DIM> along = d / this->Length;
    this->Foot = (x - a).dot(along);
    this->H = std::max((a + this->Foot * along - x).norm(), floor);
    this->U0 = std::asinh((t0 * this->Length - this->Foot) / this->H);
    this->U1 = std::asinh((t1 * this->Length - this->Foot) / this->H);
  }

  /// U1 − U0, without the cancellation of two large asinh of one sign:
  /// asinh(q) − asinh(p) = asinh((q² − p²)/(q√(1+p²) + p√(1+q²))).
  double Width() const
  {
    const double p = (this->T0 * this->Length - this->Foot) / this->H;
    const double q = (this->T1 * this->Length - this->Foot) / this->H;
    if (p * q > 0.0)
    {
      return std::asinh((q - p) * (q + p) / (q * std::sqrt(1.0 + p * p) + p * std::sqrt(1.0 + q * q)));
    }
    return this->U1 - this->U0;
  }

  /// The segment's parameter t at u, kept inside [T0, T1] against rounding.
  double ParameterAt(double u) const
  {
    return std::clamp((this->Foot + this->H * std::sinh(u)) / this->Length, this->T0, this->T1);
  }

  /// dl/du at u: the distance from x to the point at u.
  double Jacobian(double u) const { return this->H * std::cosh(u); }
};

//------------------------------------------------------------------------------
/// Polyline curve sources: segments between vertices, with `components`
/// strength values per vertex interpolated linearly along each segment.
template <int DIM>
class CurveSources
{
public:
  /// Per-thread buffers reused across queries, so that a query only
  /// allocates while they grow to the largest number of hit segments.
  struct Scratch
  {
    struct Piece
    {
      std::uint32_t Segment; // index into the kept segments
      double T0, T1;         // parameter interval inside the ball
    };
    std::vector<Piece> Pieces;
    std::vector<double> Cumulative; // running sum of the pieces' ∫ dl/|z − x|
  };

  /// Replaces the curves. `segments` are pairs of indices into `vertices`;
  /// `strengths` holds `components` numbers per vertex, vertex-major.
  /// Zero-length segments carry no measure and are dropped. Throws
  /// std::invalid_argument on a size mismatch, components < 1, an index
  /// outside `vertices` or non-finite input; the old content is then kept.
  void Set(std::vector<Vec<DIM>> vertices, std::vector<std::array<std::int64_t, 2>> segments,
    int components, std::vector<double> strengths)
  {
    const char* what = "gridfree::CurveSources";
    detail::CheckComponents(components, what);
    if (strengths.size() != vertices.size() * static_cast<std::size_t>(components))
    {
      throw std::invalid_argument("gridfree::CurveSources: strengths size is not "
                                  "components * number of vertices");
    }
    detail::CheckFinite<DIM>(vertices, what);
    detail::CheckFinite(strengths, what);

    const auto numVertices = static_cast<std::int64_t>(vertices.size());
    std::vector<SegmentData> kept;
    kept.reserve(segments.size());
    std::vector<Vec<DIM>> boxMin, boxMax;
    boxMin.reserve(segments.size());
    boxMax.reserve(segments.size());
    double total = 0.0;
    for (const auto& s : segments)
    {
      if (s[0] < 0 || s[0] >= numVertices || s[1] < 0 || s[1] >= numVertices)
      {
        throw std::invalid_argument("gridfree::CurveSources: segment references a missing vertex");
      }
      SegmentData d;
      d.A = vertices[s[0]];
      d.D = vertices[s[1]] - d.A;
      d.Length = d.D.norm();
      d.V0 = s[0];
      d.V1 = s[1];
      if (!std::isfinite(d.Length))
      {
        throw std::invalid_argument("gridfree::CurveSources: segment length overflows");
      }
      if (!(d.Length > 0.0))
      {
        continue;
      }
      boxMin.push_back(vertices[s[0]].cwiseMin(vertices[s[1]]));
      boxMax.push_back(vertices[s[0]].cwiseMax(vertices[s[1]]));
      kept.push_back(d);
      total += d.Length;
    }

    BallQueryTree<DIM> tree(boxMin, boxMax);
    this->Tree = std::move(tree);
    this->Segments = std::move(kept);
    this->Strengths = std::move(strengths);
    this->NumberOfComponents = components;
    this->Total = total;
  }

  bool Empty() const { return this->Segments.empty(); }
  int Components() const { return this->NumberOfComponents; }
  std::size_t NumberOfSegments() const { return this->Segments.size(); }
  double TotalLength() const { return this->Total; }

  /// Bounds of the kept segments; a zero box at the origin when empty.
  Vec<DIM> BoundsMin() const { return this->Empty() ? Vec<DIM>::Zero() : this->Tree.Bounds().Min; }
  Vec<DIM> BoundsMax() const { return this->Empty() ? Vec<DIM>::Zero() : this->Tree.Bounds().Max; }

  /// Samples z on the part of the curves inside the open ball B(x, radius),
  /// with density (w.r.t. arc length) proportional to 1/|z − x|. The Green's
  /// function of a ball behaves as 1/r near its centre in 3D, so a point
  /// sampled uniformly along the curve gives L·G(r), which is large and rare
  /// when a walk passes close to the curve (a heavy tail that a few hundred
  /// walks misreport; in 2D, log r is milder); with this density the sample
  /// is G(r)·r·∫dl/r, bounded by a logarithm of the pieces' extent over the
  /// walk's distance h from their lines. Writes z, its linearly
  /// interpolated strength (Components() numbers) and 1/p(z), the factor that
  /// makes f(z)/p(z) an unbiased estimate of ∫ f dl over that part; returns
  /// false, with inverseDensity = 0 and z, strength untouched, if the part is
  /// empty. One random number per call.
  bool SampleInBall(const Vec<DIM>& x, double radius, RandomStream& rng, Scratch& scratch,
    Vec<DIM>& z, double* strength, double& inverseDensity) const
  {
    const double length = this->Clip(x, radius, scratch);
    if (!(length > 0.0))
    {
      inverseDensity = 0.0;
      return false;
    }

    // Each piece's ∫ dl/r (NearLinePiece), then the piece by its share of
    // the sum and u uniformly within it.
    const double floor = 1e-12 * radius;
    auto& cum = scratch.Cumulative;
    cum.clear();
    double total = 0.0;
    for (const auto& piece : scratch.Pieces)
    {
      const SegmentData& s = this->Segments[piece.Segment];
      total += NearLinePiece<DIM>(s.A, s.D, piece.T0, piece.T1, x, floor).Width();
      cum.push_back(total);
    }
    if (!(total > 0.0) || !std::isfinite(total))
    {
      inverseDensity = 0.0;
      return false;
    }
    const double v = rng.NextDouble() * total;
    std::size_t k = static_cast<std::size_t>(std::upper_bound(cum.begin(), cum.end(), v) - cum.begin());
    // v can round up to the total; it then belongs to the last piece.
    k = std::min(k, cum.size() - 1);
    const auto& piece = scratch.Pieces[k];
    const SegmentData& s = this->Segments[piece.Segment];
    const NearLinePiece<DIM> near(s.A, s.D, piece.T0, piece.T1, x, floor);
    const double start = k == 0 ? 0.0 : cum[k - 1];
    const double width = cum[k] - start;
    const double share = width > 0.0 ? std::clamp((v - start) / width, 0.0, 1.0) : 0.0;
    const double u = near.U0 + share * near.Width();
    const double t = near.ParameterAt(u);

    z = s.A + t * s.D;
    inverseDensity = total * near.Jacobian(u);
    const std::size_t nc = static_cast<std::size_t>(this->NumberOfComponents);
    const double* s0 = this->Strengths.data() + static_cast<std::size_t>(s.V0) * nc;
    const double* s1 = this->Strengths.data() + static_cast<std::size_t>(s.V1) * nc;
    for (std::size_t c = 0; c < nc; ++c)
    {
      strength[c] = (1.0 - t) * s0[c] + t * s1[c];
    }
    return true;
  }

  /// Length of the curves inside the open ball B(x, radius).
  double LengthInBall(const Vec<DIM>& x, double radius, Scratch& scratch) const
  {
    return this->Clip(x, radius, scratch);
  }

  /// Calls visit(index, a, d, t0, t1, s0, s1) for every piece of a segment
  /// inside the open ball B(x, radius): the segment a + t d, t in [t0, t1],
  /// with the strengths s0 at t = 0 and s1 at t = 1 (Components() numbers
  /// each, linear between); `index` names the segment.
  template <class Visit>
  void ForEachPieceInBall(const Vec<DIM>& x, double radius, Scratch& scratch, Visit&& visit) const
  {
    this->Clip(x, radius, scratch);
    const std::size_t nc = static_cast<std::size_t>(this->NumberOfComponents);
    for (const auto& piece : scratch.Pieces)
    {
      const SegmentData& s = this->Segments[piece.Segment];
      visit(piece.Segment, s.A, s.D, piece.T0, piece.T1,
        this->Strengths.data() + static_cast<std::size_t>(s.V0) * nc,
        this->Strengths.data() + static_cast<std::size_t>(s.V1) * nc);
    }
  }

private:
  struct SegmentData
  {
    Vec<DIM> A; // first vertex
    Vec<DIM> D; // second vertex minus first
    double Length;
    std::int64_t V0, V1; // vertex indices, for the strengths
  };

  /// Fills the scratch with the pieces of segments inside the ball; returns
  /// their total length.
  double Clip(const Vec<DIM>& x, double radius, Scratch& scratch) const
  {
    scratch.Pieces.clear();
    const double radius2 = radius * radius;
    double sum = 0.0;
    this->Tree.ForEachOverlappingBall(x, radius, [&](std::size_t i) {
      const SegmentData& s = this->Segments[i];
      double t0, t1;
      if (detail::ClipSegmentToBall<DIM>(s.A, s.D, s.Length, x, radius2, t0, t1))
      {
        sum += (t1 - t0) * s.Length;
        scratch.Pieces.push_back({ static_cast<std::uint32_t>(i), t0, t1 });
      }
    });
    return sum;
  }

  std::vector<SegmentData> Segments;
  std::vector<double> Strengths; // per vertex given to Set
  int NumberOfComponents = 1;
  double Total = 0.0;
  BallQueryTree<DIM> Tree;
};
} // namespace gridfree

#endif
