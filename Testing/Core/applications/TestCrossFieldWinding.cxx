// Tests of gridfree/applications/CrossFieldWinding.h: the winding search
// finds every zero of a noisy ψ with its winding, flat zeros of winding ±2
// included, and the boundary winding of polygons (Poincaré–Hopf).
#include <gridfree/applications/CrossFieldWinding.h>

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <random>
#include <vector>

using namespace gridfree;

namespace
{
using C = std::complex<double>;

struct Zero
{
  C At;
  int Winding; // ±1, ±2
};

// ψ = 8 Π (z − a)^w for w > 0 and conj(z − a)^|w| for w < 0, times 1 + z/4
// (no zero in the disk), its gradient by central differences, with Gaussian
// noise of standard deviation sigma on each part of ψ and of its gradient.
CrossFieldEvaluator Synthetic(std::vector<Zero> zeros, double sigma, std::uint32_t seed)
{
  auto rng = std::make_shared<std::mt19937_64>(seed);
  return [zeros, sigma, rng](const std::vector<Vec2>& points, std::vector<CrossFieldSample>& out) {
    std::normal_distribution<double> noise(0.0, sigma);
    auto exact = [&zeros](const C& z) {
      C psi = 8.0 + 2.0 * z;
      for (const Zero& a : zeros)
      {
        const C d = a.Winding > 0 ? z - a.At : std::conj(z - a.At);
        for (int k = 0; k < std::abs(a.Winding); ++k)
        {
          psi *= d;
        }
      }
      return psi;
    };
    out.resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      const C z(points[i].x(), points[i].y());
      const double h = 1e-6;
      const C dx = (exact(z + h) - exact(z - h)) / (2.0 * h);
      const C dy = (exact(z + C(0.0, h)) - exact(z - C(0.0, h))) / (2.0 * h);
      out[i].Psi = exact(z) + C(noise(*rng), noise(*rng));
      out[i].GradRe = Vec2(dx.real() + noise(*rng), dy.real() + noise(*rng));
      out[i].GradIm = Vec2(dx.imag() + noise(*rng), dy.imag() + noise(*rng));
      out[i].PsiVariance = 2.0 * sigma * sigma;
      out[i].BoundaryDistance = 1.0 - std::abs(z);
      out[i].Valid = std::abs(z) < 1.0;
    }
    return true;
  };
}

const std::function<bool(const Vec2&)> InDisk = [](const Vec2& p) { return p.norm() < 1.0; };
} // namespace

TEST(CrossFieldWinding, FindsEveryZeroWithItsWinding)
{
  const std::vector<Zero> zeros = { { C(0.3, 0.2), 1 }, { C(-0.35, 0.1), -1 }, { C(0.05, -0.45), -2 },
    { C(-0.2, 0.5), 2 } };
  for (double sigma : { 0.0, 1e-3 })
  {
    WindingSearchStatistics stats;
    const auto found = FindSingularitiesByWinding(
      Synthetic(zeros, sigma, 3), InDisk, Vec2(-1, -1), Vec2(1, 1), {}, &stats);
    ASSERT_FALSE(stats.Aborted);
    EXPECT_EQ(stats.OuterWinding, 0) << sigma; // 1 − 1 − 2 + 2
    ASSERT_EQ(found.size(), zeros.size()) << "noise " << sigma;
    for (const Zero& z : zeros)
    {
      int matches = 0;
      for (const Singularity& s : found)
      {
        if ((s.Position - Vec2(z.At.real(), z.At.imag())).norm() < s.Radius + 0.05 &&
          s.Index == z.Winding)
        {
          ++matches;
        }
      }
      EXPECT_EQ(matches, 1) << "zero at " << z.At << " noise " << sigma;
    }
  }
}

TEST(CrossFieldWinding, NoiseMergesZerosButKeepsTheirSum)
{
  // At a noise of 0.01, |ψ| between the +2 and −1 zeros is below 3σ: they
  // are found as one region of winding +1, and the sum still holds.
  const std::vector<Zero> zeros = { { C(0.3, 0.2), 1 }, { C(-0.35, 0.1), -1 }, { C(0.05, -0.45), -2 },
    { C(-0.2, 0.5), 2 } };
  WindingSearchStatistics stats;
  const auto found = FindSingularitiesByWinding(
    Synthetic(zeros, 1e-2, 3), InDisk, Vec2(-1, -1), Vec2(1, 1), {}, &stats);
  int sum = 0;
  for (const Singularity& s : found)
  {
    EXPECT_NE(s.Index, 0);
    sum += s.Index;
  }
  EXPECT_EQ(sum, 0);
  EXPECT_EQ(stats.OuterWinding, 0);
  EXPECT_GE(found.size(), 2u);
}

TEST(CrossFieldWinding, AFlatZeroOfWindingMinusTwoIsNotMissed)
{
  // |ψ| ~ r² near the centre: flat, and under the noise over a wide disk.
  const std::vector<Zero> zeros = { { C(0.0, 0.0), -2 } };
  const auto found = FindSingularitiesByWinding(
    Synthetic(zeros, 2e-3, 5), InDisk, Vec2(-1, -1), Vec2(1, 1));
  int sum = 0;
  for (const Singularity& s : found)
  {
    sum += s.Index;
    EXPECT_LT(s.Position.norm(), 0.15);
  }
  EXPECT_EQ(sum, -2);
}

TEST(CrossFieldWinding, NoZeroNoSingularity)
{
  const auto found =
    FindSingularitiesByWinding(Synthetic({}, 1e-2, 7), InDisk, Vec2(-1, -1), Vec2(1, 1));
  EXPECT_TRUE(found.empty());
}

TEST(CrossFieldWinding, BoundaryWindingOfPolygons)
{
  auto regular = [](int n, bool clockwise) {
    std::vector<Vec2> v;
    for (int k = 0; k < n; ++k)
    {
      const double a = (clockwise ? -1.0 : 1.0) * 2.0 * M_PI * k / n;
      v.emplace_back(std::cos(a), std::sin(a));
    }
    return v;
  };
  // Σ wrap(4α) / 2π with α = 2π/n: triangle +1, square 0, pentagon −1,
  // hexagon −2, and a finely sampled circle +4 (index sum 1 = χ(disk)).
  EXPECT_EQ(BoundaryWindingOfPolygon(regular(3, false)), 1);
  EXPECT_EQ(BoundaryWindingOfPolygon(regular(4, false)), 0);
  EXPECT_EQ(BoundaryWindingOfPolygon(regular(5, true)), -1);
  EXPECT_EQ(BoundaryWindingOfPolygon(regular(6, false)), -2);
  EXPECT_EQ(BoundaryWindingOfPolygon(regular(6, true)), -2);
  EXPECT_EQ(BoundaryWindingOfPolygon(regular(512, false)), 4);
  bool ambiguous = false;
  BoundaryWindingOfPolygon(regular(8, false), &ambiguous);
  EXPECT_TRUE(ambiguous); // 45° turns: ψ vanishes at the corners
  // An annulus of two fine circles: +4 outside, −4 around the hole (the
  // domain on the left: clockwise), χ = 0.
  std::vector<Vec2> hole = regular(512, true);
  for (Vec2& v : hole)
  {
    v *= 0.5;
  }
  EXPECT_EQ(BoundaryWinding({ regular(512, false), hole }), 0);
  // An L shape: five 90° turns and one −90° turn: 0.
  EXPECT_EQ(BoundaryWindingOfPolygon({ Vec2(0, 0), Vec2(2, 0), Vec2(2, 1), Vec2(1, 1), Vec2(1, 2),
              Vec2(0, 2) }),
    0);
}
