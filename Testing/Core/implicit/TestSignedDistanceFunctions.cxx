// Tests of the exact signed distance primitives and of the CSG operators.
//
// Primitives are checked against brute force over a dense sampling of their
// surfaces, built from a parametrization of each surface and never from the
// code under test. The sampled minimum distance is an upper bound of the
// true distance and at most the sampling resolution above it, so an exact φ
// must satisfy sampled − resolution ≤ |φ| ≤ sampled (up to rounding).
//
// CSG results are not exact distances. What walk on spheres relies on is
// that they are 1-Lipschitz, hence |φ| never exceeds the distance to their
// own zero set; that is checked against zero-set points found by bisection
// along random lines, together with independent reference formulas, set
// membership, part reporting and bounds. Seeds are fixed, so failures are
// reproducible.
#include <gridfree/geometry/BoundingBox.h>
#include <gridfree/implicit/CsgFunctions.h>
#include <gridfree/implicit/SignedDistance.h>
#include <gridfree/implicit/SignedDistanceFunctions.h>
#include <gridfree/math/Vector.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
using gridfree::BoundingBox;
using gridfree::BoxDistance;
using gridfree::CapsuleDistance;
using gridfree::CsgDistance;
using gridfree::CsgOperation;
using gridfree::CylinderDistance;
using gridfree::ImplicitSample;
using gridfree::PlaneDistance;
using gridfree::RoundedBoxDistance;
using gridfree::SignedDistanceFunction;
using gridfree::SphereDistance;
using gridfree::TorusDistance;
using gridfree::Vec;
using gridfree::Vec2;
using gridfree::Vec3;

using Rng = std::mt19937_64;

template <int DIM>
using SdfPointer = std::shared_ptr<const SignedDistanceFunction<DIM>>;

constexpr double kPi = 3.14159265358979323846;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// The first DIM of three coordinates, so that 2D and 3D tests share setups.
template <int DIM>
Vec<DIM> V(double x, double y, double z = 0.0)
{
  Vec<DIM> v;
  v[0] = x;
  v[1] = y;
  if constexpr (DIM == 3)
  {
    v[2] = z;
  }
  return v;
}

template <int DIM>
Vec<DIM> UniformPoint(Rng& rng, const Vec<DIM>& lo, const Vec<DIM>& hi)
{
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Vec<DIM> p;
  for (int i = 0; i < DIM; ++i)
  {
    p[i] = lo[i] + u(rng) * (hi[i] - lo[i]);
  }
  return p;
}

template <int DIM>
Vec<DIM> RandomDirection(Rng& rng)
{
  std::normal_distribution<double> n(0.0, 1.0);
  Vec<DIM> d;
  do
  {
    for (int i = 0; i < DIM; ++i)
    {
      d[i] = n(rng);
    }
  } while (d.norm() < 1e-3);
  return d.normalized();
}

template <int DIM>
double NearestDistance(const std::vector<Vec<DIM>>& points, const Vec<DIM>& x)
{
  double best = kInf;
  for (const Vec<DIM>& p : points)
  {
    best = std::min(best, (p - x).squaredNorm());
  }
  return std::sqrt(best);
}

//------------------------------------------------------------------------------
// Dense surface samplings, by construction.
template <int DIM>
struct SurfaceSamples
{
  std::vector<Vec<DIM>> Points;
  // Every surface point has a sample within this distance.
  double Resolution = 0.0;
};

// Points f(s), s on a uniform grid of [0, 1] (ends included). `speed` bounds
// |f'|; a curve point is within half a step of arc length of a grid point.
template <int DIM, typename F>
void AddCurve(SurfaceSamples<DIM>& out, F f, double speed, double spacing)
{
  const int n = std::max(1, static_cast<int>(std::ceil(speed / spacing)));
  for (int i = 0; i <= n; ++i)
  {
    out.Points.push_back(f(static_cast<double>(i) / n));
  }
  out.Resolution = std::max(out.Resolution, 0.5 * speed / n);
}

// Points f(s, t) on a grid of [0, 1]^2 (edges included). speedS and speedT
// bound |∂f/∂s| and |∂f/∂t|: a surface point is reached from the nearest
// grid point by half a step along s and half a step along t.
template <typename F>
void AddPatch(SurfaceSamples<3>& out, F f, double speedS, double speedT, double spacing)
{
  const int ns = std::max(1, static_cast<int>(std::ceil(speedS / spacing)));
  const int nt = std::max(1, static_cast<int>(std::ceil(speedT / spacing)));
  for (int i = 0; i <= ns; ++i)
  {
    for (int j = 0; j <= nt; ++j)
    {
      out.Points.push_back(f(static_cast<double>(i) / ns, static_cast<double>(j) / nt));
    }
  }
  out.Resolution = std::max(out.Resolution, 0.5 * (speedS / ns + speedT / nt));
}

// An orthonormal frame (E1, E2, U) around a unit axis U, by Gram–Schmidt.
struct Frame
{
  Vec3 U, E1, E2;
};

Frame MakeFrame(const Vec3& axis)
{
  Frame f;
  f.U = axis.normalized();
  const Vec3 t = std::abs(f.U[0]) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  f.E1 = (t - t.dot(f.U) * f.U).normalized();
  f.E2 = f.U.cross(f.E1);
  return f;
}

Vec3 Circle(const Frame& f, double angle)
{
  return std::cos(angle) * f.E1 + std::sin(angle) * f.E2;
}

template <int DIM>
SurfaceSamples<DIM> SphereSurface(const Vec<DIM>& c, double r, double spacing)
{
  SurfaceSamples<DIM> out;
  if constexpr (DIM == 2)
  {
    AddCurve<2>(
      out, [&](double s) { return Vec2(c + r * Vec2(std::cos(2 * kPi * s), std::sin(2 * kPi * s))); },
      2 * kPi * r, spacing);
  }
  else
  {
    AddPatch(
      out,
      [&](double s, double t) {
        const double theta = kPi * s, phi = 2 * kPi * t;
        return Vec3(c +
          r * Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)));
      },
      kPi * r, 2 * kPi * r, spacing);
  }
  return out;
}

template <int DIM>
SurfaceSamples<DIM> BoxSurface(const Vec<DIM>& c, const Vec<DIM>& h, double spacing)
{
  SurfaceSamples<DIM> out;
  for (int k = 0; k < DIM; ++k)
  {
    for (double sign : { -1.0, 1.0 })
    {
      Vec<DIM> faceCenter = c;
      faceCenter[k] += sign * h[k];
      if constexpr (DIM == 2)
      {
        const int i = 1 - k;
        AddCurve<2>(
          out,
          [&](double s) {
            Vec2 p = faceCenter;
            p[i] += (2 * s - 1) * h[i];
            return p;
          },
          2 * h[i], spacing);
      }
      else
      {
        const int i = (k + 1) % 3, j = (k + 2) % 3;
        AddPatch(
          out,
          [&](double s, double t) {
            Vec3 p = faceCenter;
            p[i] += (2 * s - 1) * h[i];
            p[j] += (2 * t - 1) * h[j];
            return p;
          },
          2 * h[i], 2 * h[j], spacing);
      }
    }
  }
  return out;
}

// The rounded box is the convex set K = (inner box) ⊕ ball(ρ). Its boundary
// is the image of the outer box surface under the projection onto K, which
// is q + ρ (y − q)/|y − q| with q the clamp of y to the inner box. The
// projection onto a convex set is 1-Lipschitz and onto (every boundary point
// is the projection of the point where its normal ray leaves the outer box),
// so the projected samples keep the resolution of the outer box samples.
template <int DIM>
SurfaceSamples<DIM> RoundedBoxSurface(
  const Vec<DIM>& c, const Vec<DIM>& h, double rounding, double spacing)
{
  SurfaceSamples<DIM> out = BoxSurface<DIM>(c, h, spacing);
  const Vec<DIM> lo = c - (h.array() - rounding).matrix(), hi = c + (h.array() - rounding).matrix();
  for (Vec<DIM>& y : out.Points)
  {
    const Vec<DIM> q = y.cwiseMax(lo).cwiseMin(hi);
    const double gap = (y - q).norm();
    if (gap > 0.0)
    {
      y = q + rounding * (y - q) / gap;
    }
  }
  return out;
}

template <int DIM>
SurfaceSamples<DIM> CapsuleSurface(const Vec<DIM>& a, const Vec<DIM>& b, double r, double spacing)
{
  SurfaceSamples<DIM> out;
  const double length = (b - a).norm();
  const Vec<DIM> d = (b - a) / length;
  if constexpr (DIM == 2)
  {
    const Vec2 n(-d[1], d[0]);
    for (double sign : { -1.0, 1.0 })
    {
      AddCurve<2>(
        out, [&](double s) { return Vec2(a + s * (b - a) + sign * r * n); }, length, spacing);
    }
    AddCurve<2>(
      out,
      [&](double s) {
        const double alpha = -kPi / 2 + kPi * s;
        return Vec2(b + r * (std::cos(alpha) * d + std::sin(alpha) * n));
      },
      kPi * r, spacing);
    AddCurve<2>(
      out,
      [&](double s) {
        const double alpha = -kPi / 2 + kPi * s;
        return Vec2(a + r * (-std::cos(alpha) * d + std::sin(alpha) * n));
      },
      kPi * r, spacing);
  }
  else
  {
    const Frame f = MakeFrame(d);
    AddPatch(
      out, [&](double s, double t) { return Vec3(a + s * (b - a) + r * Circle(f, 2 * kPi * t)); },
      length, 2 * kPi * r, spacing);
    for (const auto& [center, pole] : { std::make_pair(b, d), std::make_pair(a, Vec3(-d)) })
    {
      AddPatch(
        out,
        [&](double s, double t) {
          const double theta = 0.5 * kPi * s;
          return Vec3(
            center + r * (std::cos(theta) * pole + std::sin(theta) * Circle(f, 2 * kPi * t)));
        },
        0.5 * kPi * r, 2 * kPi * r, spacing);
    }
  }
  return out;
}

// A square patch of the plane, large enough for queries near the origin.
template <int DIM>
SurfaceSamples<DIM> PlaneSurface(const Vec<DIM>& p, const Vec<DIM>& normal, double half, double spacing)
{
  SurfaceSamples<DIM> out;
  const Vec<DIM> n = normal.normalized();
  if constexpr (DIM == 2)
  {
    const Vec2 t(-n[1], n[0]);
    AddCurve<2>(out, [&](double s) { return Vec2(p + (2 * s - 1) * half * t); }, 2 * half, spacing);
  }
  else
  {
    const Frame f = MakeFrame(n);
    AddPatch(
      out,
      [&](double s, double t) { return Vec3(p + (2 * s - 1) * half * f.E1 + (2 * t - 1) * half * f.E2); },
      2 * half, 2 * half, spacing);
  }
  return out;
}

SurfaceSamples<3> TorusSurface(const Vec3& c, const Vec3& axis, double R, double r, double spacing)
{
  SurfaceSamples<3> out;
  const Frame f = MakeFrame(axis);
  AddPatch(
    out,
    [&](double s, double t) {
      const double around = 2 * kPi * s, tube = 2 * kPi * t;
      return Vec3(c + (R + r * std::cos(tube)) * Circle(f, around) + r * std::sin(tube) * f.U);
    },
    2 * kPi * (R + r), 2 * kPi * r, spacing);
  return out;
}

SurfaceSamples<3> CylinderSurface(const Vec3& c, const Vec3& axis, double r, double H, double spacing)
{
  SurfaceSamples<3> out;
  const Frame f = MakeFrame(axis);
  AddPatch(
    out, [&](double s, double t) { return Vec3(c + (2 * s - 1) * H * f.U + r * Circle(f, 2 * kPi * t)); },
    2 * H, 2 * kPi * r, spacing);
  for (double sign : { -1.0, 1.0 })
  {
    AddPatch(
      out,
      [&](double s, double t) { return Vec3(c + sign * H * f.U + s * r * Circle(f, 2 * kPi * t)); },
      r, 2 * kPi * r, spacing);
  }
  return out;
}

//------------------------------------------------------------------------------
// Shared checks.
template <int DIM>
Vec<DIM> CentralDifference(const SignedDistanceFunction<DIM>& f, const Vec<DIM>& x, double h)
{
  Vec<DIM> g;
  for (int i = 0; i < DIM; ++i)
  {
    Vec<DIM> a = x, b = x;
    a[i] += h;
    b[i] -= h;
    g[i] = (f.Value(a) - f.Value(b)) / (2 * h);
  }
  return g;
}

// Compares the analytic gradient with central differences. Near a kink two
// step sizes disagree; such points are counted in `skipped` and not judged.
template <int DIM>
bool GradientAgrees(const SignedDistanceFunction<DIM>& f, const Vec<DIM>& x, int& skipped)
{
  const Vec<DIM> fine = CentralDifference<DIM>(f, x, 1e-6);
  const Vec<DIM> coarse = CentralDifference<DIM>(f, x, 1e-5);
  if ((fine - coarse).norm() > 1e-5)
  {
    ++skipped;
    return true;
  }
  return (f.Gradient(x) - fine).norm() <= 1e-6;
}

// |φ(x) − φ(y)| ≤ |x − y| on random pairs, far apart and close together.
// The absolute slack covers the rounding of φ itself (values of order 1).
template <int DIM>
void CheckLipschitz(const SignedDistanceFunction<DIM>& f, const Vec<DIM>& lo, const Vec<DIM>& hi,
  std::uint64_t seed, const std::string& name)
{
  Rng rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worst = -kInf;
  for (int i = 0; i < 4000; ++i)
  {
    const Vec<DIM> x = UniformPoint<DIM>(rng, lo, hi);
    const double length = (i % 2 == 0) ? 2.0 * u(rng) : 1e-4 + 1e-3 * u(rng);
    const Vec<DIM> y = x + length * RandomDirection<DIM>(rng);
    const double slack = std::abs(f.Value(x) - f.Value(y)) - (x - y).norm() * (1 + 1e-12) - 4e-15;
    worst = std::max(worst, slack);
  }
  EXPECT_LE(worst, 0.0) << name << ": Lipschitz bound 1 violated";
}

//------------------------------------------------------------------------------
// Primitives.
template <int DIM>
struct PrimitiveCase
{
  std::string Name;
  SdfPointer<DIM> Function;
  SurfaceSamples<DIM> Surface;
  // Independent membership test of the open solid.
  std::function<bool(const Vec<DIM>&)> Inside;
  // Where φ is not differentiable: the gradient must still be a unit vector.
  std::vector<Vec<DIM>> SpecialPoints;
  // Query region for unbounded primitives (bounded ones use Bounds()).
  Vec<DIM> QueryMin = Vec<DIM>::Constant(-2.0);
  Vec<DIM> QueryMax = Vec<DIM>::Constant(2.0);
  int Queries = 2000;
};

template <int DIM>
void CheckPrimitive(const PrimitiveCase<DIM>& c, std::uint64_t seed)
{
  const SignedDistanceFunction<DIM>& f = *c.Function;
  const SurfaceSamples<DIM>& surface = c.Surface;
  ASSERT_FALSE(surface.Points.empty());
  Rng rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);

  const BoundingBox<DIM> bounds = f.Bounds();
  Vec<DIM> lo = c.QueryMin, hi = c.QueryMax;
  if (!bounds.IsEmpty())
  {
    lo = bounds.Min - Vec<DIM>::Constant(0.5);
    hi = bounds.Max + Vec<DIM>::Constant(0.5);
  }
  // Near-surface queries start from samples in the query region only: near
  // the rim of a plane patch the nearest sample is not the nearest point.
  std::vector<Vec<DIM>> anchors;
  for (const Vec<DIM>& p : surface.Points)
  {
    if ((p.array() >= lo.array()).all() && (p.array() <= hi.array()).all())
    {
      anchors.push_back(p);
    }
  }
  ASSERT_FALSE(anchors.empty());
  std::uniform_int_distribution<std::size_t> pick(0, anchors.size() - 1);

  double worstAbove = -kInf, worstBelow = -kInf, worstProjection = 0, worstUnit = 0;
  int signErrors = 0, inside = 0, outside = 0, gradientErrors = 0, skipped = 0, sampleErrors = 0;
  for (int q = 0; q < c.Queries; ++q)
  {
    // Half uniform, half near the surface where mistakes in the formulas
    // (edges, rims, caps) show most.
    const Vec<DIM> x = (q % 2 == 0)
      ? UniformPoint<DIM>(rng, lo, hi)
      : Vec<DIM>(anchors[pick(rng)] + 0.3 * u(rng) * RandomDirection<DIM>(rng));
    const double phi = f.Value(x);
    const double sampled = NearestDistance<DIM>(surface.Points, x);
    worstAbove = std::max(worstAbove, std::abs(phi) - sampled);
    worstBelow = std::max(worstBelow, sampled - std::abs(phi));
    if (std::abs(phi) > 1e-9)
    {
      const bool in = c.Inside(x);
      (in ? inside : outside)++;
      signErrors += ((phi < 0) != in) ? 1 : 0;
    }
    const Vec<DIM> g = f.Gradient(x);
    worstUnit = std::max(worstUnit, g.allFinite() ? std::abs(g.norm() - 1) : kInf);
    const Vec<DIM> projected = x - phi * g;
    worstProjection = std::max(worstProjection, std::abs(f.Value(projected)));
    gradientErrors += GradientAgrees<DIM>(f, x, skipped) ? 0 : 1;
    const ImplicitSample s = f.Sample(x);
    sampleErrors += (s.value == phi && s.part == 0) ? 0 : 1;
  }
  EXPECT_LE(worstAbove, 1e-9) << c.Name << ": |φ| exceeds the distance to surface samples";
  EXPECT_LE(worstBelow, surface.Resolution + 1e-12)
    << c.Name << ": |φ| below the distance by more than the sampling resolution "
    << surface.Resolution;
  EXPECT_EQ(signErrors, 0) << c.Name;
  EXPECT_GT(inside, c.Queries / 20) << c.Name;
  EXPECT_GT(outside, c.Queries / 20) << c.Name;
  EXPECT_LE(worstUnit, 1e-12) << c.Name << ": gradient not unit";
  EXPECT_LE(worstProjection, 1e-9) << c.Name << ": x − φ∇φ is not on the surface";
  EXPECT_EQ(gradientErrors, 0) << c.Name << ": analytic gradient differs from central differences";
  EXPECT_LE(skipped, c.Queries / 50) << c.Name << ": too many points near kinks";
  EXPECT_EQ(sampleErrors, 0) << c.Name;
  EXPECT_EQ(f.NumberOfParts(), 1);
  EXPECT_EQ(f.Lipschitz(), 1.0);

  CheckLipschitz<DIM>(f, lo, hi, seed + 1, c.Name);

  for (const Vec<DIM>& p : c.SpecialPoints)
  {
    const Vec<DIM> g = f.Gradient(p);
    EXPECT_TRUE(g.allFinite()) << c.Name << " at " << p.transpose();
    EXPECT_NEAR(g.norm(), 1.0, 1e-12) << c.Name << " at " << p.transpose();
    EXPECT_TRUE(std::isfinite(f.Value(p)));
    // Where φ has no gradient the primitives still return a direction to a
    // nearest surface point, so the projection stays on the surface.
    EXPECT_LE(std::abs(f.Value(p - f.Value(p) * g)), 1e-9) << c.Name << " at " << p.transpose();
  }

  if (bounds.IsEmpty())
  {
    return;
  }
  // Bounds: hold every surface sample, and are tight to the resolution.
  Vec<DIM> sampleMin = Vec<DIM>::Constant(kInf), sampleMax = Vec<DIM>::Constant(-kInf);
  for (const Vec<DIM>& p : surface.Points)
  {
    sampleMin = sampleMin.cwiseMin(p);
    sampleMax = sampleMax.cwiseMax(p);
  }
  for (int i = 0; i < DIM; ++i)
  {
    EXPECT_LE(bounds.Min[i], sampleMin[i] + 1e-12) << c.Name;
    EXPECT_GE(bounds.Max[i], sampleMax[i] - 1e-12) << c.Name;
    EXPECT_LE(sampleMin[i] - bounds.Min[i], surface.Resolution) << c.Name << ": bounds not tight";
    EXPECT_LE(bounds.Max[i] - sampleMax[i], surface.Resolution) << c.Name << ": bounds not tight";
  }
}

// Sampling steps: fine in 2D, coarser in 3D where samples grow quadratically.
constexpr double kSpacing2 = 0.002;
constexpr double kSpacing3 = 0.02;

template <int DIM>
constexpr double Spacing()
{
  return DIM == 2 ? kSpacing2 : kSpacing3;
}

template <int DIM>
PrimitiveCase<DIM> SphereCase()
{
  const Vec<DIM> c = V<DIM>(0.3, -0.2, 0.1);
  const double r = 0.8;
  PrimitiveCase<DIM> pc;
  pc.Name = "sphere" + std::to_string(DIM);
  pc.Function = std::make_shared<SphereDistance<DIM>>(c, r);
  pc.Surface = SphereSurface<DIM>(c, r, Spacing<DIM>());
  pc.Inside = [=](const Vec<DIM>& x) { return (x - c).norm() < r; };
  pc.SpecialPoints = { c };
  return pc;
}

template <int DIM>
PrimitiveCase<DIM> BoxCase()
{
  const Vec<DIM> c = V<DIM>(-0.1, 0.2, 0.3), h = V<DIM>(0.6, 0.35, 0.8);
  PrimitiveCase<DIM> pc;
  pc.Name = "box" + std::to_string(DIM);
  pc.Function = std::make_shared<BoxDistance<DIM>>(c, h);
  pc.Surface = BoxSurface<DIM>(c, h, Spacing<DIM>());
  pc.Inside = [=](const Vec<DIM>& x) { return ((x - c).cwiseAbs().array() < h.array()).all(); };
  pc.SpecialPoints = { c, Vec<DIM>(c + h), Vec<DIM>(c - h), c + V<DIM>(0.1, 0.1, 0.1) };
  return pc;
}

template <int DIM>
PrimitiveCase<DIM> RoundedBoxCase(double rounding, const std::string& name)
{
  const Vec<DIM> c = V<DIM>(0.2, 0.1, -0.2), h = V<DIM>(0.7, 0.4, 0.55);
  auto f = std::make_shared<RoundedBoxDistance<DIM>>(c, h, rounding);
  const double rho = f->GetRounding();
  const Vec<DIM> innerLo = c - (h.array() - rho).matrix(), innerHi = c + (h.array() - rho).matrix();
  PrimitiveCase<DIM> pc;
  pc.Name = name + std::to_string(DIM);
  pc.Function = f;
  pc.Surface = RoundedBoxSurface<DIM>(c, h, rho, Spacing<DIM>());
  pc.Inside = [=](const Vec<DIM>& x) { return (x - x.cwiseMax(innerLo).cwiseMin(innerHi)).norm() < rho; };
  pc.SpecialPoints = { c, innerHi, innerLo };
  return pc;
}

template <int DIM>
PrimitiveCase<DIM> CapsuleCase()
{
  const Vec<DIM> a = V<DIM>(-0.7, -0.3, 0.2), b = V<DIM>(0.5, 0.4, -0.3);
  const double r = 0.35;
  PrimitiveCase<DIM> pc;
  pc.Name = "capsule" + std::to_string(DIM);
  pc.Function = std::make_shared<CapsuleDistance<DIM>>(a, b, r);
  pc.Surface = CapsuleSurface<DIM>(a, b, r, Spacing<DIM>());
  pc.Inside = [=](const Vec<DIM>& x) {
    const double t = std::clamp((x - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    return (x - (a + t * (b - a))).norm() < r;
  };
  pc.SpecialPoints = { a, b, Vec<DIM>(0.5 * (a + b)) };
  return pc;
}

template <int DIM>
PrimitiveCase<DIM> PlaneCase()
{
  const Vec<DIM> p = V<DIM>(0.1, -0.2, 0.15), n = V<DIM>(2.0, -1.0, 3.0); // not unit on purpose
  PrimitiveCase<DIM> pc;
  pc.Name = "plane" + std::to_string(DIM);
  pc.Function = std::make_shared<PlaneDistance<DIM>>(p, n);
  // The patch must hold the closest points of all queries in [−2.5, 2.5]^DIM.
  pc.Surface = PlaneSurface<DIM>(p, n, 5.5, DIM == 2 ? kSpacing2 : 0.05);
  pc.Inside = [=](const Vec<DIM>& x) { return (x - p).dot(n) < 0; };
  pc.QueryMin = Vec<DIM>::Constant(-2.0);
  pc.QueryMax = Vec<DIM>::Constant(2.0);
  pc.Queries = DIM == 2 ? 2000 : 600;
  return pc;
}

TEST(SignedDistancePrimitives, Sphere2D) { CheckPrimitive<2>(SphereCase<2>(), 11); }
TEST(SignedDistancePrimitives, Sphere3D) { CheckPrimitive<3>(SphereCase<3>(), 12); }
TEST(SignedDistancePrimitives, Box2D) { CheckPrimitive<2>(BoxCase<2>(), 21); }
TEST(SignedDistancePrimitives, Box3D) { CheckPrimitive<3>(BoxCase<3>(), 22); }
TEST(SignedDistancePrimitives, RoundedBox2D)
{
  CheckPrimitive<2>(RoundedBoxCase<2>(0.15, "roundedBox"), 31);
}
TEST(SignedDistancePrimitives, RoundedBox3D)
{
  CheckPrimitive<3>(RoundedBoxCase<3>(0.15, "roundedBox"), 32);
}
// Rounding beyond the smallest half extent is clamped to it: the inner box
// is then flat, a case the box formula must still handle exactly.
TEST(SignedDistancePrimitives, FullyRoundedBox2D)
{
  CheckPrimitive<2>(RoundedBoxCase<2>(10.0, "fullyRoundedBox"), 33);
}
TEST(SignedDistancePrimitives, FullyRoundedBox3D)
{
  CheckPrimitive<3>(RoundedBoxCase<3>(10.0, "fullyRoundedBox"), 34);
}
TEST(SignedDistancePrimitives, Capsule2D) { CheckPrimitive<2>(CapsuleCase<2>(), 41); }
TEST(SignedDistancePrimitives, Capsule3D) { CheckPrimitive<3>(CapsuleCase<3>(), 42); }
TEST(SignedDistancePrimitives, Plane2D) { CheckPrimitive<2>(PlaneCase<2>(), 51); }
TEST(SignedDistancePrimitives, Plane3D) { CheckPrimitive<3>(PlaneCase<3>(), 52); }

TEST(SignedDistancePrimitives, Torus)
{
  const Vec3 c(0.1, -0.2, 0.3), axis(1.0, 2.0, 2.0); // not unit on purpose
  const double R = 0.8, r = 0.3;
  const Frame frame = MakeFrame(axis);
  PrimitiveCase<3> pc;
  pc.Name = "torus";
  pc.Function = std::make_shared<TorusDistance>(c, axis, R, r);
  pc.Surface = TorusSurface(c, axis, R, r, kSpacing3);
  pc.Inside = [=](const Vec3& x) {
    const Vec3 d = x - c;
    const double z = d.dot(frame.U);
    const double rho = (d - z * frame.U).norm();
    return (rho - R) * (rho - R) + z * z < r * r;
  };
  // On the axis (every circle point closest) and on the core circle.
  pc.SpecialPoints = { c, Vec3(c + 0.5 * frame.U), Vec3(c + R * frame.E1), Vec3(c - R * frame.E2) };
  CheckPrimitive<3>(pc, 61);
}

// A horn torus (r = R) is still exact; a spindle torus (r > R) is refused.
TEST(SignedDistancePrimitives, HornTorus)
{
  const Vec3 c(0.0, 0.1, 0.0), axis(0.0, 0.0, 1.0);
  const double R = 0.5, r = 0.5;
  PrimitiveCase<3> pc;
  pc.Name = "hornTorus";
  pc.Function = std::make_shared<TorusDistance>(c, axis, R, r);
  pc.Surface = TorusSurface(c, axis, R, r, kSpacing3);
  pc.Inside = [=](const Vec3& x) {
    const Vec3 d = x - c;
    const double rho = std::hypot(d[0], d[1]);
    return (rho - R) * (rho - R) + d[2] * d[2] < r * r;
  };
  pc.SpecialPoints = { c };
  CheckPrimitive<3>(pc, 62);
}

TEST(SignedDistancePrimitives, Cylinder)
{
  const Vec3 c(-0.2, 0.1, 0.05), axis(0.3, -0.5, 0.8); // not unit on purpose
  const double r = 0.45, H = 0.6;
  const Frame frame = MakeFrame(axis);
  PrimitiveCase<3> pc;
  pc.Name = "cylinder";
  pc.Function = std::make_shared<CylinderDistance>(c, axis, r, H);
  pc.Surface = CylinderSurface(c, axis, r, H, kSpacing3);
  pc.Inside = [=](const Vec3& x) {
    const Vec3 d = x - c;
    const double z = d.dot(frame.U);
    return std::abs(z) < H && (d - z * frame.U).norm() < r;
  };
  // Center and axis (medial), and a rim point (edge).
  pc.SpecialPoints = { c, Vec3(c + 0.1 * frame.U), Vec3(c + H * frame.U + r * frame.E1) };
  CheckPrimitive<3>(pc, 71);
}

TEST(SignedDistancePrimitives, DegenerateParameters)
{
  // Rounding 0 (and negative, clamped) is the plain box.
  const Vec3 c(0.1, 0.2, 0.3), h(0.5, 0.6, 0.7);
  const BoxDistance<3> box(c, h);
  const RoundedBoxDistance<3> sharp(c, h, 0.0), negative(c, h, -1.0);
  EXPECT_EQ(negative.GetRounding(), 0.0);
  EXPECT_EQ(RoundedBoxDistance<3>(c, h, 2.0).GetRounding(), 0.5);
  // A capsule with a = b is a ball.
  const SphereDistance<3> ball(c, 0.4);
  const CapsuleDistance<3> point(c, c, 0.4);
  Rng rng(81);
  for (int i = 0; i < 500; ++i)
  {
    const Vec3 x = UniformPoint<3>(rng, Vec3::Constant(-2), Vec3::Constant(2));
    EXPECT_NEAR(sharp.Value(x), box.Value(x), 1e-15);
    EXPECT_NEAR(negative.Value(x), box.Value(x), 1e-15);
    EXPECT_NEAR(point.Value(x), ball.Value(x), 1e-15);
    EXPECT_LE((point.Gradient(x) - ball.Gradient(x)).norm(), 1e-14);
  }
  EXPECT_NEAR(point.Gradient(c).norm(), 1.0, 1e-15);
  // Normals and axes are stored normalized.
  EXPECT_NEAR(PlaneDistance<3>(c, Vec3(0, 0, 5)).GetNormal().norm(), 1.0, 1e-15);
  EXPECT_NEAR(PlaneDistance<3>(c, Vec3(1e-200, 0, 0)).GetNormal()[0], 1.0, 1e-15);
  EXPECT_NEAR(TorusDistance(c, Vec3(0, 3, 4), 1, 0.5).GetAxis().norm(), 1.0, 1e-15);
  EXPECT_NEAR(CylinderDistance(c, Vec3(0, 3, 4), 1, 0.5).GetAxis().norm(), 1.0, 1e-15);
  EXPECT_TRUE(PlaneDistance<2>(Vec2(0, 0), Vec2(1, 1)).Bounds().IsEmpty());
}

TEST(SignedDistancePrimitives, ArgumentValidation)
{
  const Vec3 c(0, 0, 0), h(1, 1, 1), nanPoint(kNaN, 0, 0), infPoint(0, kInf, 0);
  EXPECT_THROW(SphereDistance<3>(c, 0.0), std::invalid_argument);
  EXPECT_THROW(SphereDistance<3>(c, -1.0), std::invalid_argument);
  EXPECT_THROW(SphereDistance<3>(c, kNaN), std::invalid_argument);
  EXPECT_THROW(SphereDistance<3>(c, kInf), std::invalid_argument);
  EXPECT_THROW(SphereDistance<3>(nanPoint, 1.0), std::invalid_argument);
  EXPECT_THROW(SphereDistance<2>(Vec2(kInf, 0), 1.0), std::invalid_argument);
  EXPECT_THROW(BoxDistance<3>(c, Vec3(1, 0, 1)), std::invalid_argument);
  EXPECT_THROW(BoxDistance<3>(c, Vec3(1, -1, 1)), std::invalid_argument);
  EXPECT_THROW(BoxDistance<2>(Vec2(0, 0), Vec2(1, kNaN)), std::invalid_argument);
  EXPECT_THROW(BoxDistance<3>(infPoint, h), std::invalid_argument);
  EXPECT_THROW(RoundedBoxDistance<3>(c, Vec3(0, 1, 1), 0.1), std::invalid_argument);
  EXPECT_THROW(RoundedBoxDistance<3>(c, h, kNaN), std::invalid_argument);
  EXPECT_THROW(RoundedBoxDistance<3>(nanPoint, h, 0.1), std::invalid_argument);
  EXPECT_THROW(CapsuleDistance<3>(c, h, 0.0), std::invalid_argument);
  EXPECT_THROW(CapsuleDistance<3>(nanPoint, h, 1.0), std::invalid_argument);
  EXPECT_THROW(CapsuleDistance<2>(Vec2(0, 0), Vec2(kInf, 0), 1.0), std::invalid_argument);
  EXPECT_THROW(PlaneDistance<3>(c, Vec3::Zero()), std::invalid_argument);
  EXPECT_THROW(PlaneDistance<2>(Vec2(0, 0), Vec2(kNaN, 1)), std::invalid_argument);
  EXPECT_THROW(PlaneDistance<3>(infPoint, h), std::invalid_argument);
  EXPECT_THROW(TorusDistance(c, Vec3::Zero(), 1.0, 0.5), std::invalid_argument);
  EXPECT_THROW(TorusDistance(c, h, 0.0, 0.5), std::invalid_argument);
  EXPECT_THROW(TorusDistance(c, h, 1.0, 0.0), std::invalid_argument);
  EXPECT_THROW(TorusDistance(c, h, 1.0, 1.5), std::invalid_argument);
  EXPECT_THROW(TorusDistance(nanPoint, h, 1.0, 0.5), std::invalid_argument);
  EXPECT_THROW(CylinderDistance(c, Vec3::Zero(), 1.0, 1.0), std::invalid_argument);
  EXPECT_THROW(CylinderDistance(c, h, -1.0, 1.0), std::invalid_argument);
  EXPECT_THROW(CylinderDistance(c, h, 1.0, 0.0), std::invalid_argument);
  EXPECT_THROW(CylinderDistance(c, Vec3(kInf, 0, 0), 1.0, 1.0), std::invalid_argument);
  EXPECT_NO_THROW(TorusDistance(c, h, 1.0, 1.0));
}

//------------------------------------------------------------------------------
// CSG.

// 3 × (distance to a ball) with Lipschitz constant 3: not a distance, so CSG
// must divide it by 3 before combining.
template <int DIM>
class ScaledSphere final : public SignedDistanceFunction<DIM>
{
public:
  ScaledSphere(const Vec<DIM>& c, double r, double lipschitz = 3.0)
    : Center(c)
    , Radius(r)
    , L(lipschitz)
  {
  }
  double Value(const Vec<DIM>& x) const override { return 3.0 * ((x - this->Center).norm() - this->Radius); }
  Vec<DIM> Gradient(const Vec<DIM>& x) const override
  {
    return 3.0 * (x - this->Center).normalized();
  }
  double Lipschitz() const override { return this->L; }
  BoundingBox<DIM> Bounds() const override
  {
    return BoundingBox<DIM>(this->Center - Vec<DIM>::Constant(this->Radius),
      this->Center + Vec<DIM>::Constant(this->Radius));
  }

private:
  Vec<DIM> Center;
  double Radius;
  double L;
};

template <int DIM>
SdfPointer<DIM> Csg(CsgOperation op, SdfPointer<DIM> a, SdfPointer<DIM> b, double k = 0.0)
{
  return std::make_shared<CsgDistance<DIM>>(op, std::move(a), std::move(b), k);
}

// Overlapping ball and box shared by the CSG tests.
template <int DIM>
struct SphereAndBox
{
  Vec<DIM> SphereCenter = V<DIM>(0.3, 0.1, 0.0);
  double SphereRadius = 0.9;
  Vec<DIM> BoxCenter = V<DIM>(-0.4, 0.0, 0.1);
  Vec<DIM> BoxHalf = V<DIM>(0.7, 0.5, 0.6);
  SdfPointer<DIM> Sphere = std::make_shared<SphereDistance<DIM>>(SphereCenter, SphereRadius);
  SdfPointer<DIM> Box = std::make_shared<BoxDistance<DIM>>(BoxCenter, BoxHalf);

  bool InSphere(const Vec<DIM>& x) const { return (x - SphereCenter).norm() < SphereRadius; }
  bool InBox(const Vec<DIM>& x) const
  {
    return ((x - BoxCenter).cwiseAbs().array() < BoxHalf.array()).all();
  }
};

// Points of the zero set: every sign change along random lines crossing the
// domain, refined by bisection to the last bits. The lines pass through
// random points of Bounds() (when bounded) so that small shapes get hit,
// but they run across the whole domain, so zero-set points outside Bounds()
// would be found too.
template <int DIM>
std::vector<Vec<DIM>> ZeroSetPoints(const SignedDistanceFunction<DIM>& f, double domain, int lines,
  double step, std::uint64_t seed)
{
  Rng rng(seed);
  const Vec<DIM> lo = Vec<DIM>::Constant(-domain), hi = Vec<DIM>::Constant(domain);
  const double half = (hi - lo).norm();
  Vec<DIM> originLo = lo, originHi = hi;
  const BoundingBox<DIM> bounds = f.Bounds();
  if (!bounds.IsEmpty())
  {
    originLo = bounds.Min.cwiseMax(lo);
    originHi = bounds.Max.cwiseMin(hi);
  }
  const int steps = static_cast<int>(std::ceil(2 * half / step));
  std::vector<Vec<DIM>> points;
  for (int l = 0; l < lines; ++l)
  {
    const Vec<DIM> o = UniformPoint<DIM>(rng, originLo, originHi);
    const Vec<DIM> d = RandomDirection<DIM>(rng);
    double t0 = -half, f0 = f.Value(o + t0 * d);
    for (int i = 1; i <= steps; ++i)
    {
      const double t1 = -half + i * step, f1 = f.Value(o + t1 * d);
      if ((f0 < 0) != (f1 < 0))
      {
        double a = t0, b = t1;
        const bool negativeAtA = f0 < 0;
        for (int it = 0; it < 80 && b - a > 0; ++it)
        {
          const double m = 0.5 * (a + b);
          if (m <= a || m >= b)
          {
            break;
          }
          ((f.Value(o + m * d) < 0) == negativeAtA ? a : b) = m;
        }
        points.push_back(o + 0.5 * (a + b) * d);
      }
      t0 = t1;
      f0 = f1;
    }
  }
  return points;
}

// Properties every CSG result must have, whatever it combines: 1-Lipschitz,
// hence |φ| ≤ the distance to its zero set; bounds that hold the zero set;
// the chain-rule gradient; Sample() consistent with Value().
template <int DIM>
void CheckConservative(const SignedDistanceFunction<DIM>& f, const std::string& name, std::uint64_t seed)
{
  const double domain = 2.2;
  const std::vector<Vec<DIM>> zero =
    ZeroSetPoints<DIM>(f, domain, DIM == 2 ? 1000 : 2000, DIM == 2 ? 0.005 : 0.02, seed);
  ASSERT_GT(zero.size(), 300u) << name;

  double worstZero = 0;
  for (const Vec<DIM>& p : zero)
  {
    worstZero = std::max(worstZero, std::abs(f.Value(p)));
  }
  EXPECT_LE(worstZero, 1e-12) << name << ": bisection did not land on the zero set";

  const BoundingBox<DIM> bounds = f.Bounds();
  if (!bounds.IsEmpty())
  {
    int outsideBounds = 0;
    for (const Vec<DIM>& p : zero)
    {
      outsideBounds += ((p.array() >= bounds.Min.array() - 1e-9).all() &&
                         (p.array() <= bounds.Max.array() + 1e-9).all())
        ? 0
        : 1;
    }
    EXPECT_EQ(outsideBounds, 0) << name << ": zero-set points outside Bounds()";
  }

  Rng rng(seed + 1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::uniform_int_distribution<std::size_t> pick(0, zero.size() - 1);
  const Vec<DIM> lo = Vec<DIM>::Constant(-domain), hi = Vec<DIM>::Constant(domain);
  double worstExcess = -kInf, worstNorm = 0;
  int gradientErrors = 0, skipped = 0, sampleErrors = 0;
  const int queries = 2000;
  for (int q = 0; q < queries; ++q)
  {
    const Vec<DIM> x = (q % 2 == 0)
      ? UniformPoint<DIM>(rng, lo, hi)
      : Vec<DIM>(zero[pick(rng)] + 0.3 * u(rng) * RandomDirection<DIM>(rng));
    const double phi = f.Value(x);
    worstExcess = std::max(worstExcess, std::abs(phi) - NearestDistance<DIM>(zero, x));
    const Vec<DIM> g = f.Gradient(x);
    worstNorm = std::max(worstNorm, g.allFinite() ? g.norm() : kInf);
    gradientErrors += GradientAgrees<DIM>(f, x, skipped) ? 0 : 1;
    const ImplicitSample s = f.Sample(x);
    sampleErrors += (s.value == phi && s.part >= 0 && s.part < f.NumberOfParts()) ? 0 : 1;
  }
  EXPECT_LE(worstExcess, 1e-9) << name << ": |φ| exceeds the distance to the zero set";
  EXPECT_LE(worstNorm, 1 + 1e-12) << name << ": |∇φ| > 1";
  EXPECT_EQ(gradientErrors, 0) << name << ": gradient differs from central differences";
  EXPECT_LE(skipped, queries / 50) << name << ": too many points near kinks";
  EXPECT_EQ(sampleErrors, 0) << name;
  EXPECT_EQ(f.Lipschitz(), 1.0);
  CheckLipschitz<DIM>(f, lo, hi, seed + 2, name);
}

const char* OperationName(CsgOperation op)
{
  switch (op)
  {
    case CsgOperation::Union:
      return "union";
    case CsgOperation::Intersection:
      return "intersection";
    default:
      return "difference";
  }
}

// The reference blend in a different but equivalent form: with
// w = max(k − |a − b|, 0) / k, smin = min(a, b) − k w²/4 and
// smax = max(a, b) + k w²/4.
double ReferenceSmoothMin(double a, double b, double k)
{
  const double w = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - 0.25 * k * w * w;
}

double ReferenceSmoothMax(double a, double b, double k)
{
  const double w = std::max(k - std::abs(a - b), 0.0) / k;
  return std::max(a, b) + 0.25 * k * w * w;
}

// Value, sign and part against the primitives combined by hand.
template <int DIM>
void CheckAgainstReference(CsgOperation op, double k, std::uint64_t seed)
{
  const SphereAndBox<DIM> s;
  const CsgDistance<DIM> f(op, s.Sphere, s.Box, k);
  const std::string name =
    std::string(OperationName(op)) + (k > 0 ? " smooth " : " hard ") + std::to_string(DIM) + "D";
  Rng rng(seed);
  int valueErrors = 0, signErrors = 0, partErrors = 0, boundErrors = 0, partsSeen[2] = { 0, 0 };
  for (int i = 0; i < 4000; ++i)
  {
    const Vec<DIM> x = UniformPoint<DIM>(rng, Vec<DIM>::Constant(-2), Vec<DIM>::Constant(2));
    const double a = s.Sphere->Value(x);
    const double b = (op == CsgOperation::Difference ? -1.0 : 1.0) * s.Box->Value(x);
    const bool isUnion = op == CsgOperation::Union;
    const double hard = isUnion ? std::min(a, b) : std::max(a, b);
    const double reference = k == 0 ? hard : (isUnion ? ReferenceSmoothMin(a, b, k) : ReferenceSmoothMax(a, b, k));
    const double phi = f.Value(x);
    valueErrors += std::abs(phi - reference) <= 1e-12 ? 0 : 1;
    // A blend moves the value by at most k/4, towards the inside for a union.
    const double shift = phi - hard;
    boundErrors += (isUnion ? (shift <= 1e-15 && shift >= -0.25 * k - 1e-15)
                            : (shift >= -1e-15 && shift <= 0.25 * k + 1e-15))
      ? 0
      : 1;
    if (k == 0 && std::abs(phi) > 1e-9)
    {
      const bool inA = s.InSphere(x), inB = s.InBox(x);
      const bool member = op == CsgOperation::Union ? (inA || inB)
        : op == CsgOperation::Intersection        ? (inA && inB)
                                                  : (inA && !inB);
      signErrors += ((phi < 0) == member) ? 0 : 1;
    }
    // The child with the larger weight decides: a for min when a ≤ b, for
    // max when a ≥ b (ties skipped).
    if (std::abs(a - b) > 1e-12)
    {
      const bool decidedByA = isUnion ? a < b : a > b;
      const std::int64_t part = f.Sample(x).part;
      partErrors += (part == (decidedByA ? 0 : 1)) ? 0 : 1;
      partsSeen[part == 0 ? 0 : 1]++;
    }
  }
  EXPECT_EQ(valueErrors, 0) << name;
  EXPECT_EQ(boundErrors, 0) << name;
  EXPECT_EQ(signErrors, 0) << name;
  EXPECT_EQ(partErrors, 0) << name;
  EXPECT_GT(partsSeen[0], 100) << name;
  EXPECT_GT(partsSeen[1], 100) << name;
  EXPECT_EQ(f.NumberOfParts(), 2);
}

template <int DIM>
void CheckAllReferences(std::uint64_t seed)
{
  for (CsgOperation op : { CsgOperation::Union, CsgOperation::Intersection, CsgOperation::Difference })
  {
    for (double k : { 0.0, 0.3 })
    {
      CheckAgainstReference<DIM>(op, k, seed++);
    }
  }
}

TEST(CsgDistance, MatchesReferenceFormulas2D) { CheckAllReferences<2>(100); }
TEST(CsgDistance, MatchesReferenceFormulas3D) { CheckAllReferences<3>(200); }

template <int DIM>
void CheckConservativeTrees(std::uint64_t seed)
{
  const SphereAndBox<DIM> s;
  const SdfPointer<DIM> capsule =
    std::make_shared<CapsuleDistance<DIM>>(V<DIM>(-1.0, -0.6, 0.0), V<DIM>(1.0, 0.6, 0.2), 0.25);
  const SdfPointer<DIM> scaled = std::make_shared<ScaledSphere<DIM>>(V<DIM>(-0.2, 0.5, -0.1), 0.6);
  const SdfPointer<DIM> plane = std::make_shared<PlaneDistance<DIM>>(V<DIM>(0.0, 0.2, 0.0), V<DIM>(1.0, 2.0, -1.0));
  for (CsgOperation op : { CsgOperation::Union, CsgOperation::Intersection, CsgOperation::Difference })
  {
    for (double k : { 0.0, 0.3 })
    {
      const std::string suffix = std::string(" ") + OperationName(op) + (k > 0 ? " smooth" : " hard");
      CheckConservative<DIM>(*Csg<DIM>(op, s.Sphere, s.Box, k), "sphere/box" + suffix, seed++);
      CheckConservative<DIM>(*Csg<DIM>(op, scaled, s.Box, k), "scaled sphere/box" + suffix, seed++);
      CheckConservative<DIM>(*Csg<DIM>(op, s.Box, scaled, k), "box/scaled sphere" + suffix, seed++);
      // A tree: (sphere ∪~ box) op capsule.
      const SdfPointer<DIM> inner = Csg<DIM>(CsgOperation::Union, s.Sphere, s.Box, 0.2);
      CheckConservative<DIM>(*Csg<DIM>(op, inner, capsule, k), "tree" + suffix, seed++);
      CheckConservative<DIM>(*Csg<DIM>(op, capsule, inner, k), "tree reversed" + suffix, seed++);
      if (op != CsgOperation::Union)
      {
        CheckConservative<DIM>(*Csg<DIM>(op, s.Sphere, plane, k), "sphere/plane" + suffix, seed++);
      }
    }
  }
}

TEST(CsgDistance, ConservativeAndLipschitz2D) { CheckConservativeTrees<2>(1000); }
TEST(CsgDistance, ConservativeAndLipschitz3D) { CheckConservativeTrees<3>(2000); }

// Dividing by the child's Lipschitz constant makes the 3 × distance child
// count as a distance: the hard union with a box is then the exact distance
// to the union outside it, as with the true ball.
template <int DIM>
void CheckNormalization(std::uint64_t seed)
{
  const SphereAndBox<DIM> s;
  const SdfPointer<DIM> scaled = std::make_shared<ScaledSphere<DIM>>(s.SphereCenter, s.SphereRadius);
  Rng rng(seed);
  for (CsgOperation op : { CsgOperation::Union, CsgOperation::Intersection, CsgOperation::Difference })
  {
    for (double k : { 0.0, 0.3 })
    {
      const CsgDistance<DIM> withScaled(op, scaled, s.Box, k), withTrue(op, s.Sphere, s.Box, k);
      const CsgDistance<DIM> scaledSecond(op, s.Box, scaled, k), trueSecond(op, s.Box, s.Sphere, k);
      for (int i = 0; i < 500; ++i)
      {
        const Vec<DIM> x = UniformPoint<DIM>(rng, Vec<DIM>::Constant(-2), Vec<DIM>::Constant(2));
        EXPECT_NEAR(withScaled.Value(x), withTrue.Value(x), 1e-12) << OperationName(op);
        EXPECT_NEAR(scaledSecond.Value(x), trueSecond.Value(x), 1e-12) << OperationName(op);
        EXPECT_LE((withScaled.Gradient(x) - withTrue.Gradient(x)).norm(), 1e-12) << OperationName(op);
        EXPECT_LE((scaledSecond.Gradient(x) - trueSecond.Gradient(x)).norm(), 1e-12) << OperationName(op);
      }
    }
  }
}

TEST(CsgDistance, NormalizesChildLipschitz2D) { CheckNormalization<2>(3000); }
TEST(CsgDistance, NormalizesChildLipschitz3D) { CheckNormalization<3>(3001); }

// Outside both solids the hard union is the exact distance to the union:
// compare with the dense surface samples of both primitives.
template <int DIM>
void CheckHardUnionExactOutside(std::uint64_t seed)
{
  const SphereAndBox<DIM> s;
  const CsgDistance<DIM> f(CsgOperation::Union, s.Sphere, s.Box);
  SurfaceSamples<DIM> surface = SphereSurface<DIM>(s.SphereCenter, s.SphereRadius, Spacing<DIM>());
  const SurfaceSamples<DIM> box = BoxSurface<DIM>(s.BoxCenter, s.BoxHalf, Spacing<DIM>());
  surface.Points.insert(surface.Points.end(), box.Points.begin(), box.Points.end());
  surface.Resolution = std::max(surface.Resolution, box.Resolution);
  Rng rng(seed);
  int tested = 0;
  double worstAbove = -kInf, worstBelow = -kInf;
  for (int i = 0; i < 2000; ++i)
  {
    const Vec<DIM> x = UniformPoint<DIM>(rng, Vec<DIM>::Constant(-2), Vec<DIM>::Constant(2));
    if (s.InSphere(x) || s.InBox(x))
    {
      continue;
    }
    ++tested;
    const double phi = f.Value(x), sampled = NearestDistance<DIM>(surface.Points, x);
    worstAbove = std::max(worstAbove, phi - sampled);
    worstBelow = std::max(worstBelow, sampled - phi);
  }
  EXPECT_GT(tested, 1000);
  EXPECT_LE(worstAbove, 1e-9);
  EXPECT_LE(worstBelow, surface.Resolution + 1e-12);
}

TEST(CsgDistance, HardUnionIsExactOutside2D) { CheckHardUnionExactOutside<2>(4000); }
TEST(CsgDistance, HardUnionIsExactOutside3D) { CheckHardUnionExactOutside<3>(4001); }

// Each point lies closest to one face or cap of a known leaf, away from
// every blend: the part reported must be that leaf's number in the tree.
template <int DIM>
void CheckParts()
{
  const SdfPointer<DIM> sphere = std::make_shared<SphereDistance<DIM>>(V<DIM>(-1.2, 0.0, 0.0), 0.6);
  const SdfPointer<DIM> box = std::make_shared<BoxDistance<DIM>>(V<DIM>(1.0, 0.0, 0.0), V<DIM>(0.5, 0.4, 0.3));
  const SdfPointer<DIM> capsule =
    std::make_shared<CapsuleDistance<DIM>>(V<DIM>(0.0, -1.0, 0.0), V<DIM>(0.0, 1.0, 0.0), 0.2);
  for (double k : { 0.0, 0.1 })
  {
    const SdfPointer<DIM> pair = Csg<DIM>(CsgOperation::Union, sphere, box, k);
    const SdfPointer<DIM> tree = Csg<DIM>(CsgOperation::Union, pair, capsule, k);
    EXPECT_EQ(pair->NumberOfParts(), 2);
    EXPECT_EQ(tree->NumberOfParts(), 3);
    // Near the box's +x face, outside and inside.
    EXPECT_EQ(pair->Sample(V<DIM>(1.55, 0.1, 0.05)).part, 1) << k;
    EXPECT_EQ(pair->Sample(V<DIM>(1.45, 0.1, 0.05)).part, 1) << k;
    EXPECT_EQ(tree->Sample(V<DIM>(1.55, 0.1, 0.05)).part, 1) << k;
    EXPECT_EQ(tree->Sample(V<DIM>(-1.85, 0.0, 0.0)).part, 0) << k;
    EXPECT_EQ(tree->Sample(V<DIM>(0.25, 0.3, 0.0)).part, 2) << k;
    EXPECT_EQ(tree->Sample(V<DIM>(-0.1, -0.9, 0.0)).part, 2) << k;
    // The capsule first: the box becomes part 2.
    const SdfPointer<DIM> flipped = Csg<DIM>(CsgOperation::Union, capsule, pair, k);
    EXPECT_EQ(flipped->Sample(V<DIM>(1.55, 0.1, 0.05)).part, 2) << k;
    EXPECT_EQ(flipped->Sample(V<DIM>(0.25, 0.3, 0.0)).part, 0) << k;

    // A ball carved out of a corner of a box: points on the carved surface
    // report the ball (part 1), points near the remaining faces the box.
    const SdfPointer<DIM> cube = std::make_shared<BoxDistance<DIM>>(Vec<DIM>::Zero(), Vec<DIM>::Ones());
    const SdfPointer<DIM> corner = std::make_shared<SphereDistance<DIM>>(Vec<DIM>::Ones(), 0.8);
    const SdfPointer<DIM> carved = Csg<DIM>(CsgOperation::Difference, cube, corner, k);
    const Vec<DIM> nearCarve = Vec<DIM>::Ones() - 0.9 * Vec<DIM>::Ones().normalized();
    EXPECT_EQ(carved->Sample(nearCarve).part, 1) << k;
    EXPECT_LT(carved->Value(nearCarve), 0.0);
    EXPECT_EQ(carved->Sample(V<DIM>(-0.95, 0.0, 0.0)).part, 0) << k;
    // A carved point inside the ball is outside the difference.
    EXPECT_GT(carved->Value(Vec<DIM>::Constant(0.9)), 0.0);
  }
}

TEST(CsgDistance, PartReporting2D) { CheckParts<2>(); }
TEST(CsgDistance, PartReporting3D) { CheckParts<3>(); }

template <int DIM>
void ExpectBox(const BoundingBox<DIM>& box, const Vec<DIM>& lo, const Vec<DIM>& hi, const std::string& what)
{
  ASSERT_FALSE(box.IsEmpty()) << what;
  EXPECT_LE((box.Min - lo).cwiseAbs().maxCoeff(), 1e-15) << what;
  EXPECT_LE((box.Max - hi).cwiseAbs().maxCoeff(), 1e-15) << what;
}

template <int DIM>
void CheckBounds()
{
  const SphereAndBox<DIM> s;
  const BoundingBox<DIM> a = s.Sphere->Bounds(), b = s.Box->Bounds();
  const Vec<DIM> unionLo = a.Min.cwiseMin(b.Min), unionHi = a.Max.cwiseMax(b.Max);
  const Vec<DIM> interLo = a.Min.cwiseMax(b.Min), interHi = a.Max.cwiseMin(b.Max);
  ExpectBox<DIM>(Csg<DIM>(CsgOperation::Union, s.Sphere, s.Box)->Bounds(), unionLo, unionHi, "union");
  const Vec<DIM> margin = Vec<DIM>::Constant(0.1);
  ExpectBox<DIM>(Csg<DIM>(CsgOperation::Union, s.Sphere, s.Box, 0.4)->Bounds(), unionLo - margin,
    unionHi + margin, "smooth union");
  ExpectBox<DIM>(Csg<DIM>(CsgOperation::Intersection, s.Sphere, s.Box)->Bounds(), interLo, interHi,
    "intersection");
  ExpectBox<DIM>(Csg<DIM>(CsgOperation::Intersection, s.Sphere, s.Box, 0.4)->Bounds(), interLo, interHi,
    "smooth intersection");
  ExpectBox<DIM>(Csg<DIM>(CsgOperation::Difference, s.Sphere, s.Box, 0.4)->Bounds(), a.Min, a.Max,
    "difference");

  // Disjoint boxes: nothing in common.
  const SdfPointer<DIM> far = std::make_shared<SphereDistance<DIM>>(Vec<DIM>::Constant(5.0), 0.5);
  EXPECT_TRUE(Csg<DIM>(CsgOperation::Intersection, s.Sphere, far)->Bounds().IsEmpty());

  // Unbounded children.
  const SdfPointer<DIM> plane = std::make_shared<PlaneDistance<DIM>>(Vec<DIM>::Zero(), Vec<DIM>::Ones());
  EXPECT_TRUE(Csg<DIM>(CsgOperation::Union, s.Sphere, plane)->Bounds().IsEmpty());
  EXPECT_TRUE(Csg<DIM>(CsgOperation::Union, plane, s.Sphere, 0.2)->Bounds().IsEmpty());
  EXPECT_TRUE(Csg<DIM>(CsgOperation::Difference, plane, s.Sphere)->Bounds().IsEmpty());
  EXPECT_TRUE(Csg<DIM>(CsgOperation::Intersection, plane, plane)->Bounds().IsEmpty());
  ExpectBox<DIM>(Csg<DIM>(CsgOperation::Intersection, plane, s.Sphere)->Bounds(), a.Min, a.Max, "plane ∩ sphere");
  ExpectBox<DIM>(Csg<DIM>(CsgOperation::Intersection, s.Sphere, plane, 0.3)->Bounds(), a.Min, a.Max,
    "sphere ∩ plane");
  ExpectBox<DIM>(Csg<DIM>(CsgOperation::Difference, s.Sphere, plane)->Bounds(), a.Min, a.Max, "sphere − plane");
}

TEST(CsgDistance, Bounds2D) { CheckBounds<2>(); }
TEST(CsgDistance, Bounds3D) { CheckBounds<3>(); }

TEST(CsgDistance, ArgumentValidation)
{
  const SdfPointer<3> sphere = std::make_shared<SphereDistance<3>>(Vec3::Zero(), 1.0);
  const SdfPointer<3> none;
  for (CsgOperation op : { CsgOperation::Union, CsgOperation::Intersection, CsgOperation::Difference })
  {
    EXPECT_THROW(CsgDistance<3>(op, none, sphere), std::invalid_argument);
    EXPECT_THROW(CsgDistance<3>(op, sphere, none), std::invalid_argument);
    EXPECT_THROW(CsgDistance<3>(op, sphere, sphere, -0.1), std::invalid_argument);
    EXPECT_THROW(CsgDistance<3>(op, sphere, sphere, kNaN), std::invalid_argument);
    EXPECT_THROW(CsgDistance<3>(op, sphere, sphere, kInf), std::invalid_argument);
    EXPECT_NO_THROW(CsgDistance<3>(op, sphere, sphere, 0.0));
    EXPECT_NO_THROW(CsgDistance<3>(op, sphere, sphere, 0.5));
  }
  // A child must declare a usable Lipschitz bound.
  for (double l : { 0.0, -1.0, kInf, kNaN })
  {
    const SdfPointer<3> bad = std::make_shared<ScaledSphere<3>>(Vec3::Zero(), 1.0, l);
    EXPECT_THROW(CsgDistance<3>(CsgOperation::Union, bad, sphere), std::invalid_argument) << l;
    EXPECT_THROW(CsgDistance<3>(CsgOperation::Union, sphere, bad), std::invalid_argument) << l;
  }
}
} // namespace
