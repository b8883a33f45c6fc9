// Boundary data of the biharmonic shape deformation of "Monte Carlo Geometry
// Processing" (Sawhney & Crane 2020, Sec. 6.7), in 2D.
//
// The map φ: Ω → Ω' solves Δ²φ = 0 per coordinate, written as the nested
// system Δφ = v, Δv = 0 with φ = g and Δφ = h on ∂Ω. The data come from a
// boundary curve γ (where φ's domain boundary lies) and its image curve with
// the same parametrization, u = φ∘γ:
//
// * g = u, the corresponding point of the image curve.
// * h: the map is asked to be "as linear as possible" across the boundary,
//   ∂²φ/∂N² = 0, so h = Δφ = ∂²φ/∂T². Along the curve (arc length s),
//   u'' = ∂²φ/∂T² + Dφ γ'', hence h = u'' − Dφ γ''. Only the tangential part
//   of Dφ is known from the Dirichlet data (u' = Dφ T); the normal part is
//   closed by assuming φ is locally a similarity (conformal and orientation
//   preserving) at the boundary, so Dφ commutes with rotations and
//   Dφ N = R u' where R is the rotation taking T to N.
//
// Normal and orientation convention. J is the counter-clockwise quarter turn,
// J(x, y) = (−y, x). T = γ'/|γ'| and N = −J T = (T_y, −T_x), the right-hand
// normal: the outward normal when a closed curve is traversed
// counter-clockwise. The curvature is signed by γ'' = κ N, so κ = −1/r on a
// counter-clockwise circle of radius r, and R = −J (rotation by −90°). Then
//
//   h = u'' − κ R u' = u'' − k J u',   k = κ_left = T × γ'' (= −κ),
//
// the product κ R does not depend on which normal is chosen (flipping N flips
// both κ and R). Reversing the traversal flips T, u' and k and keeps u'', so
// h does not depend on the orientation either: reversing both curves gives
// the same h at corresponding points. For a curve in any regular parameter t
// (a = dγ/dt, b = d²γ/dt²) the chain rule gives
//
//   h = ( d²u/dt² − (⟨a, b⟩ u_t + (a × b) J u_t) / |a|² ) / |a|²,
//
// i.e. u_ss = u_tt/|a|² − u_t ⟨b, a⟩/|a|⁴ and k = (a × b)/|a|³, the paper's
// formulas. In complex notation h = (u_tt − u_t b/a)/|a|²: a similarity
// u = c γ + d gives h = 0 exactly, and a holomorphic φ = f (for which the
// closure is exact) gives h = f''(γ) T², the true ∂²φ/∂T². An orientation
// reversing map is not a similarity in this sense: a reflection gets h ≠ 0.
//
// Polylines. The vertices p_i are the samples of γ at the polyline's own arc
// length (cumulative chord length), and a, b, u_t, u_tt are the non-uniform
// three-point derivatives in that parameter (the derivatives of the quadratic
// through a vertex and its two neighbours). They are plugged into the
// parametric formula above rather than into u'' − k J u' with a separately
// estimated curvature (turning angle over mean length): the two agree to
// second order on smooth curves, but only the parametric form keeps the
// algebraic identity that makes a similarity's h vanish; with the turning
// angle a rotated square would get a spurious h of order 1/edge length at
// every corner, and its interior would not move rigidly. The curvature that
// the formula uses is (a × b)/|a|³ = 2 sin θ/((l₀ + l₁)|a|³) at a vertex of
// turning angle θ between segments of lengths l₀, l₁, i.e. θ/mean length up
// to O(θ²). Accuracy: second order in the spacing on smooth curves whose
// spacing varies smoothly; at corners h is whatever the three-point stencil
// gives (zero for similarities, finite otherwise), the data being singular
// there anyway.
//
// * Open ends use the one-sided quadratic through the end vertex and its two
//   successors (derivatives of that quadratic at the end): exact for
//   similarities and straight lines, first-order accurate in general.
// * Consecutive points closer than 1e-12 of the curve's bounding-box
//   diagonal are merged: derivatives are computed on the distinct vertices,
//   and a duplicate gets its own image point as g and the h of the vertex it
//   was merged into. A curve whose last point repeats the first is closed
//   (whatever the flag); a closed curve needs three distinct vertices, fewer
//   are treated as open. One distinct vertex gives h = 0, two give h = 0 (a
//   segment: u linear in s).
// * A vertex where the polyline turns back on itself (|a| < 1e-3 in the
//   arc-length parameter, i.e. within about 0.1° of a full reversal between
//   equal segments) has no tangent: h = 0 there.
//
// Cubic Bézier curves. a, b, u_t, u_tt are the exact Bernstein derivatives at
// t, clamped to [0, 1]. Where |B'(t)| is below 1e-4 of the control polygon's
// size (an end with a repeated control point, a cusp) there is no tangent,
// and in general no limit to reproduce either: a cubic with P1 = P0 has
// curvature ~ 1/t at its end (unless it is straight there), so h ~ 1/t too.
// h is then taken at the nearest regular parameters: the mean of h(t − δ)
// and h(t + δ) inside the curve, h(t ± δ) towards the inside at an end, with
// δ the first of 1e-3, 1e-2, 1e-1 for which the curve is regular there. The
// result is finite, of the size h has at that distance, and still exactly
// zero for a similarity. A curve whose control points all coincide gives
// h = 0.
#ifndef GRIDFREE_APPLICATIONS_DEFORMATION_BOUNDARY_DATA_H
#define GRIDFREE_APPLICATIONS_DEFORMATION_BOUNDARY_DATA_H

#include <gridfree/math/Vector.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace gridfree
{
/// Dirichlet data of the nested biharmonic system at one boundary point:
/// Value = g = φ on the boundary, Laplacian = h = Δφ on the boundary.
struct DeformationBoundarySample
{
  Vec2 Value = Vec2::Zero();
  Vec2 Laplacian = Vec2::Zero();
};

namespace detail
{
// Counter-clockwise quarter turn J.
inline Vec2 QuarterTurn(const Vec2& v)
{
  return Vec2(-v[1], v[0]);
}

inline double Cross(const Vec2& a, const Vec2& b)
{
  return a[0] * b[1] - a[1] * b[0];
}

// Derivatives of a curve and its image at one point, in a common parameter.
struct CurveJet
{
  Vec2 CurveD1, CurveD2, ImageD1, ImageD2;
};

inline Vec2 BezierPoint(const std::array<Vec2, 4>& p, double t)
{
  const double s = 1.0 - t;
  return (s * s * s) * p[0] + (3.0 * s * s * t) * p[1] + (3.0 * s * t * t) * p[2] +
    (t * t * t) * p[3];
}

inline Vec2 BezierDerivative(const std::array<Vec2, 4>& p, double t)
{
  const double s = 1.0 - t;
  return 3.0 * ((s * s) * (p[1] - p[0]) + (2.0 * s * t) * (p[2] - p[1]) + (t * t) * (p[3] - p[2]));
}

inline Vec2 BezierSecondDerivative(const std::array<Vec2, 4>& p, double t)
{
  const Vec2 e0 = (p[2] - p[1]) - (p[1] - p[0]);
  const Vec2 e1 = (p[3] - p[2]) - (p[2] - p[1]);
  return 6.0 * ((1.0 - t) * e0 + t * e1);
}
} // namespace detail

/// h from the first and second derivatives of the boundary curve (dCurve,
/// d2Curve) and of its image (dImage, d2Image) in any common parameter: the
/// chain rule to arc length with the similarity closure (see the top of the
/// file). Zero when dCurve = 0 (no tangent); callers avoid that case.
inline Vec2 DeformationLaplacian(
  const Vec2& dCurve, const Vec2& d2Curve, const Vec2& dImage, const Vec2& d2Image)
{
  const double speed2 = dCurve.squaredNorm();
  if (!(speed2 > 0.0))
  {
    return Vec2::Zero();
  }
  // ⟨a, b⟩/|a|² turns u_tt into |a|² u_ss; (a × b)/|a|² is |a|² times the
  // left curvature k over |a|, so the last term is |a|² k J u_s.
  const double along = dCurve.dot(d2Curve) / speed2;
  const double turn = detail::Cross(dCurve, d2Curve) / speed2;
  return (d2Image - along * dImage - turn * detail::QuarterTurn(dImage)) / speed2;
}

/// g and h at every point of a polyline `curve` (where the data are given)
/// with images `image` (same count, image[i] corresponds to curve[i]).
/// `closed` joins the last point to the first; a curve whose last point
/// repeats the first is closed anyway. Throws std::invalid_argument when the
/// counts differ.
inline std::vector<DeformationBoundarySample> PolylineDeformationData(
  const std::vector<Vec2>& curve, const std::vector<Vec2>& image, bool closed)
{
  if (curve.size() != image.size())
  {
    throw std::invalid_argument("deformation boundary data: " + std::to_string(curve.size()) +
      " curve points but " + std::to_string(image.size()) + " image points");
  }
  const std::size_t n = curve.size();
  std::vector<DeformationBoundarySample> samples(n);
  if (n == 0)
  {
    return samples;
  }

  // Merge tolerance relative to the curve's extent, so that the result does
  // not depend on the units; exact repeats are merged even for a point curve.
  Vec2 lo = curve[0], hi = curve[0];
  for (const Vec2& p : curve)
  {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double tolerance = 1e-12 * (hi - lo).norm();
  const auto same = [tolerance](const Vec2& a, const Vec2& b) {
    return (a - b).norm() <= tolerance;
  };

  // Distinct vertices (indices into curve) and, per input point, the distinct
  // vertex it belongs to.
  std::vector<std::size_t> kept;
  std::vector<std::size_t> owner(n);
  kept.push_back(0);
  for (std::size_t i = 1; i < n; ++i)
  {
    if (!same(curve[i], curve[kept.back()]))
    {
      kept.push_back(i);
    }
    owner[i] = kept.size() - 1;
  }
  if (kept.size() >= 2 && same(curve[kept.back()], curve[kept.front()]))
  {
    // The last distinct vertex repeats the first: a closed curve written
    // with its first point repeated.
    for (std::size_t i = 0; i < n; ++i)
    {
      if (owner[i] == kept.size() - 1)
      {
        owner[i] = 0;
      }
    }
    kept.pop_back();
    closed = true;
  }
  const std::size_t m = kept.size();
  if (m < 3)
  {
    closed = false;
  }

  // h per distinct vertex, from three-point derivatives in arc length.
  std::vector<Vec2> laplacian(m, Vec2::Zero());
  const auto point = [&](std::size_t j) -> const Vec2& { return curve[kept[j]]; };
  const auto mapped = [&](std::size_t j) -> const Vec2& { return image[kept[j]]; };
  // Below this speed the polyline turns back on itself (|a| is about
  // cos(θ/2) at a vertex of turning angle θ between equal segments).
  constexpr double minimumSpeed = 1e-3;
  if (m == 2)
  {
    // A segment: u is linear in s, γ'' = 0, so h = 0.
  }
  else if (m >= 3)
  {
    for (std::size_t j = 0; j < m; ++j)
    {
      detail::CurveJet jet;
      const bool interior = closed || (j > 0 && j + 1 < m);
      if (interior)
      {
        // Quadratic through the previous, this and the next vertex, at this
        // vertex (parameter offsets −l0, 0, +l1).
        const std::size_t prev = j == 0 ? m - 1 : j - 1;
        const std::size_t next = j + 1 == m ? 0 : j + 1;
        const double l0 = (point(j) - point(prev)).norm();
        const double l1 = (point(next) - point(j)).norm();
        const double w0 = l1 / (l0 + l1), w1 = l0 / (l0 + l1), c = 2.0 / (l0 + l1);
        const Vec2 dc0 = (point(j) - point(prev)) / l0, dc1 = (point(next) - point(j)) / l1;
        const Vec2 di0 = (mapped(j) - mapped(prev)) / l0, di1 = (mapped(next) - mapped(j)) / l1;
        jet.CurveD1 = w0 * dc0 + w1 * dc1;
        jet.CurveD2 = c * (dc1 - dc0);
        jet.ImageD1 = w0 * di0 + w1 * di1;
        jet.ImageD2 = c * (di1 - di0);
      }
      else
      {
        // One-sided: the quadratic through the end vertex and the next two
        // towards the inside, differentiated at the end. Written for the
        // first vertex with the three vertices ordered from the end inwards;
        // at the last vertex the parameter runs the other way, which flips
        // the first derivatives only.
        const bool first = j == 0;
        const std::size_t v0 = j, v1 = first ? 1 : m - 2, v2 = first ? 2 : m - 3;
        const double l0 = (point(v1) - point(v0)).norm();
        const double l1 = (point(v2) - point(v1)).norm();
        const Vec2 dc0 = (point(v1) - point(v0)) / l0, dc1 = (point(v2) - point(v1)) / l1;
        const Vec2 di0 = (mapped(v1) - mapped(v0)) / l0, di1 = (mapped(v2) - mapped(v1)) / l1;
        const double w = l0 / (l0 + l1), c = 2.0 / (l0 + l1);
        const double sign = first ? 1.0 : -1.0;
        jet.CurveD1 = sign * (dc0 - w * (dc1 - dc0));
        jet.CurveD2 = c * (dc1 - dc0);
        jet.ImageD1 = sign * (di0 - w * (di1 - di0));
        jet.ImageD2 = c * (di1 - di0);
      }
      if (jet.CurveD1.norm() >= minimumSpeed)
      {
        laplacian[j] =
          DeformationLaplacian(jet.CurveD1, jet.CurveD2, jet.ImageD1, jet.ImageD2);
      }
    }
  }

  for (std::size_t i = 0; i < n; ++i)
  {
    samples[i].Value = image[i];
    samples[i].Laplacian = laplacian[owner[i]];
  }
  return samples;
}

/// PolylineDeformationData for several curves: one result per curve, in the
/// same order. `closed` holds one flag per curve, or is empty (all open
/// unless their first point is repeated).
inline std::vector<std::vector<DeformationBoundarySample>> PolylinesDeformationData(
  const std::vector<std::vector<Vec2>>& curves, const std::vector<std::vector<Vec2>>& images,
  const std::vector<bool>& closed)
{
  if (curves.size() != images.size() || (!closed.empty() && closed.size() != curves.size()))
  {
    throw std::invalid_argument("deformation boundary data: " + std::to_string(curves.size()) +
      " curves, " + std::to_string(images.size()) + " images and " +
      std::to_string(closed.size()) + " closed flags");
  }
  std::vector<std::vector<DeformationBoundarySample>> result;
  result.reserve(curves.size());
  for (std::size_t c = 0; c < curves.size(); ++c)
  {
    result.push_back(
      PolylineDeformationData(curves[c], images[c], closed.empty() ? false : bool(closed[c])));
  }
  return result;
}

/// g = Q(t) and h at parameter t of the cubic Bézier curve with control
/// points `curve` (where the data are given) and its image with control
/// points `image` (same parameter). t is clamped to [0, 1].
inline DeformationBoundarySample DeformationDataAt(
  const std::array<Vec2, 4>& curve, const std::array<Vec2, 4>& image, double t)
{
  t = std::min(1.0, std::max(0.0, t));
  DeformationBoundarySample sample;
  sample.Value = detail::BezierPoint(image, t);

  double size = 0.0;
  for (int i = 1; i < 4; ++i)
  {
    size = std::max(size, (curve[i] - curve[0]).norm());
  }
  if (!(size > 0.0))
  {
    return sample; // a point: no tangent anywhere, h = 0
  }
  // Below this speed the cancellation in u_tt − (…)u_t, divided by |a|⁴,
  // costs more than the O(δ²) of the fallback.
  const double minimumSpeed = 1e-4 * size;
  const auto regular = [&](double s) {
    return s >= 0.0 && s <= 1.0 && detail::BezierDerivative(curve, s).norm() >= minimumSpeed;
  };
  const auto laplacianAt = [&](double s) {
    return DeformationLaplacian(detail::BezierDerivative(curve, s),
      detail::BezierSecondDerivative(curve, s), detail::BezierDerivative(image, s),
      detail::BezierSecondDerivative(image, s));
  };
  if (regular(t))
  {
    sample.Laplacian = laplacianAt(t);
    return sample;
  }
  for (double delta : { 1e-3, 1e-2, 1e-1 })
  {
    if (regular(t - delta) && regular(t + delta))
    {
      sample.Laplacian = 0.5 * (laplacianAt(t - delta) + laplacianAt(t + delta));
      return sample;
    }
    const double inward = t <= 0.5 ? t + delta : t - delta;
    if (regular(inward))
    {
      sample.Laplacian = laplacianAt(inward);
      return sample;
    }
  }
  return sample; // degenerate over a large part of the curve: h = 0
}
} // namespace gridfree

#endif
