// Tests of the boundary data (g, h) of the biharmonic shape deformation.
//
// The reference h is written here in the notation of the paper and of the
// header's convention, independently of the header's code path: outward
// normal N = (T_y, −T_x) for a counter-clockwise curve, γ_ss = κ N, R the
// rotation by −90° taking T to N, h = u_ss − κ R u_s, with u_s, u_ss, T and
// γ_ss computed analytically (circles, ellipses) or from finite differences
// of the Bézier evaluation in t. A second, complex-analytic reference checks
// the closure itself: for a holomorphic map f the closure is exact and h must
// be the true ∂²φ/∂T² = f''(z) T². Similarities must give h = 0 to rounding,
// which fails for either sign error (a flipped closure gives h = 2u'').
#include <gridfree/applications/DeformationBoundaryData.h>
#include <gridfree/math/Vector.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <functional>
#include <random>
#include <stdexcept>
#include <vector>

namespace
{
using gridfree::DeformationBoundarySample;
using gridfree::DeformationDataAt;
using gridfree::PolylineDeformationData;
using gridfree::PolylinesDeformationData;
using gridfree::Vec2;
using Complex = std::complex<double>;
using Bezier = std::array<Vec2, 4>;

const double kPi = std::acos(-1.0);

Complex ToComplex(const Vec2& v)
{
  return Complex(v[0], v[1]);
}

Vec2 ToVec(const Complex& z)
{
  return Vec2(z.real(), z.imag());
}

// h = u_ss − κ R u_s with N = (T_y, −T_x), κ = ⟨γ_ss, N⟩, R v = (v_y, −v_x).
Vec2 ReferenceLaplacian(const Vec2& tangent, const Vec2& curveSS, const Vec2& imageS,
  const Vec2& imageSS)
{
  const Vec2 normal(tangent[1], -tangent[0]);
  const double kappa = curveSS.dot(normal);
  const Vec2 rotated(imageS[1], -imageS[0]);
  return imageSS - kappa * rotated;
}

// A map with its first and second derivatives: u_s = Dφ T, u_ss = D²φ[T, T]
// + Dφ γ_ss along a curve.
struct SmoothMap
{
  std::function<Vec2(const Vec2&)> Value;
  std::function<Vec2(const Vec2&, const Vec2&)> Derivative;              // Dφ(x) v
  std::function<Vec2(const Vec2&, const Vec2&)> SecondDerivative;        // D²φ(x)[v, v]
};

// φ(x, y) = (x + 0.1 y², y + 0.1 x y), the map of the convergence study.
SmoothMap PolynomialMap()
{
  SmoothMap map;
  map.Value = [](const Vec2& p) {
    return Vec2(p[0] + 0.1 * p[1] * p[1], p[1] + 0.1 * p[0] * p[1]);
  };
  map.Derivative = [](const Vec2& p, const Vec2& v) {
    return Vec2(v[0] + 0.2 * p[1] * v[1], 0.1 * p[1] * v[0] + (1.0 + 0.1 * p[0]) * v[1]);
  };
  map.SecondDerivative = [](const Vec2&, const Vec2& v) {
    return Vec2(0.2 * v[1] * v[1], 0.2 * v[0] * v[1]);
  };
  return map;
}

// Similarity x ↦ s Q x + b (rotation by `angle`, orientation preserving).
SmoothMap Similarity(double scale, double angle, const Vec2& shift)
{
  const Complex c = std::polar(scale, angle);
  SmoothMap map;
  map.Value = [c, shift](const Vec2& p) { return Vec2(ToVec(c * ToComplex(p)) + shift); };
  map.Derivative = [c](const Vec2&, const Vec2& v) { return ToVec(c * ToComplex(v)); };
  map.SecondDerivative = [](const Vec2&, const Vec2&) { return Vec2(Vec2::Zero()); };
  return map;
}

// A smooth closed curve given by its position, and first and second
// derivatives in a parameter θ ∈ [0, 2π).
struct ParametricCurve
{
  std::function<Vec2(double)> Position, D1, D2;
};

ParametricCurve Ellipse(const Vec2& centre, double a, double b, double tilt)
{
  const double c = std::cos(tilt), s = std::sin(tilt);
  const auto rotate = [c, s](const Vec2& v) {
    return Vec2(c * v[0] - s * v[1], s * v[0] + c * v[1]);
  };
  ParametricCurve curve;
  curve.Position = [=](double t) {
    return Vec2(centre + rotate(Vec2(a * std::cos(t), b * std::sin(t))));
  };
  curve.D1 = [=](double t) { return rotate(Vec2(-a * std::sin(t), b * std::cos(t))); };
  curve.D2 = [=](double t) { return rotate(Vec2(-a * std::cos(t), -b * std::sin(t))); };
  return curve;
}

// Exact h of the map on the curve at parameter θ, by the reference formula.
Vec2 ExactLaplacian(const ParametricCurve& curve, const SmoothMap& map, double t)
{
  const Vec2 p = curve.Position(t), d1 = curve.D1(t), d2 = curve.D2(t);
  const double speed = d1.norm();
  const Vec2 tangent = d1 / speed;
  // γ_ss = (γ_tt − ⟨γ_tt, T⟩ T)/|γ_t|² (unit speed removes the tangential part).
  const Vec2 curveSS = (d2 - d2.dot(tangent) * tangent) / (speed * speed);
  const Vec2 imageS = map.Derivative(p, tangent);
  const Vec2 imageSS = map.SecondDerivative(p, tangent) + map.Derivative(p, curveSS);
  return ReferenceLaplacian(tangent, curveSS, imageS, imageSS);
}

// Parameters θ_i, i < n, of a closed curve: uniform, or smoothly graded.
std::vector<double> Parameters(int n, double grading)
{
  std::vector<double> t(n);
  for (int i = 0; i < n; ++i)
  {
    const double x = 2.0 * kPi * i / n;
    t[i] = x + grading * std::sin(x);
  }
  return t;
}

std::vector<Vec2> Sample(const ParametricCurve& curve, const std::vector<double>& t)
{
  std::vector<Vec2> points;
  for (double x : t)
  {
    points.push_back(curve.Position(x));
  }
  return points;
}

std::vector<Vec2> Apply(const std::function<Vec2(const Vec2&)>& f, const std::vector<Vec2>& points)
{
  std::vector<Vec2> images;
  for (const Vec2& p : points)
  {
    images.push_back(f(p));
  }
  return images;
}

double MaxNorm(const std::vector<DeformationBoundarySample>& samples)
{
  double m = 0.0;
  for (const auto& s : samples)
  {
    m = std::max(m, s.Laplacian.norm());
  }
  return m;
}

// Largest |h_i − exact(θ_i)| over the indices in [first, last).
double MaxError(const std::vector<DeformationBoundarySample>& samples,
  const std::vector<double>& t, const std::function<Vec2(double)>& exact, std::size_t first,
  std::size_t last)
{
  double m = 0.0;
  for (std::size_t i = first; i < last; ++i)
  {
    m = std::max(m, (samples[i].Laplacian - exact(t[i])).norm());
  }
  return m;
}

template <typename T>
std::vector<T> Reversed(std::vector<T> v)
{
  std::reverse(v.begin(), v.end());
  return v;
}

// An open S: two half circles of radius 1 joined at the origin, sampled
// unevenly.
std::vector<Vec2> SCurve(int n)
{
  std::vector<Vec2> points;
  for (int i = 0; i <= n; ++i)
  {
    const double x = double(i) / n;
    const double u = x + 0.03 * std::sin(7.0 * x); // uneven, still monotone
    const double angle = 2.0 * kPi * u;            // 0..2π
    if (angle <= kPi)
    {
      points.emplace_back(-1.0 + std::cos(kPi - angle), std::sin(kPi - angle));
    }
    else
    {
      points.emplace_back(1.0 - std::cos(angle - kPi), -std::sin(angle - kPi));
    }
  }
  return points;
}

// A polygon with `perEdge` unevenly spaced points per edge, counter-clockwise,
// and the indices of its corners.
std::vector<Vec2> Polygon(
  const std::vector<Vec2>& corners, int perEdge, std::vector<int>* cornerIds)
{
  std::vector<Vec2> points;
  for (std::size_t c = 0; c < corners.size(); ++c)
  {
    const Vec2& a = corners[c];
    const Vec2& b = corners[(c + 1) % corners.size()];
    cornerIds->push_back(static_cast<int>(points.size()));
    for (int k = 0; k < perEdge; ++k)
    {
      const double x = double(k) / perEdge;
      points.push_back(a + (x * x * 0.4 + 0.6 * x) * (b - a));
    }
  }
  return points;
}

Vec2 BezierAt(const Bezier& p, double t)
{
  const double s = 1.0 - t;
  return s * s * s * p[0] + 3.0 * s * s * t * p[1] + 3.0 * s * t * t * p[2] + t * t * t * p[3];
}

Bezier RandomBezier(std::mt19937& rng, double size)
{
  std::uniform_real_distribution<double> u(-size, size);
  Bezier b;
  for (Vec2& p : b)
  {
    p = Vec2(u(rng), u(rng));
  }
  return b;
}

Bezier ReversedBezier(const Bezier& b)
{
  return { b[3], b[2], b[1], b[0] };
}

// Control points of the cubic c0 + c1 t + c2 t² + c3 t³ (complex coefficients).
Bezier FromMonomials(Complex c0, Complex c1, Complex c2, Complex c3)
{
  return { ToVec(c0), ToVec(c0 + c1 / 3.0), ToVec(c0 + 2.0 * c1 / 3.0 + c2 / 3.0),
    ToVec(c0 + c1 + c2 + c3) };
}

bool Finite(const std::vector<DeformationBoundarySample>& samples)
{
  for (const auto& s : samples)
  {
    if (!s.Value.allFinite() || !s.Laplacian.allFinite())
    {
      return false;
    }
  }
  return true;
}
} // namespace

// ---------------------------------------------------------------------------
// Similarities: h = 0 to rounding, on any curve.

TEST(DeformationBoundaryData, SimilarityOnCircleAndEllipseGivesZero)
{
  const SmoothMap map = Similarity(1.7, 0.6, Vec2(0.3, -2.0));
  for (const ParametricCurve& curve :
    { Ellipse(Vec2(0.2, 0.1), 1.0, 1.0, 0.0), Ellipse(Vec2(-1.0, 3.0), 2.0, 0.5, 0.4) })
  {
    for (double grading : { 0.0, 0.3 })
    {
      const std::vector<Vec2> points = Sample(curve, Parameters(1000, grading));
      const auto samples = PolylineDeformationData(points, Apply(map.Value, points), true);
      ASSERT_EQ(samples.size(), points.size());
      // |u_ss| alone is about 1.7/0.5 here; rounding of the three-point
      // second difference is about 1e-16 |u| / spacing² ~ 1e-10.
      EXPECT_LT(MaxNorm(samples), 1e-8);
      for (std::size_t i = 0; i < points.size(); ++i)
      {
        EXPECT_EQ(samples[i].Value, map.Value(points[i]));
      }
    }
  }
}

TEST(DeformationBoundaryData, SimilarityOnOpenSCurveGivesZeroIncludingEnds)
{
  const std::vector<Vec2> points = SCurve(300);
  for (const SmoothMap& map :
    { Similarity(0.4, -2.0, Vec2(5.0, 1.0)), Similarity(3.0, 1.0, Vec2(-1.0, 0.0)) })
  {
    const auto samples = PolylineDeformationData(points, Apply(map.Value, points), false);
    EXPECT_LT(MaxNorm(samples), 1e-8);
  }
}

TEST(DeformationBoundaryData, SimilarityOnPolygonGivesZeroAtCornersToo)
{
  std::vector<int> corners;
  const std::vector<Vec2> points =
    Polygon({ Vec2(0, 0), Vec2(2, 0), Vec2(2.5, 1.5), Vec2(0.5, 2.0) }, 7, &corners);
  const SmoothMap map = Similarity(2.0, 2.5, Vec2(1.0, 1.0));
  const auto samples = PolylineDeformationData(points, Apply(map.Value, points), true);
  EXPECT_LT(MaxNorm(samples), 1e-10);
}

TEST(DeformationBoundaryData, ReflectionIsNotASimilarity)
{
  // φ(x, y) = (x, −y) on the unit circle: u_ss − k J u_s = −2 u exactly (k =
  // 1 counter-clockwise). A closure with the wrong handedness would give 0.
  const ParametricCurve circle = Ellipse(Vec2(0, 0), 1.0, 1.0, 0.0);
  const std::vector<double> t = Parameters(800, 0.0);
  const std::vector<Vec2> points = Sample(circle, t);
  const auto reflect = [](const Vec2& p) { return Vec2(p[0], -p[1]); };
  const auto samples = PolylineDeformationData(points, Apply(reflect, points), true);
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    EXPECT_NEAR((samples[i].Laplacian + 2.0 * reflect(points[i])).norm(), 0.0, 1e-4);
  }
}

// ---------------------------------------------------------------------------
// Affine maps on straight segments.

TEST(DeformationBoundaryData, AffineMapOnPolygonIsZeroAwayFromCorners)
{
  std::vector<int> corners;
  const std::vector<Vec2> points = Polygon(
    { Vec2(0, 0), Vec2(3, -0.5), Vec2(4, 2), Vec2(1.5, 3), Vec2(-0.5, 1.5) }, 9, &corners);
  const auto affine = [](const Vec2& p) {
    return Vec2(1.3 * p[0] + 0.4 * p[1] + 2.0, -0.2 * p[0] + 0.8 * p[1] - 1.0);
  };
  const auto samples = PolylineDeformationData(points, Apply(affine, points), true);
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const bool corner = std::find(corners.begin(), corners.end(), int(i)) != corners.end();
    if (corner)
    {
      // A shear is not a similarity: the corners carry a finite h.
      EXPECT_GT(samples[i].Laplacian.norm(), 1e-2) << i;
      EXPECT_TRUE(samples[i].Laplacian.allFinite());
    }
    else
    {
      EXPECT_LT(samples[i].Laplacian.norm(), 1e-10) << i;
    }
  }
}

TEST(DeformationBoundaryData, AffineMapOnOpenSegmentsIsZero)
{
  // Two points, and collinear uneven points: straight, u linear in s.
  const auto affine = [](const Vec2& p) {
    return Vec2(2.0 * p[0] - p[1], 0.5 * p[0] + 3.0 * p[1]);
  };
  const std::vector<Vec2> two = { Vec2(0, 0), Vec2(1, 2) };
  EXPECT_LT(MaxNorm(PolylineDeformationData(two, Apply(affine, two), false)), 1e-14);
  const std::vector<Vec2> line = { Vec2(0, 0), Vec2(0.1, 0.2), Vec2(0.5, 1.0), Vec2(0.6, 1.2),
    Vec2(2, 4) };
  EXPECT_LT(MaxNorm(PolylineDeformationData(line, Apply(affine, line), false)), 1e-12);
}

// ---------------------------------------------------------------------------
// Convergence to the exact expression for smooth nonlinear maps.

namespace
{
// Max error of the polyline h against `exact` for 200, 400, 800 samples.
std::array<double, 3> ClosedErrors(const ParametricCurve& curve, const SmoothMap& map,
  double grading, const std::function<Vec2(double)>& exact, bool reverse)
{
  std::array<double, 3> errors{};
  int k = 0;
  for (int n : { 200, 400, 800 })
  {
    std::vector<double> t = Parameters(n, grading);
    if (reverse)
    {
      t = Reversed(t);
    }
    const std::vector<Vec2> points = Sample(curve, t);
    const auto samples = PolylineDeformationData(points, Apply(map.Value, points), true);
    errors[k++] = MaxError(samples, t, exact, 0, points.size());
  }
  return errors;
}
} // namespace

TEST(DeformationBoundaryData, PolylineConvergesAtSecondOrderOnCircle)
{
  const SmoothMap map = PolynomialMap();
  const ParametricCurve circle = Ellipse(Vec2(0.3, -0.2), 1.0, 1.0, 0.0);
  const auto exact = [&](double t) { return ExactLaplacian(circle, map, t); };
  for (double grading : { 0.0, 0.4 })
  {
    for (bool reverse : { false, true })
    {
      const auto e = ClosedErrors(circle, map, grading, exact, reverse);
      EXPECT_LT(e[2], 2e-4);
      EXPECT_NEAR(e[0] / e[1], 4.0, 0.4) << grading << " " << reverse;
      EXPECT_NEAR(e[1] / e[2], 4.0, 0.4) << grading << " " << reverse;
    }
  }
}

TEST(DeformationBoundaryData, ReferenceFormulaAgreesWithHolomorphicTruth)
{
  // For holomorphic f the closure holds exactly, so the reference formula
  // must reproduce the true ∂²φ/∂T² = f''(z) T²: validates the reference.
  const ParametricCurve ellipse = Ellipse(Vec2(0.5, 0.2), 1.5, 0.7, 0.3);
  SmoothMap map;
  map.Value = [](const Vec2& p) { return ToVec(std::exp(0.7 * ToComplex(p))); };
  map.Derivative = [](const Vec2& p, const Vec2& v) {
    return ToVec(0.7 * std::exp(0.7 * ToComplex(p)) * ToComplex(v));
  };
  map.SecondDerivative = [](const Vec2& p, const Vec2& v) {
    const Complex w = ToComplex(v);
    return ToVec(0.49 * std::exp(0.7 * ToComplex(p)) * w * w);
  };
  for (int i = 0; i < 50; ++i)
  {
    const double t = 0.1 + 0.13 * i;
    const Complex tangent = ToComplex(ellipse.D1(t).normalized());
    const Complex truth = 0.49 * std::exp(0.7 * ToComplex(ellipse.Position(t))) * tangent * tangent;
    EXPECT_NEAR((ExactLaplacian(ellipse, map, t) - ToVec(truth)).norm(), 0.0, 1e-12);
  }
  // And the polyline converges to it at second order.
  const auto exact = [&](double t) { return ExactLaplacian(ellipse, map, t); };
  const auto e = ClosedErrors(ellipse, map, 0.25, exact, false);
  EXPECT_NEAR(e[0] / e[1], 4.0, 0.4);
  EXPECT_NEAR(e[1] / e[2], 4.0, 0.4);
}

TEST(DeformationBoundaryData, AbruptSpacingConvergesAtFirstOrder)
{
  // Spacing alternating 1:2: the three-point second difference is only
  // first-order accurate there (documented); h must still converge.
  const SmoothMap map = PolynomialMap();
  const ParametricCurve circle = Ellipse(Vec2(0.3, -0.2), 1.0, 1.0, 0.0);
  const auto exact = [&](double t) { return ExactLaplacian(circle, map, t); };
  std::array<double, 3> errors{};
  int k = 0;
  for (int n : { 200, 400, 800 })
  {
    std::vector<double> t;
    double position = 0.0;
    for (int i = 0; i < n; ++i)
    {
      t.push_back(2.0 * kPi * position / (1.5 * n));
      position += i % 2 == 0 ? 1.0 : 2.0;
    }
    const std::vector<Vec2> points = Sample(circle, t);
    const auto samples = PolylineDeformationData(points, Apply(map.Value, points), true);
    errors[k++] = MaxError(samples, t, exact, 0, points.size());
  }
  EXPECT_NEAR(errors[0] / errors[1], 2.0, 0.3);
  EXPECT_NEAR(errors[1] / errors[2], 2.0, 0.3);
  EXPECT_LT(errors[2], 0.02);
}

TEST(DeformationBoundaryData, OpenArcConvergesInsideAndAtTheEnds)
{
  // Open arc θ ∈ [0.2, 2.8] of an ellipse: second order inside, first order
  // at the one-sided ends.
  const SmoothMap map = PolynomialMap();
  const ParametricCurve ellipse = Ellipse(Vec2(0.1, 0.4), 1.2, 0.8, -0.2);
  const auto exact = [&](double t) { return ExactLaplacian(ellipse, map, t); };
  std::array<double, 3> inside{}, ends{};
  int k = 0;
  for (int n : { 100, 200, 400 })
  {
    std::vector<double> t;
    for (int i = 0; i <= n; ++i)
    {
      const double x = double(i) / n;
      t.push_back(0.2 + 2.6 * (x + 0.05 * std::sin(kPi * x)));
    }
    const std::vector<Vec2> points = Sample(ellipse, t);
    const auto samples = PolylineDeformationData(points, Apply(map.Value, points), false);
    inside[k] = MaxError(samples, t, exact, 1, points.size() - 1);
    ends[k] = std::max(MaxError(samples, t, exact, 0, 1),
      MaxError(samples, t, exact, points.size() - 1, points.size()));
    ++k;
  }
  EXPECT_NEAR(inside[0] / inside[1], 4.0, 0.5);
  EXPECT_NEAR(inside[1] / inside[2], 4.0, 0.5);
  EXPECT_NEAR(ends[0] / ends[1], 2.0, 0.4);
  EXPECT_NEAR(ends[1] / ends[2], 2.0, 0.4);
  EXPECT_LT(ends[2], 0.05 * exact(1.0).norm());
}

// ---------------------------------------------------------------------------
// Orientation, duplicates, degenerate input.

TEST(DeformationBoundaryData, ReversingBothCurvesGivesTheSameLaplacian)
{
  const SmoothMap map = PolynomialMap();
  std::vector<int> corners;
  const std::vector<std::vector<Vec2>> curves = { SCurve(150),
    Sample(Ellipse(Vec2(0, 1), 1.0, 0.6, 0.2), Parameters(300, 0.2)),
    Polygon({ Vec2(0, 0), Vec2(2, 0), Vec2(2.5, 1.5), Vec2(0.5, 2.0) }, 5, &corners) };
  for (std::size_t c = 0; c < curves.size(); ++c)
  {
    const bool closed = c > 0;
    const std::vector<Vec2>& points = curves[c];
    const std::vector<Vec2> images = Apply(map.Value, points);
    const auto forward = PolylineDeformationData(points, images, closed);
    const auto backward = PolylineDeformationData(Reversed(points), Reversed(images), closed);
    const double scale = MaxNorm(forward);
    ASSERT_GT(scale, 0.0);
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      const auto& b = backward[points.size() - 1 - i];
      EXPECT_NEAR((forward[i].Laplacian - b.Laplacian).norm(), 0.0, 1e-11 * scale) << c << " " << i;
      EXPECT_EQ(forward[i].Value, b.Value);
    }
  }
}

TEST(DeformationBoundaryData, DuplicatePointsAreMergedAndFinite)
{
  const SmoothMap map = PolynomialMap();
  const std::vector<Vec2> clean = Sample(Ellipse(Vec2(0, 0), 1.0, 0.7, 0.0), Parameters(60, 0.0));
  const auto reference = PolylineDeformationData(clean, Apply(map.Value, clean), true);

  // Every 7th point doubled (one tripled), and the first point repeated at
  // the end with the flag off: the same closed curve.
  std::vector<Vec2> points;
  std::vector<std::size_t> source;
  for (std::size_t i = 0; i < clean.size(); ++i)
  {
    const int copies = i == 14 ? 3 : (i % 7 == 0 ? 2 : 1);
    for (int c = 0; c < copies; ++c)
    {
      points.push_back(clean[i]);
      source.push_back(i);
    }
  }
  points.push_back(clean[0]);
  source.push_back(0);
  std::vector<Vec2> images = Apply(map.Value, points);
  images[1] += Vec2(1e-3, 0); // a duplicate keeps its own image point as g
  const auto samples = PolylineDeformationData(points, images, false);
  ASSERT_TRUE(Finite(samples));
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    EXPECT_EQ(samples[i].Laplacian, reference[source[i]].Laplacian) << i;
    EXPECT_EQ(samples[i].Value, images[i]);
  }
}

TEST(DeformationBoundaryData, DegenerateInputsStayFinite)
{
  const auto map = PolynomialMap().Value;
  const std::vector<std::vector<Vec2>> cases = {
    {},
    { Vec2(1, 1) },
    { Vec2(1, 1), Vec2(1, 1), Vec2(1, 1) },
    { Vec2(0, 0), Vec2(1, 0) },
    { Vec2(0, 0), Vec2(1, 0), Vec2(0, 0) },             // back and forth, "closed"
    { Vec2(0, 0), Vec2(1, 0), Vec2(0, 0), Vec2(1, 0) }, // reversals (spikes)
    { Vec2(0, 0), Vec2(0, 0), Vec2(1, 0), Vec2(1, 0), Vec2(1, 1), Vec2(1, 1) },
    { Vec2(0, 0), Vec2(1, 0), Vec2(1, 1e-20), Vec2(2, 0) },
  };
  for (const auto& points : cases)
  {
    for (bool closed : { false, true })
    {
      const auto samples = PolylineDeformationData(points, Apply(map, points), closed);
      EXPECT_EQ(samples.size(), points.size());
      EXPECT_TRUE(Finite(samples)) << points.size();
    }
  }
  EXPECT_THROW(PolylineDeformationData({ Vec2(0, 0) }, {}, false), std::invalid_argument);
}

TEST(DeformationBoundaryData, SeveralCurvesMatchSingleCurves)
{
  const auto map = PolynomialMap().Value;
  const std::vector<std::vector<Vec2>> curves = { SCurve(40),
    Sample(Ellipse(Vec2(3, 0), 0.5, 0.5, 0.0), Parameters(30, 0.0)) };
  const std::vector<std::vector<Vec2>> images = { Apply(map, curves[0]), Apply(map, curves[1]) };
  const auto all = PolylinesDeformationData(curves, images, { false, true });
  ASSERT_EQ(all.size(), 2u);
  for (std::size_t c = 0; c < 2; ++c)
  {
    const auto one = PolylineDeformationData(curves[c], images[c], c == 1);
    ASSERT_EQ(all[c].size(), one.size());
    for (std::size_t i = 0; i < one.size(); ++i)
    {
      EXPECT_EQ(all[c][i].Laplacian, one[i].Laplacian);
    }
  }
  EXPECT_THROW(PolylinesDeformationData(curves, images, { true }), std::invalid_argument);
}

// ---------------------------------------------------------------------------
// Cubic Bézier curves.

TEST(DeformationBoundaryDataBezier, SimilarityGivesZeroAtManyParameters)
{
  std::mt19937 rng(7);
  for (int trial = 0; trial < 50; ++trial)
  {
    const Bezier curve = RandomBezier(rng, 2.0);
    const Complex c = std::polar(0.3 + 0.1 * trial, 0.4 * trial);
    const Complex d(1.0 - 0.05 * trial, 0.5);
    Bezier image;
    for (int i = 0; i < 4; ++i)
    {
      image[i] = ToVec(c * ToComplex(curve[i]) + d);
    }
    for (int k = 0; k <= 100; ++k)
    {
      const double t = k / 100.0;
      const DeformationBoundarySample s = DeformationDataAt(curve, image, t);
      // h scales like |c| |γ''| / |γ'|²: compare with |c| / size.
      const double r = 1.0 - t;
      const double speed = (3.0 * (r * r * (curve[1] - curve[0]) +
                                    2.0 * r * t * (curve[2] - curve[1]) +
                                    t * t * (curve[3] - curve[2])))
                             .norm();
      if (speed > 1e-2)
      {
        EXPECT_LT(s.Laplacian.norm(), 1e-12 * std::abs(c) * (1.0 + 100.0 / (speed * speed)))
          << trial << " " << t;
      }
      EXPECT_TRUE(s.Laplacian.allFinite());
      EXPECT_NEAR((s.Value - BezierAt(image, t)).norm(), 0.0, 1e-13 * (1.0 + std::abs(c)));
    }
  }
}

TEST(DeformationBoundaryDataBezier, MatchesFiniteDifferencesOfTheCurves)
{
  std::mt19937 rng(11);
  for (int trial = 0; trial < 40; ++trial)
  {
    const Bezier curve = RandomBezier(rng, 1.0);
    const Bezier image = RandomBezier(rng, 1.5);
    for (int k = 1; k < 20; ++k)
    {
      const double t = k / 20.0;
      const double e = 1e-4;
      const Vec2 c0 = BezierAt(curve, t), cp = BezierAt(curve, t + e), cm = BezierAt(curve, t - e);
      const Vec2 i0 = BezierAt(image, t), ip = BezierAt(image, t + e), im = BezierAt(image, t - e);
      const Vec2 ct = (cp - cm) / (2 * e), ctt = (cp - 2.0 * c0 + cm) / (e * e);
      const Vec2 it = (ip - im) / (2 * e), itt = (ip - 2.0 * i0 + im) / (e * e);
      const double speed = ct.norm();
      if (speed < 0.3)
      {
        continue; // near a cusp the difference quotients lose their digits
      }
      // Chain rule to arc length, then the reference formula.
      const Vec2 tangent = ct / speed;
      const Vec2 curveSS = ctt / (speed * speed) - ct * ct.dot(ctt) / std::pow(speed, 4);
      const Vec2 imageS = it / speed;
      const Vec2 imageSS = itt / (speed * speed) - it * ct.dot(ctt) / std::pow(speed, 4);
      const Vec2 expected = ReferenceLaplacian(tangent, curveSS, imageS, imageSS);
      const Vec2 h = DeformationDataAt(curve, image, t).Laplacian;
      EXPECT_NEAR((h - expected).norm(), 0.0, 1e-5 * (1.0 + expected.norm())) << trial << " " << t;
    }
  }
}

TEST(DeformationBoundaryDataBezier, HolomorphicImageOfASegment)
{
  // A uniformly parametrized segment z(t) = A + t D and its image under
  // f(z) = z³ (a cubic in t): the closure is exact, so h = f''(z) T² = 6 z T².
  const Complex a(0.5, -0.3), d(1.2, 0.9);
  const Bezier curve = FromMonomials(a, d, 0.0, 0.0);
  const Bezier image = FromMonomials(a * a * a, 3.0 * a * a * d, 3.0 * a * d * d, d * d * d);
  const Complex tangent = d / std::abs(d);
  for (int k = 0; k <= 20; ++k)
  {
    const double t = k / 20.0;
    const Complex z = a + t * d;
    const DeformationBoundarySample s = DeformationDataAt(curve, image, t);
    EXPECT_NEAR((s.Laplacian - ToVec(6.0 * z * tangent * tangent)).norm(), 0.0, 1e-12) << t;
    EXPECT_NEAR((s.Value - ToVec(z * z * z)).norm(), 0.0, 1e-13);
  }
}

TEST(DeformationBoundaryDataBezier, ReversingBothCurvesGivesTheSameLaplacian)
{
  std::mt19937 rng(3);
  for (int trial = 0; trial < 20; ++trial)
  {
    const Bezier curve = RandomBezier(rng, 1.0), image = RandomBezier(rng, 1.0);
    for (int k = 0; k <= 10; ++k)
    {
      const double t = k / 10.0;
      const auto f = DeformationDataAt(curve, image, t);
      const auto b = DeformationDataAt(ReversedBezier(curve), ReversedBezier(image), 1.0 - t);
      EXPECT_NEAR((f.Laplacian - b.Laplacian).norm(), 0.0, 1e-9 * (1.0 + f.Laplacian.norm()));
      EXPECT_NEAR((f.Value - b.Value).norm(), 0.0, 1e-13);
    }
  }
}

TEST(DeformationBoundaryDataBezier, RepeatedEndControlPointIsFinite)
{
  // P1 = P0: B'(0) = 0 and the curvature goes like 1/t at the end, so h has
  // no limit (with Q1 = Q0 too, t h(t) is nearly constant; with Q1 ≠ Q0 the
  // image moves while the curve stands still and h grows faster). The
  // fallback must give a finite value of the size of h next to the end, the
  // same at either end of the reversed curve, and exactly zero for a
  // similarity.
  const Bezier curve = { Vec2(0, 0), Vec2(0, 0), Vec2(1, 1), Vec2(2, 0) };
  const Bezier matching = { Vec2(0, 1), Vec2(0, 1), Vec2(1, 2.5), Vec2(2.5, 1) };
  const Vec2 m1 = DeformationDataAt(curve, matching, 1e-3).Laplacian;
  const Vec2 m2 = DeformationDataAt(curve, matching, 2e-3).Laplacian;
  EXPECT_NEAR((1e-3 * m1 - 2e-3 * m2).norm(), 0.0, 0.01 * 1e-3 * m1.norm());
  for (const Bezier& image :
    { matching, Bezier{ Vec2(0, 1), Vec2(0.3, 1.2), Vec2(1, 2.5), Vec2(2.5, 1) } })
  {
    const Vec2 h1 = DeformationDataAt(curve, image, 1e-3).Laplacian;
    const DeformationBoundarySample s = DeformationDataAt(curve, image, 0.0);
    ASSERT_TRUE(s.Laplacian.allFinite());
    EXPECT_LT(s.Laplacian.norm(), 2.0 * h1.norm());
    EXPECT_GT(s.Laplacian.norm(), 0.5 * h1.norm());
    EXPECT_EQ(s.Value, image[0]);
    const DeformationBoundarySample e =
      DeformationDataAt(ReversedBezier(curve), ReversedBezier(image), 1.0);
    EXPECT_NEAR((e.Laplacian - s.Laplacian).norm(), 0.0, 1e-9 * s.Laplacian.norm());
  }
  Bezier rotated;
  for (int i = 0; i < 4; ++i)
  {
    rotated[i] = ToVec(Complex(0.6, 0.8) * ToComplex(curve[i]) + Complex(1, 2));
  }
  EXPECT_LT(DeformationDataAt(curve, rotated, 0.0).Laplacian.norm(), 1e-9);
  // Straight with a repeated control point, affine image: h = 0.
  const Bezier straight = { Vec2(0, 0), Vec2(0, 0), Vec2(1, 2), Vec2(1.5, 3) };
  const Bezier sheared = { Vec2(0, 0), Vec2(0, 0), Vec2(3, 1), Vec2(4.5, 1.5) };
  EXPECT_LT(DeformationDataAt(straight, sheared, 0.0).Laplacian.norm(), 1e-9);
}

TEST(DeformationBoundaryDataBezier, CuspsAndPointsStayFinite)
{
  // B'(0.5) = 0 when P3 + P2 = P1 + P0.
  const Bezier cusp = { Vec2(0, 0), Vec2(1, 1), Vec2(0, 1), Vec2(1, 0) };
  const Bezier image = { Vec2(0, 0), Vec2(1, 0.5), Vec2(2, 1), Vec2(3, 0) };
  for (double t : { 0.5, 0.49999, 0.500001 })
  {
    EXPECT_TRUE(DeformationDataAt(cusp, image, t).Laplacian.allFinite()) << t;
  }
  const Bezier point = { Vec2(1, 1), Vec2(1, 1), Vec2(1, 1), Vec2(1, 1) };
  for (double t : { 0.0, 0.3, 1.0 })
  {
    const auto s = DeformationDataAt(point, image, t);
    EXPECT_EQ(s.Laplacian, Vec2::Zero());
    EXPECT_NEAR((s.Value - BezierAt(image, t)).norm(), 0.0, 1e-14);
  }
  // t outside [0, 1] is clamped.
  EXPECT_EQ(DeformationDataAt(image, cusp, -0.5).Value, cusp[0]);
}
