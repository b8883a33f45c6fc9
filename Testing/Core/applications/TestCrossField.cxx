#include <gridfree/applications/CrossField.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdint>
#include <cstring>
#include <functional>
#include <random>
#include <vector>

using gridfree::CrossDirections;
using gridfree::CrossFieldEvaluator;
using gridfree::CrossFieldSample;
using gridfree::EncodeNormalFourth;
using gridfree::FindSingularities;
using gridfree::Separatrix;
using gridfree::SeparatrixSettings;
using gridfree::SeparatrixStatistics;
using gridfree::SeparatrixStop;
using gridfree::Singularity;
using gridfree::SingularitySearchStatistics;
using gridfree::SingularitySettings;
using gridfree::TraceSeparatrices;
using gridfree::Vec2;

namespace
{
using Complex = std::complex<double>;

// ψ and its partial derivatives ∂xψ, ∂yψ at z.
struct Jet
{
  Complex Psi, Dx, Dy;
};
using Field = std::function<Jet(Complex)>;

// Holomorphic ψ: ∂x = ψ', ∂y = iψ'.
Jet Holomorphic(Complex psi, Complex derivative)
{
  return { psi, derivative, Complex(0, 1) * derivative };
}

// Π (z − a_k): a simple zero of winding 1 at each a_k.
Field Product(std::vector<Complex> zeros, Complex factor = 1.0)
{
  return [zeros, factor](Complex z) {
    Complex psi = factor, derivative = 0.0;
    for (std::size_t k = 0; k < zeros.size(); ++k)
    {
      Complex others = factor;
      for (std::size_t j = 0; j < zeros.size(); ++j)
      {
        if (j != k)
        {
          others *= z - zeros[j];
        }
      }
      psi *= z - zeros[k];
      derivative += others;
    }
    return Holomorphic(psi, derivative);
  };
}

std::uint64_t Bits(double v)
{
  std::uint64_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

// The unit disk with ψ given analytically; optionally Gaussian noise of
// standard deviation `psiNoise` (total over Re and Im) on ψ and `gradientNoise`
// per gradient component, drawn from a generator seeded by a hash of the
// point so that every run, and every evaluation of the same point, agrees.
struct DiskEvaluator
{
  Field F;
  double PsiNoise = 0.0;
  double GradientNoise = 0.0;
  std::size_t Calls = 0;
  std::size_t Points = 0;
  bool Fail = false;

  CrossFieldEvaluator Function()
  {
    return [this](const std::vector<Vec2>& points, std::vector<CrossFieldSample>& out) {
      ++this->Calls;
      this->Points += points.size();
      if (this->Fail)
      {
        return false;
      }
      out.resize(points.size());
      for (std::size_t i = 0; i < points.size(); ++i)
      {
        out[i] = this->Sample(points[i]);
      }
      return true;
    };
  }

  CrossFieldSample Sample(const Vec2& p) const
  {
    CrossFieldSample s;
    const Complex z(p.x(), p.y());
    if (!(std::abs(z) < 1.0))
    {
      s.Valid = false;
      s.BoundaryDistance = 1.0 - std::abs(z);
      return s;
    }
    const Jet jet = this->F(z);
    s.Psi = jet.Psi;
    s.GradRe = Vec2(jet.Dx.real(), jet.Dy.real());
    s.GradIm = Vec2(jet.Dx.imag(), jet.Dy.imag());
    s.BoundaryDistance = 1.0 - std::abs(z);
    if (this->PsiNoise > 0.0 || this->GradientNoise > 0.0)
    {
      std::uint64_t h = 0x9e3779b97f4a7c15ull;
      for (std::uint64_t v : { Bits(p.x()), Bits(p.y()) })
      {
        h = (h ^ v) * 0x100000001b3ull;
        h ^= h >> 29;
      }
      std::mt19937_64 rng(h);
      std::normal_distribution<double> normal(0.0, 1.0);
      const double perComponent = this->PsiNoise / std::sqrt(2.0);
      s.Psi += Complex(perComponent * normal(rng), perComponent * normal(rng));
      for (int a = 0; a < 2; ++a)
      {
        s.GradRe[a] += this->GradientNoise * normal(rng);
        s.GradIm[a] += this->GradientNoise * normal(rng);
      }
      s.PsiVariance = this->PsiNoise * this->PsiNoise;
    }
    return s;
  }
};

// Seeds on a square grid of spacing h inside the disk of radius `radius`.
std::vector<Vec2> GridSeeds(double h, double radius)
{
  std::vector<Vec2> seeds;
  const int n = static_cast<int>(std::ceil(radius / h));
  for (int j = -n; j <= n; ++j)
  {
    for (int i = -n; i <= n; ++i)
    {
      const Vec2 p(i * h + 0.013, j * h - 0.007);
      if (p.norm() < radius)
      {
        seeds.push_back(p);
      }
    }
  }
  return seeds;
}

// The singularity nearest to p, or null.
const Singularity* Nearest(const std::vector<Singularity>& found, const Vec2& p)
{
  const Singularity* best = nullptr;
  for (const Singularity& s : found)
  {
    if (!best || (s.Position - p).norm() < (best->Position - p).norm())
    {
      best = &s;
    }
  }
  return best;
}

// Angle between unit u and the nearest direction of the cross of ψ.
double CrossMisalignment(Complex psi, const Vec2& u)
{
  std::array<Vec2, 4> directions;
  if (!CrossDirections(psi, directions))
  {
    return M_PI;
  }
  double best = -1.0;
  for (const Vec2& d : directions)
  {
    best = std::max(best, d.dot(u.normalized()));
  }
  return std::acos(std::min(1.0, best));
}

// Checks every separatrix: it starts at its source, its first direction is
// radial-aligned with the cross, every segment follows the cross, and it ends
// at the boundary or exactly at another singularity's position.
void CheckSeparatrices(const std::vector<Separatrix>& curves, const std::vector<Singularity>& found,
  const DiskEvaluator& exact, const SeparatrixSettings& settings, double directionTolerance,
  double segmentTolerance)
{
  for (const Separatrix& c : curves)
  {
    ASSERT_GE(c.Source, 0);
    ASSERT_GE(c.Points.size(), 3u);
    EXPECT_EQ(c.Points.front(), found[c.Source].Position);
    const Vec2 radial = c.Points[1] - c.Points[0];
    EXPECT_LT(CrossMisalignment(exact.Sample(c.Points[1]).Psi, radial), directionTolerance);
    // The first step continues outward along the radial direction.
    EXPECT_GT((c.Points[2] - c.Points[1]).normalized().dot(radial.normalized()), 0.9);
    const std::size_t last = c.Reason == SeparatrixStop::Singularity ? c.Points.size() - 2 : c.Points.size() - 1;
    for (std::size_t k = 1; k < last; ++k)
    {
      const Vec2 mid = 0.5 * (c.Points[k] + c.Points[k + 1]);
      EXPECT_LT(CrossMisalignment(exact.Sample(mid).Psi, c.Points[k + 1] - c.Points[k]), segmentTolerance)
        << "segment " << k << " of a curve from " << c.Source;
    }
    if (c.Reason == SeparatrixStop::Boundary)
    {
      EXPECT_EQ(c.Target, -1);
      EXPECT_GE(c.Points.back().norm(), 1.0 - settings.StopDistance - 1e-12);
      EXPECT_LT(c.Points.back().norm(), 1.0);
    }
    else
    {
      ASSERT_EQ(c.Reason, SeparatrixStop::Singularity);
      ASSERT_GE(c.Target, 0);
      EXPECT_EQ(c.Points.back(), found[c.Target].Position);
    }
  }
}
} // namespace

TEST(CrossField, EncodeNormalFourth)
{
  EXPECT_NEAR(std::abs(EncodeNormalFourth(Vec2(1, 0)) - 1.0), 0.0, 1e-15);
  EXPECT_NEAR(std::abs(EncodeNormalFourth(Vec2(0, 3)) - 1.0), 0.0, 1e-15);
  EXPECT_NEAR(std::abs(EncodeNormalFourth(Vec2(2, 2)) + 1.0), 0.0, 1e-15);
  const double angle = 0.3;
  EXPECT_NEAR(std::abs(EncodeNormalFourth(Vec2(5 * std::cos(angle), 5 * std::sin(angle))) -
                std::polar(1.0, 4 * angle)),
    0.0, 1e-14);
  EXPECT_EQ(EncodeNormalFourth(Vec2::Zero()), Complex(0.0));
  EXPECT_EQ(EncodeNormalFourth(Vec2(std::nan(""), 1.0)), Complex(0.0));
}

TEST(CrossField, CrossDirections)
{
  std::array<Vec2, 4> d;
  ASSERT_TRUE(CrossDirections(2.0, d));
  EXPECT_NEAR((d[0] - Vec2(1, 0)).norm(), 0.0, 1e-15);
  EXPECT_NEAR((d[1] - Vec2(0, 1)).norm(), 0.0, 1e-15);
  EXPECT_NEAR((d[2] - Vec2(-1, 0)).norm(), 0.0, 1e-15);
  EXPECT_NEAR((d[3] - Vec2(0, -1)).norm(), 0.0, 1e-15);
  ASSERT_TRUE(CrossDirections(-1.0, d));
  EXPECT_NEAR(std::abs(d[0].x()), std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(std::abs(d[0].y()), std::sqrt(0.5), 1e-15);
  // The cross encoded by ν⁴ contains ν and its perpendicular, whatever ν.
  for (double angle : { -2.5, -0.4, 0.1, 1.3, 3.0 })
  {
    const Vec2 normal(std::cos(angle), std::sin(angle));
    ASSERT_TRUE(CrossDirections(0.7 * EncodeNormalFourth(normal), d));
    EXPECT_LT(CrossMisalignment(EncodeNormalFourth(normal), normal), 1e-7);
    EXPECT_LT(CrossMisalignment(EncodeNormalFourth(normal), Vec2(-normal.y(), normal.x())), 1e-7);
    for (const Vec2& v : d)
    {
      EXPECT_NEAR(v.norm(), 1.0, 1e-15);
    }
  }
  EXPECT_FALSE(CrossDirections(0.0, d));
  EXPECT_EQ(d[2], Vec2::Zero());
  EXPECT_FALSE(CrossDirections(Complex(std::nan(""), 0.0), d));
  EXPECT_FALSE(CrossDirections(Complex(INFINITY, 0.0), d));

  // The aligned direction is the cross direction nearest the tangent.
  Vec2 aligned;
  ASSERT_TRUE(gridfree::AlignedCrossDirection(1.0, Vec2(-0.2, -1.0), aligned));
  EXPECT_NEAR((aligned - Vec2(0, -1)).norm(), 0.0, 1e-15);
  ASSERT_TRUE(gridfree::AlignedCrossDirection(std::polar(1.0, 0.8), Vec2(-1.0, 0.1), aligned));
  EXPECT_NEAR((aligned - Vec2(-std::cos(0.2), -std::sin(0.2))).norm(), 0.0, 1e-14);
  EXPECT_FALSE(gridfree::AlignedCrossDirection(0.0, Vec2(1, 0), aligned));
}

// Noise can make arg ψ − 4θ cross a multiple of 2π several times near one
// separatrix direction; each direction is still reported once.
TEST(CrossFieldSeparatrices, NoisyStartCircleGivesOneDirectionPerCrossing)
{
  std::vector<double> theta;
  std::vector<Complex> psi;
  for (int j = 0; j < 64; ++j)
  {
    theta.push_back(2 * M_PI * j / 64);
    // Winding −3 relative to 4θ (a simple zero) plus an alternating wiggle
    // larger than half the change between samples.
    const double g = 1.0 - 3.0 * theta.back() + 0.2 * (j % 2 == 0 ? 1 : -1);
    psi.push_back(std::polar(0.5, 4.0 * theta.back() + g));
  }
  const std::vector<double> angles = gridfree::detail::SeparatrixAngles(theta, psi);
  ASSERT_EQ(angles.size(), 3u);
  for (int m = 0; m < 3; ++m)
  {
    const double expected = (1.0 + 2 * M_PI * m) / 3.0;
    EXPECT_LT(std::abs(angles[m] - expected), 2 * M_PI / 64) << m;
  }
  // No winding relative to 4θ (a zero of winding 4): no direction.
  for (int j = 0; j < 64; ++j)
  {
    psi[j] = std::polar(1.0, 4.0 * theta[j] + 0.5);
  }
  EXPECT_TRUE(gridfree::detail::SeparatrixAngles(theta, psi).empty());
}

// The disk's own cross field: ψ = z⁴ is harmonic with boundary values ν⁴.
// One singularity of winding 4 (index +1) and no separatrix.
TEST(CrossFieldSingularities, DiskFieldHasOneIndexFourZero)
{
  DiskEvaluator disk{ [](Complex z) { return Holomorphic(z * z * z * z, 4.0 * z * z * z); } };
  const std::vector<Vec2> seeds = GridSeeds(0.1, 0.9);
  SingularitySettings settings;
  SingularitySearchStatistics stats;
  const std::vector<Singularity> found = FindSingularities(disk.Function(), seeds, settings, &stats);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_LT(found[0].Position.norm(), 1e-4);
  EXPECT_EQ(found[0].Index, 4);
  EXPECT_EQ(found[0].PhaseWinding, 4);
  EXPECT_LT(std::abs(found[0].IndexResidual), 1e-9);
  EXPECT_LT(std::abs(found[0].IndexImaginary), 1e-9);
  EXPECT_EQ(found[0].SeedCount, static_cast<int>(seeds.size()));
  EXPECT_NEAR(found[0].Radius, settings.IndexRadius, 1e-12);
  EXPECT_EQ(found[0].IndexSampleCount, settings.IndexSamples);
  // Batching: one call for the seeds, one per iteration, one for the index
  // circles, whatever the number of seeds.
  EXPECT_EQ(stats.EvaluatorCalls, disk.Calls);
  EXPECT_EQ(disk.Calls, static_cast<std::size_t>(stats.Iterations) + 2);
  EXPECT_LT(stats.Iterations, settings.MaxIterations);
  EXPECT_EQ(stats.SeedsMaxIterations, 0);
  EXPECT_FALSE(stats.Aborted);

  disk.Calls = 0;
  EXPECT_TRUE(TraceSeparatrices(disk.Function(), found).empty());
  EXPECT_EQ(disk.Calls, 0u);
}

// Four simple zeros: windings 1 summing to 4 as on the disk, three
// separatrices each, ending at the boundary or at another zero.
TEST(CrossFieldSingularities, FourSimpleZeros)
{
  const std::vector<Complex> zeros = { { 0.4, 0.1 }, { -0.3, 0.35 }, { -0.2, -0.45 }, { 0.35, -0.4 } };
  DiskEvaluator disk{ Product(zeros) };
  const std::vector<Vec2> seeds = GridSeeds(0.1, 0.9);
  SingularitySearchStatistics stats;
  const std::vector<Singularity> found = FindSingularities(disk.Function(), seeds, {}, &stats);
  ASSERT_EQ(found.size(), 4u);
  int sum = 0, seedSum = 0;
  for (const Complex& a : zeros)
  {
    const Singularity* s = Nearest(found, Vec2(a.real(), a.imag()));
    ASSERT_NE(s, nullptr);
    EXPECT_LT((s->Position - Vec2(a.real(), a.imag())).norm(), 1e-5);
    EXPECT_EQ(s->Index, 1);
    EXPECT_EQ(s->PhaseWinding, 1);
    EXPECT_LT(std::abs(s->IndexResidual), 1e-6);
    EXPECT_LT(s->PsiMagnitude, 1e-5);
    sum += s->Index;
    seedSum += s->SeedCount;
  }
  EXPECT_EQ(sum, 4);
  // Nearly every seed ends in one of the zeros.
  EXPECT_GT(seedSum, static_cast<int>(0.95 * seeds.size()));
  EXPECT_EQ(disk.Calls, static_cast<std::size_t>(stats.Iterations) + 2);

  disk.Calls = 0;
  SeparatrixSettings settings;
  SeparatrixStatistics traceStats;
  const std::vector<Separatrix> curves = TraceSeparatrices(disk.Function(), found, settings, &traceStats);
  ASSERT_EQ(curves.size(), 12u);
  std::vector<int> perSource(4, 0);
  for (const Separatrix& c : curves)
  {
    ++perSource[c.Source];
  }
  EXPECT_EQ(perSource, std::vector<int>(4, 3));
  CheckSeparatrices(curves, found, disk, settings, 0.01, 0.01);
  // One call for the start circles, then two per step for all curves.
  EXPECT_EQ(disk.Calls, traceStats.EvaluatorCalls);
  EXPECT_LE(disk.Calls, 2u * traceStats.Steps + 3u);
  EXPECT_LT(traceStats.Steps, 400);
  EXPECT_FALSE(traceStats.Aborted);
}

// ψ = c (z − a) and ψ = conj(z − a): the separatrices are straight rays at the
// angles θ with arg ψ ≡ 4θ, three for winding 1 and five for winding −1.
TEST(CrossFieldSeparatrices, RaysOfLinearFields)
{
  const Complex a(0.1, -0.2);
  struct Case
  {
    Field F;
    int Winding;
    std::vector<double> Angles;
  };
  const Complex c = std::polar(1.0, 0.7);
  std::vector<Case> cases;
  cases.push_back({ [a, c](Complex z) { return Holomorphic(c * (z - a), c); }, 1, {} });
  for (int k = 0; k < 3; ++k)
  {
    cases.back().Angles.push_back((0.7 + 2 * M_PI * k) / 3);
  }
  cases.push_back(
    { [a](Complex z) { return Jet{ std::conj(z - a), 1.0, Complex(0, -1) }; }, -1, {} });
  for (int k = 0; k < 5; ++k)
  {
    cases.back().Angles.push_back(2 * M_PI * k / 5);
  }
  for (const Case& test : cases)
  {
    DiskEvaluator disk{ test.F };
    const std::vector<Singularity> found = FindSingularities(disk.Function(), GridSeeds(0.15, 0.9));
    ASSERT_EQ(found.size(), 1u);
    EXPECT_EQ(found[0].Index, test.Winding);
    EXPECT_LT(std::abs(found[0].IndexResidual), 1e-9);
    const Vec2 centre(a.real(), a.imag());
    EXPECT_LT((found[0].Position - centre).norm(), 1e-5);

    SeparatrixSettings settings;
    const std::vector<Separatrix> curves = TraceSeparatrices(disk.Function(), found, settings);
    ASSERT_EQ(curves.size(), static_cast<std::size_t>(4 - test.Winding));
    CheckSeparatrices(curves, found, disk, settings, 1e-6, 1e-6);
    std::vector<int> used(test.Angles.size(), 0);
    for (const Separatrix& curve : curves)
    {
      EXPECT_EQ(curve.Reason, SeparatrixStop::Boundary);
      // The curve's angle is one of the expected ones, and every point lies
      // on that ray.
      int match = -1;
      for (std::size_t k = 0; k < test.Angles.size(); ++k)
      {
        if (std::abs(gridfree::detail::WrapAngle(curve.StartAngle - test.Angles[k])) < 1e-6)
        {
          match = static_cast<int>(k);
        }
      }
      ASSERT_GE(match, 0) << "unexpected angle " << curve.StartAngle;
      ++used[match];
      const Vec2 ray(std::cos(test.Angles[match]), std::sin(test.Angles[match]));
      for (const Vec2& p : curve.Points)
      {
        const Vec2 offset = p - found[0].Position;
        EXPECT_GE(offset.dot(ray), -1e-12);
        EXPECT_LT(std::abs(offset.x() * ray.y() - offset.y() * ray.x()), 1e-6);
      }
    }
    EXPECT_EQ(used, std::vector<int>(test.Angles.size(), 1));
  }
}

// ψ = −(z − a)(z − b) with a, b on the real axis: ψ > 0 on the segment
// between them, so the segment is a separatrix joining the two zeros, found
// from both ends; the other four separatrices reach the boundary.
TEST(CrossFieldSeparatrices, SaddleConnectionEndsAtTheOtherSingularity)
{
  DiskEvaluator disk{ Product({ { -0.3, 0.0 }, { 0.3, 0.0 } }, -1.0) };
  const std::vector<Singularity> found = FindSingularities(disk.Function(), GridSeeds(0.1, 0.9));
  ASSERT_EQ(found.size(), 2u);
  SeparatrixSettings settings;
  const std::vector<Separatrix> curves = TraceSeparatrices(disk.Function(), found, settings);
  ASSERT_EQ(curves.size(), 6u);
  CheckSeparatrices(curves, found, disk, settings, 0.01, 0.01);
  int connections = 0;
  for (const Separatrix& c : curves)
  {
    if (c.Reason == SeparatrixStop::Singularity)
    {
      ++connections;
      EXPECT_NE(c.Target, c.Source);
      EXPECT_NEAR(c.Length, 0.6, 1e-3);
      for (const Vec2& p : c.Points)
      {
        EXPECT_LT(std::abs(p.y()), 1e-6);
      }
    }
    else
    {
      EXPECT_EQ(c.Reason, SeparatrixStop::Boundary);
    }
  }
  EXPECT_EQ(connections, 2);
}

// ψ ≡ 1 has no zero; ψ = 0.2 + |z|² has a minimum of |ψ| that is not a zero.
TEST(CrossFieldSingularities, NoZerosMeansNoSingularities)
{
  DiskEvaluator constant{ [](Complex) { return Jet{ 1.0, 0.0, 0.0 }; } };
  SingularitySearchStatistics stats;
  EXPECT_TRUE(FindSingularities(constant.Function(), GridSeeds(0.1, 0.9), {}, &stats).empty());
  EXPECT_EQ(constant.Calls, 1u); // zero gradient everywhere: no descent step
  EXPECT_EQ(stats.SeedsStalled, static_cast<int>(GridSeeds(0.1, 0.9).size()));

  DiskEvaluator bowl{ [](Complex z) {
    return Jet{ 0.2 + std::norm(z), 2.0 * z.real(), 2.0 * z.imag() };
  } };
  EXPECT_TRUE(FindSingularities(bowl.Function(), GridSeeds(0.1, 0.9), {}, &stats).empty());
  EXPECT_GT(stats.SeedsNotZero, 0);
  EXPECT_GT(stats.SeedsStalled, 0);
  EXPECT_TRUE(TraceSeparatrices(bowl.Function(), {}).empty());
}

TEST(CrossFieldSingularities, InvalidSeedsAndFailingEvaluator)
{
  DiskEvaluator disk{ Product({ { 0.2, 0.1 } }) };
  std::vector<Vec2> seeds = { Vec2(0.5, 0.5), Vec2(2.0, 0.0), Vec2(std::nan(""), 0.0), Vec2(-0.4, 0.1) };
  SingularitySearchStatistics stats;
  const std::vector<Singularity> found = FindSingularities(disk.Function(), seeds, {}, &stats);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].SeedCount, 2);
  EXPECT_EQ(stats.SeedsInvalid, 2);

  disk.Fail = true;
  EXPECT_TRUE(FindSingularities(disk.Function(), seeds, {}, &stats).empty());
  EXPECT_TRUE(stats.Aborted);
  SeparatrixStatistics traceStats;
  EXPECT_TRUE(TraceSeparatrices(disk.Function(), found, {}, &traceStats).empty());
  EXPECT_TRUE(traceStats.Aborted);
}

TEST(CrossFieldSingularities, Deterministic)
{
  DiskEvaluator disk{ Product({ { 0.4, 0.1 }, { -0.3, 0.35 }, { -0.2, -0.45 }, { 0.35, -0.4 } }) };
  disk.PsiNoise = 0.003;
  disk.GradientNoise = 0.03;
  const auto first = FindSingularities(disk.Function(), GridSeeds(0.1, 0.9));
  const auto second = FindSingularities(disk.Function(), GridSeeds(0.1, 0.9));
  ASSERT_EQ(first.size(), second.size());
  for (std::size_t i = 0; i < first.size(); ++i)
  {
    EXPECT_EQ(first[i].Position, second[i].Position);
    EXPECT_EQ(first[i].IndexResidual, second[i].IndexResidual);
  }
}

// Monte Carlo noise on ψ and its gradient: the indices and their sum stay
// exact, positions move by a few noise-floor radii σ/|ψ'(a)|, and the
// separatrices keep their number and their ends.
TEST(CrossFieldNoise, FourSimpleZerosWithNoise)
{
  const std::vector<Complex> zeros = { { 0.4, 0.1 }, { -0.3, 0.35 }, { -0.2, -0.45 }, { 0.35, -0.4 } };
  for (double sigma : { 0.001, 0.002, 0.003 })
  {
    SCOPED_TRACE(sigma);
    DiskEvaluator disk{ Product(zeros) };
    disk.PsiNoise = sigma;
    disk.GradientNoise = 10 * sigma;
    SingularitySettings settings;
    settings.MergeRadius = 0.1;
    settings.IndexRadius = 0.15;
    SingularitySearchStatistics stats;
    const std::vector<Singularity> found =
      FindSingularities(disk.Function(), GridSeeds(0.1, 0.9), settings, &stats);
    ASSERT_EQ(found.size(), 4u);
    int sum = 0;
    for (std::size_t k = 0; k < zeros.size(); ++k)
    {
      const Vec2 a(zeros[k].real(), zeros[k].imag());
      double slope = 1.0;
      for (std::size_t j = 0; j < zeros.size(); ++j)
      {
        if (j != k)
        {
          slope *= std::abs(zeros[k] - zeros[j]);
        }
      }
      const Singularity* s = Nearest(found, a);
      ASSERT_NE(s, nullptr);
      EXPECT_LT((s->Position - a).norm(), 3.0 * sigma / slope);
      EXPECT_EQ(s->Index, 1);
      EXPECT_LT(std::abs(s->IndexResidual), 0.1);
      sum += s->Index;
    }
    EXPECT_EQ(sum, 4);
    EXPECT_EQ(disk.Calls, static_cast<std::size_t>(stats.Iterations) + 2);

    SeparatrixSettings traceSettings;
    const std::vector<Separatrix> curves = TraceSeparatrices(disk.Function(), found, traceSettings);
    ASSERT_EQ(curves.size(), 12u);
    DiskEvaluator exact{ Product(zeros) };
    CheckSeparatrices(curves, found, exact, traceSettings, 0.1, 0.25);
  }
}

// A zero of order 4 under noise: |ψ| = r⁴ is below the noise floor over a
// wide disk, so seeds stop far apart; with a merge radius and an index circle
// larger than that disk it is still one singularity of winding 4.
TEST(CrossFieldNoise, DiskFieldWithNoise)
{
  DiskEvaluator disk{ [](Complex z) { return Holomorphic(z * z * z * z, 4.0 * z * z * z); } };
  disk.PsiNoise = 1e-4;
  disk.GradientNoise = 1e-3;
  SingularitySettings settings;
  settings.MergeRadius = 0.3;
  settings.IndexRadius = 0.4;
  const std::vector<Singularity> found = FindSingularities(disk.Function(), GridSeeds(0.1, 0.9), settings);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].Index, 4);
  EXPECT_LT(std::abs(found[0].IndexResidual), 0.05);
  EXPECT_LT(found[0].Position.norm(), std::pow(3e-4, 0.25));
}
