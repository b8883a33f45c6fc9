// Scaled Bessel functions and the ball Green's functions (harmonic, Yukawa):
// closed forms against quadrature of the mean-value identities of
// FORMULAS.md §1-§4, limits c → 0 and z → ∞, and the image-method gradient.
#include <gridfree/math/BesselFunctions.h>
#include <gridfree/greens/GreensFunctions.h>
#include "Quadrature.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <vector>

using namespace gridfree;
using gridfree::testing::GaussLegendre;

namespace
{
double RelativeError(double value, double reference)
{
  return std::abs(value - reference) / std::abs(reference);
}

template <int DIM>
double RelativeError(const Vec<DIM>& value, const Vec<DIM>& reference)
{
  return (value - reference).norm() / reference.norm();
}

template <class T>
T ZeroOf()
{
  return T::Zero();
}

template <>
double ZeroOf<double>()
{
  return 0.0;
}

// ∫_0^b h(r) dr on geometric panels [b 2^{-k-1}, b 2^{-k}]: the panels follow
// log and 1/r behaviour at 0 and the e^{-sr} peak at r ~ 1/s of large z.
template <class T>
T RadialIntegral(const std::function<T(double)>& h, double b, int panels = 60, int order = 16)
{
  static const GaussLegendre rule16(16);
  static const GaussLegendre rule12(12);
  const GaussLegendre& rule = order == 16 ? rule16 : rule12;
  T sum = ZeroOf<T>();
  double hi = b;
  for (int k = 0; k <= panels; ++k)
  {
    const double lo = k == panels ? 0.0 : 0.5 * hi;
    const double half = 0.5 * (hi - lo);
    const double mid = 0.5 * (hi + lo);
    for (std::size_t i = 0; i < rule.Nodes.size(); ++i)
    {
      sum += (rule.Weights[i] * half) * h(mid + half * rule.Nodes[i]);
    }
    hi = lo;
  }
  return sum;
}

// mean over the unit sphere of g(ω): trapezoid in angle (2D), Gauss-Legendre
// in cos θ times trapezoid in φ (3D); spectrally accurate for smooth g.
template <int DIM, class T>
T SphereMean(const std::function<T(const Vec<DIM>&)>& g)
{
  T sum = ZeroOf<T>();
  if constexpr (DIM == 2)
  {
    const int m = 64;
    for (int j = 0; j < m; ++j)
    {
      const double phi = 2.0 * M_PI * (j + 0.5) / m;
      sum += g(Vec<2>(std::cos(phi), std::sin(phi))) / double(m);
    }
  }
  else
  {
    static const GaussLegendre rule(24);
    const int m = 48;
    for (std::size_t i = 0; i < rule.Nodes.size(); ++i)
    {
      const double mu = rule.Nodes[i];
      const double rho = std::sqrt(1.0 - mu * mu);
      for (int j = 0; j < m; ++j)
      {
        const double phi = 2.0 * M_PI * (j + 0.5) / m;
        sum +=
          (0.5 * rule.Weights[i] / m) * g(Vec<3>(rho * std::cos(phi), rho * std::sin(phi), mu));
      }
    }
  }
  return sum;
}

// ∫_{B(0,R)} F(d) dd in polar coordinates around the pole d = 0.
template <int DIM, class T>
T BallIntegral(const std::function<T(const Vec<DIM>&)>& integrand, double radius)
{
  const std::function<T(double)> shell = [&](double r) -> T {
    const std::function<T(const Vec<DIM>&)> g = [&](const Vec<DIM>& w) -> T {
      return integrand(r * w);
    };
    return (UnitSphereArea<DIM>() * std::pow(r, DIM - 1)) * SphereMean<DIM, T>(g);
  };
  return RadialIntegral<T>(shell, radius, 30, 12);
}

// |S| ∫_0^R r^{n−1} G(r) dr.
template <int DIM, class Kernel>
double RadialVolumeIntegral(const Kernel& kernel)
{
  const std::function<double(double)> h = [&](double r) {
    return UnitSphereArea<DIM>() * std::pow(r, DIM - 1) * kernel.Value(r);
  };
  return RadialIntegral<double>(h, kernel.Radius());
}

template <int DIM>
Vec<DIM> OffCentre()
{
  Vec<DIM> x;
  if constexpr (DIM == 2)
  {
    x << 0.3, -0.2;
  }
  else
  {
    x << 0.3, -0.2, 0.15;
  }
  return x;
}

// A smooth u with u(x), ∇u(x) and f = Δu − c u known in closed form.
template <int DIM>
struct TestFunction
{
  std::function<double(const Vec<DIM>&)> U;
  std::function<Vec<DIM>(const Vec<DIM>&)> GradU;
  std::function<double(const Vec<DIM>&)> F;
};

// u = e^{s y1} (1 + y2²): Δu − c u = 2 e^{s y1} (f ≠ 0 and odd in y1 − x1).
template <int DIM>
TestFunction<DIM> ScreenedExponential(double c)
{
  const double s = std::sqrt(c);
  TestFunction<DIM> t;
  t.U = [s](const Vec<DIM>& y) { return std::exp(s * y[0]) * (1.0 + y[1] * y[1]); };
  t.GradU = [s](const Vec<DIM>& y) {
    Vec<DIM> g = Vec<DIM>::Zero();
    g[0] = s * std::exp(s * y[0]) * (1.0 + y[1] * y[1]);
    g[1] = std::exp(s * y[0]) * 2.0 * y[1];
    return g;
  };
  t.F = [s](const Vec<DIM>& y) { return 2.0 * std::exp(s * y[0]); };
  return t;
}

// Polynomials of FORMULAS.md §5 with f = Δu − c u:
// 2D u = x⁴ + x³y − 2xy² + 3y³ + xy, 3D u = |x|⁴ + xyz² + x³ − 2yz.
template <int DIM>
TestFunction<DIM> Polynomial(double c)
{
  TestFunction<DIM> t;
  if constexpr (DIM == 2)
  {
    t.U = [](const Vec<2>& p) {
      const double x = p[0], y = p[1];
      return x * x * x * x + x * x * x * y - 2 * x * y * y + 3 * y * y * y + x * y;
    };
    t.GradU = [](const Vec<2>& p) {
      const double x = p[0], y = p[1];
      return Vec<2>(
        4 * x * x * x + 3 * x * x * y - 2 * y * y + y, x * x * x - 4 * x * y + 9 * y * y + x);
    };
    t.F = [c, u = t.U](const Vec<2>& p) {
      const double x = p[0], y = p[1];
      return 12 * x * x + 6 * x * y - 4 * x + 18 * y - c * u(p);
    };
  }
  else
  {
    t.U = [](const Vec<3>& p) {
      const double q = p.squaredNorm();
      return q * q + p[0] * p[1] * p[2] * p[2] + p[0] * p[0] * p[0] - 2 * p[1] * p[2];
    };
    t.GradU = [](const Vec<3>& p) {
      const double q = p.squaredNorm();
      const double x = p[0], y = p[1], z = p[2];
      return Vec<3>(4 * q * x + y * z * z + 3 * x * x, 4 * q * y + x * z * z - 2 * z,
        4 * q * z + 2 * x * y * z - 2 * y);
    };
    // Δ|x|⁴ = 4(n + 2)|x|² = 20|x|², Δ(xyz²) = 2xy, Δx³ = 6x.
    t.F = [c, u = t.U](const Vec<3>& p) {
      return 20 * p.squaredNorm() + 2 * p[0] * p[1] + 6 * p[0] - c * u(p);
    };
  }
  return t;
}

// u(x) = C·mean_∂B u − ∫_B f G (FORMULAS.md §2-§3), both sides by quadrature.
template <int DIM, class Kernel>
double ValueIdentityError(
  const Kernel& kernel, const TestFunction<DIM>& t, double sourceSign = -1.0)
{
  const Vec<DIM> x = OffCentre<DIM>();
  const double radius = kernel.Radius();
  const std::function<double(const Vec<DIM>&)> onSphere = [&](const Vec<DIM>& w) {
    return t.U(x + radius * w);
  };
  const std::function<double(const Vec<DIM>&)> source = [&](const Vec<DIM>& d) {
    return t.F(x + d) * kernel.Value(d.norm());
  };
  const double estimate = kernel.BoundaryWeight() * SphereMean<DIM, double>(onSphere) +
    sourceSign * BallIntegral<DIM, double>(source, radius);
  return RelativeError(estimate, t.U(x));
}

// ∇u(x) = κ·mean_∂B[u ν] − ∫_B f ∇G (FORMULAS.md §3-§4), both sides by quadrature.
template <int DIM, class Kernel>
double GradientIdentityError(const Kernel& kernel, const TestFunction<DIM>& t, double kappa)
{
  const Vec<DIM> x = OffCentre<DIM>();
  const double radius = kernel.Radius();
  const std::function<Vec<DIM>(const Vec<DIM>&)> onSphere = [&](const Vec<DIM>& w) -> Vec<DIM> {
    return t.U(x + radius * w) * w;
  };
  const std::function<Vec<DIM>(const Vec<DIM>&)> source = [&](const Vec<DIM>& d) -> Vec<DIM> {
    return t.F(x + d) * kernel.Gradient(d);
  };
  const Vec<DIM> estimate =
    kappa * SphereMean<DIM, Vec<DIM>>(onSphere) - BallIntegral<DIM, Vec<DIM>>(source, radius);
  return RelativeError<DIM>(estimate, t.GradU(x));
}

// Radial ODE residual G'' + (n−1)/r G' − c G relative to |G''|, by central differences.
template <int DIM, class Kernel>
double RadialPdeResidual(const Kernel& kernel, double r, double c)
{
  const double h = 1e-4 * r;
  const double gm = kernel.Value(r - h), g0 = kernel.Value(r), gp = kernel.Value(r + h);
  const double second = (gp - 2.0 * g0 + gm) / (h * h);
  const double first = (gp - gm) / (2.0 * h);
  return std::abs(second + (DIM - 1) / r * first - c * g0) / std::abs(second);
}

// Radii with z = sR fixed by R = 1, c = z².
const double Zs[] = { 0.5, 1.4, 3.0, 11.0 };
} // namespace

// ---------------------------------------------------------------- Bessel

// Against Boost in long double (other approximations, 64-bit mantissa, and
// wide enough exponent range to evaluate I and K unscaled up to x = 10⁴), so
// both the Boost branch and the Hankel branch (x >= 500) are checked.
TEST(BesselFunctions, ScaledFormsMatchLongDoubleReference)
{
  std::vector<double> xs;
  for (double x = 1e-12; x < 1e4; x *= 1.05)
  {
    xs.push_back(x);
  }
  for (double x = 490.0; x <= 510.0; x += 0.25)
  {
    xs.push_back(x); // both sides of the asymptotic threshold
  }
  double worst = 0.0;
  for (const double x : xs)
  {
    const long double lx = x;
    const long double up = std::exp(lx);
    const long double down = std::exp(-lx);
    const long double i0 = boost::math::cyl_bessel_i(0, lx) * down;
    const long double i1 = boost::math::cyl_bessel_i(1, lx) * down;
    const long double k0 = boost::math::cyl_bessel_k(0, lx) * up;
    const long double k1 = boost::math::cyl_bessel_k(1, lx) * up;
    const long double sph =
      boost::math::cyl_bessel_i(1.5L, lx) * std::sqrt(M_PIl / (2.0L * lx)) * down;
    const double errors[] = { double(std::abs(BesselI0Scaled(x) / i0 - 1.0L)),
      double(std::abs(BesselI1Scaled(x) / i1 - 1.0L)),
      double(std::abs(BesselK0Scaled(x) / k0 - 1.0L)),
      double(std::abs(BesselK1Scaled(x) / k1 - 1.0L)),
      double(std::abs(SphericalBesselI1Scaled(x) / sph - 1.0L)) };
    for (const double e : errors)
    {
      ASSERT_LT(e, 1e-13) << "x = " << x;
      worst = std::max(worst, e);
    }
  }
  EXPECT_LT(worst, 2e-15);
}

TEST(BesselFunctions, HugeArgumentsFollowTheLeadingHankelTerms)
{
  for (const double x : { 1e4, 1e5, 1e6 })
  {
    // Truncation after 1/x² leaves O(x^{-3}) <= 1e-12 relative at x = 10⁴.
    const double i = 1.0 / std::sqrt(2.0 * M_PI * x);
    const double k = std::sqrt(M_PI / (2.0 * x));
    const double t = 1.0 / (8.0 * x);
    EXPECT_LT(RelativeError(BesselI0Scaled(x), i * (1.0 + t + 9.0 * t * t / 2.0)), 1e-12);
    EXPECT_LT(RelativeError(BesselI1Scaled(x), i * (1.0 - 3.0 * t - 15.0 * t * t / 2.0)), 1e-12);
    EXPECT_LT(RelativeError(BesselK0Scaled(x), k * (1.0 - t + 9.0 * t * t / 2.0)), 1e-12);
    EXPECT_LT(RelativeError(BesselK1Scaled(x), k * (1.0 + 3.0 * t - 15.0 * t * t / 2.0)), 1e-12);
    EXPECT_LT(RelativeError(SphericalBesselI1Scaled(x), (x - 1.0) / (2.0 * x * x)), 1e-15);
  }
  EXPECT_EQ(BesselI0Scaled(0.0), 1.0);
  EXPECT_EQ(BesselI1Scaled(0.0), 0.0);
  EXPECT_EQ(SphericalBesselI1Scaled(0.0), 0.0);
  EXPECT_TRUE(std::isinf(BesselK0Scaled(0.0)));
  EXPECT_LT(RelativeError(SphericalBesselI1Scaled(1e-12), 1e-12 / 3.0 * std::exp(-1e-12)), 1e-15);
}

// ---------------------------------------------------------------- harmonic

namespace
{
template <int DIM>
void CheckHarmonicValue()
{
  const double radius = 0.7;
  const HarmonicGreensFunction<DIM> g(radius);
  EXPECT_EQ(g.Radius(), radius);
  EXPECT_EQ(g.BoundaryWeight(), 1.0);
  EXPECT_DOUBLE_EQ(g.GradientWeight(), DIM / radius);
  EXPECT_DOUBLE_EQ(g.Integral(), radius * radius / (2.0 * DIM));
  EXPECT_LT(RelativeError(RadialVolumeIntegral<DIM>(g), g.Integral()), 1e-13);
  EXPECT_EQ(g.Value(radius), 0.0);
  EXPECT_EQ(g.Value(2.0 * radius), 0.0);
  EXPECT_TRUE(std::isinf(g.Value(0.0)));
  EXPECT_DOUBLE_EQ(g.Density(0.3), g.Value(0.3) / g.Integral());
  for (const double r : { 0.01, 0.2, 0.5, 0.69 })
  {
    EXPECT_LT(RadialPdeResidual<DIM>(g, r, 0.0), 1e-6) << r;
  }
  // Flux −1 through every sphere around the pole: −Δ G = δ.
  const double h = 1e-6;
  const double slope = (g.Value(0.4 + h) - g.Value(0.4 - h)) / (2.0 * h);
  EXPECT_NEAR(UnitSphereArea<DIM>() * std::pow(0.4, DIM - 1) * slope, -1.0, 1e-8);

  // Δ|y|² = 2n off-centre: u(x) = mean u − ∫ f G; the paper's "+" is off by 2R².
  TestFunction<DIM> square;
  square.U = [](const Vec<DIM>& y) { return y.squaredNorm(); };
  square.F = [](const Vec<DIM>&) { return 2.0 * DIM; };
  EXPECT_LT(ValueIdentityError<DIM>(g, square), 1e-13);
  EXPECT_GT(ValueIdentityError<DIM>(g, square, +1.0), 1.0);
  const Vec<DIM> x = OffCentre<DIM>();
  EXPECT_NEAR(x.squaredNorm() + radius * radius - 2.0 * DIM * g.Integral(), x.squaredNorm(), 1e-15);
  EXPECT_LT(ValueIdentityError<DIM>(g, Polynomial<DIM>(0.0)), 1e-12);
}
} // namespace

TEST(HarmonicGreensFunction, ValueIntegralAndMeanValueIdentity2D)
{
  CheckHarmonicValue<2>();
}

TEST(HarmonicGreensFunction, ValueIntegralAndMeanValueIdentity3D)
{
  CheckHarmonicValue<3>();
}

namespace
{
template <int DIM>
void CheckHarmonicGradient()
{
  const HarmonicGreensFunction<DIM> g(0.7);
  const TestFunction<DIM> poly = Polynomial<DIM>(0.0);
  EXPECT_LT(GradientIdentityError<DIM>(g, poly, g.GradientWeight()), 1e-12);

  // The same identity fails for the naive kernel d/(|S| r^n) (no image term).
  struct Naive
  {
    double Radius() const { return 0.7; }
    Vec<DIM> Gradient(const Vec<DIM>& d) const
    {
      return d.norm() < 0.7 ? Vec<DIM>(d / (UnitSphereArea<DIM>() * std::pow(d.norm(), DIM)))
                            : Vec<DIM>::Zero();
    }
  };
  EXPECT_GT(GradientIdentityError<DIM>(Naive(), poly, g.GradientWeight()), 1e-2);

  // ∇_x of the image-method Green's function of the fixed ball B(0, R) at
  // x = 0: G_B(x, y) = Φ(|y − x|) − Φ(sqrt(|x|²|y|²/R² − 2x·y + R²)).
  const double radius = g.Radius();
  const auto phi = [](double r) {
    return DIM == 2 ? -std::log(r) / (2.0 * M_PI) : 1.0 / (4.0 * M_PI * r);
  };
  const auto imageGreen = [&](const Vec<DIM>& x, const Vec<DIM>& y) {
    const double image = std::sqrt(
      x.squaredNorm() * y.squaredNorm() / (radius * radius) - 2.0 * x.dot(y) + radius * radius);
    return phi((y - x).norm()) - phi(image);
  };
  RandomStream rng(7, 0);
  for (int k = 0; k < 20; ++k)
  {
    const Vec<DIM> y = radius * SampleUnitBall<DIM>(rng);
    EXPECT_LT(
      std::abs(imageGreen(Vec<DIM>::Zero(), y) - g.Value(y.norm())), 1e-13 * g.Value(y.norm()));
    Vec<DIM> difference;
    const double h = 1e-5 * y.norm();
    for (int i = 0; i < DIM; ++i)
    {
      const Vec<DIM> e = h * Vec<DIM>::Unit(i);
      difference[i] = (imageGreen(e, y) - imageGreen(-e, y)) / (2.0 * h);
    }
    EXPECT_LT(RelativeError<DIM>(g.Gradient(y), difference), 1e-7) << y.transpose();
  }
  EXPECT_EQ(g.Gradient(Vec<DIM>::Zero()).norm(), 0.0);
  EXPECT_EQ(g.Gradient(Vec<DIM>::Constant(radius)).norm(), 0.0);
}
} // namespace

TEST(HarmonicGreensFunction, GradientIdentityAndImageMethod2D)
{
  CheckHarmonicGradient<2>();
}

TEST(HarmonicGreensFunction, GradientIdentityAndImageMethod3D)
{
  CheckHarmonicGradient<3>();
}

// ---------------------------------------------------------------- Yukawa

namespace
{
template <int DIM>
void CheckYukawaValue()
{
  for (const double z : Zs)
  {
    const double c = z * z;
    const YukawaGreensFunction<DIM> g(1.0, c);
    SCOPED_TRACE(::testing::Message() << "z = " << z);
    EXPECT_EQ(g.Radius(), 1.0);
    EXPECT_EQ(g.Screening(), c);
    const double weight = DIM == 2 ? 1.0 / std::cyl_bessel_i(0.0, z) : z / std::sinh(z);
    EXPECT_LT(RelativeError(g.BoundaryWeight(), weight), 1e-14);
    EXPECT_LT(RelativeError(RadialVolumeIntegral<DIM>(g), g.Integral()), 1e-12);
    EXPECT_LT(RelativeError(g.Integral(), (1.0 - g.BoundaryWeight()) / c), 1e-13);

    // C = −flux of G_c through ∂B (Wronskian), with a 4th-order one-sided
    // difference at r = R where G_c = 0.
    const double h = 1e-3 / std::max(1.0, z);
    EXPECT_EQ(g.Value(1.0), 0.0);
    const double slope = (-48.0 * g.Value(1.0 - h) + 36.0 * g.Value(1.0 - 2 * h) -
                           16.0 * g.Value(1.0 - 3 * h) + 3.0 * g.Value(1.0 - 4 * h)) /
      (12.0 * h);
    EXPECT_LT(RelativeError(-UnitSphereArea<DIM>() * slope, g.BoundaryWeight()), 1e-9);

    for (const double r : { 0.01, 0.2, 0.5, 0.9 })
    {
      EXPECT_LT(RadialPdeResidual<DIM>(g, r, c), 1e-6) << r;
      EXPECT_GT(g.Value(r), 0.0);
      EXPECT_LE(g.Value(r), HarmonicGreensFunction<DIM>(1.0).Value(r));
    }
    EXPECT_LT(ValueIdentityError<DIM>(g, ScreenedExponential<DIM>(c)), 1e-12);
    EXPECT_LT(ValueIdentityError<DIM>(g, Polynomial<DIM>(c)), 1e-12);
    // The paper's "+" fails, and so does the harmonic weight C = 1.
    EXPECT_GT(ValueIdentityError<DIM>(g, ScreenedExponential<DIM>(c), +1.0), 1e-2);
    EXPECT_GT(
      ValueIdentityError<DIM>(HarmonicGreensFunction<DIM>(1.0), ScreenedExponential<DIM>(c)), 1e-2);
  }
}
} // namespace

TEST(YukawaGreensFunction, ValueIntegralWeightAndMeanValueIdentity2D)
{
  CheckYukawaValue<2>();
}

TEST(YukawaGreensFunction, ValueIntegralWeightAndMeanValueIdentity3D)
{
  CheckYukawaValue<3>();
}

namespace
{
template <int DIM>
void CheckYukawaGradient()
{
  for (const double z : Zs)
  {
    const double c = z * z;
    const YukawaGreensFunction<DIM> g(1.0, c);
    SCOPED_TRACE(::testing::Message() << "z = " << z);
    const double i1 =
      DIM == 2 ? std::cyl_bessel_i(1.0, z) : (z * std::cosh(z) - std::sinh(z)) / (z * z);
    EXPECT_LT(RelativeError(g.GradientWeight(), z / i1), 1e-13);

    // f = 0: checks κ alone; then f ≠ 0 checks ∇G_c.
    TestFunction<DIM> plain;
    plain.U = [z](const Vec<DIM>& y) { return std::exp(z * y[0]); };
    plain.GradU = [z](const Vec<DIM>& y) {
      return Vec<DIM>(z * std::exp(z * y[0]) * Vec<DIM>::Unit(0));
    };
    plain.F = [](const Vec<DIM>&) { return 0.0; };
    EXPECT_LT(GradientIdentityError<DIM>(g, plain, g.GradientWeight()), 1e-12);
    EXPECT_LT(
      GradientIdentityError<DIM>(g, ScreenedExponential<DIM>(c), g.GradientWeight()), 1e-11);
    EXPECT_LT(GradientIdentityError<DIM>(g, Polynomial<DIM>(c), g.GradientWeight()), 1e-11);
    // The paper's κ = n/R is wrong for c > 0.
    EXPECT_GT(GradientIdentityError<DIM>(g, plain, DIM / g.Radius()), 1e-2);
  }
}
} // namespace

TEST(YukawaGreensFunction, GradientIdentity2D)
{
  CheckYukawaGradient<2>();
}

TEST(YukawaGreensFunction, GradientIdentity3D)
{
  CheckYukawaGradient<3>();
}

namespace
{
template <int DIM>
void CheckSmallScreening()
{
  const double radius = 0.8;
  const HarmonicGreensFunction<DIM> h(radius);
  for (const double c : { 1e-12, 1e-6 })
  {
    const YukawaGreensFunction<DIM> g(radius, c);
    SCOPED_TRACE(::testing::Message() << "c = " << c);
    const double z2 = c * radius * radius;
    // Corrections are O(z²); 1e-12 leaves room for rounding in the 2D
    // K0(sr) − K0(z) I0(sr)/I0(z) difference.
    const double tolerance = z2 + 1e-12;
    EXPECT_LT(std::abs(g.BoundaryWeight() - 1.0), tolerance);
    EXPECT_LT(RelativeError(g.GradientWeight(), h.GradientWeight()), tolerance);
    EXPECT_LT(RelativeError(g.Integral(), h.Integral()), tolerance);
    for (const double r : { 1e-6, 0.08, 0.4, 0.72 })
    {
      EXPECT_LT(RelativeError(g.Value(r), h.Value(r)), tolerance) << r;
      const Vec<DIM> d = r * Vec<DIM>::Ones().normalized();
      EXPECT_LT(RelativeError<DIM>(g.Gradient(d), h.Gradient(d)), tolerance) << r;
    }
  }
  // The z < 1 series agrees with FORMULAS.md §3's expansion at z = 1e-3 and
  // with (1 − C)/c across the switch at z = 1.
  const double z = 1e-3;
  const double leading = DIM == 2 ? 0.25 - 3.0 * z * z / 64.0 : 1.0 / 6.0 - 7.0 * z * z / 360.0;
  EXPECT_LT(RelativeError(YukawaGreensFunction<DIM>(1.0, z * z).Integral(), leading), 1e-11);
  const YukawaGreensFunction<DIM> below(1.0, 1.0 - 1e-12), above(1.0, 1.0 + 1e-12);
  EXPECT_LT(RelativeError(below.Integral(), above.Integral()), 1e-11);
  EXPECT_LT(RelativeError(below.Integral(), (1.0 - below.BoundaryWeight()) / (1.0 - 1e-12)), 1e-14);
}
} // namespace

TEST(YukawaGreensFunction, SmallScreeningRecoversHarmonic2D)
{
  CheckSmallScreening<2>();
}

TEST(YukawaGreensFunction, SmallScreeningRecoversHarmonic3D)
{
  CheckSmallScreening<3>();
}

namespace
{
template <int DIM>
void CheckLargeScreening()
{
  for (const double z : { 800.0, 5000.0 })
  {
    const double c = z * z;
    const YukawaGreensFunction<DIM> g(1.0, c);
    SCOPED_TRACE(::testing::Message() << "z = " << z);
    // C ~ e^{−z} underflows to 0, as it should; nothing may be NaN or inf.
    EXPECT_TRUE(std::isfinite(g.BoundaryWeight()) && g.BoundaryWeight() >= 0.0);
    EXPECT_TRUE(std::isfinite(g.GradientWeight()) && g.GradientWeight() >= 0.0);
    EXPECT_LT(g.BoundaryWeight(), 1e-300);
    EXPECT_LT(RelativeError(g.Integral(), 1.0 / c), 1e-15);
    EXPECT_LT(RelativeError(RadialVolumeIntegral<DIM>(g), g.Integral()), 1e-12);
    const double s = z;
    for (const double r : { 1e-9, 0.1 / z, 1.0 / z, 10.0 / z, 100.0 / z, 0.1, 0.5 })
    {
      const double sr = s * r;
      // Free-space kernel near the pole; the image correction is ~e^{−2s(R−r)}.
      const double free =
        DIM == 2 ? std::cyl_bessel_k(0.0, sr) / (2.0 * M_PI) : std::exp(-sr) / (4.0 * M_PI * r);
      const double value = g.Value(r);
      ASSERT_TRUE(std::isfinite(value)) << r;
      if (sr < 600.0)
      {
        EXPECT_GT(value, 0.0) << r;
        EXPECT_LT(RelativeError(value, free), 1e-13) << r;
      }
      const Vec<DIM> d = r * Vec<DIM>::Unit(0);
      const Vec<DIM> gradient = g.Gradient(d);
      ASSERT_TRUE(std::isfinite(gradient.norm())) << r;
      if (sr < 600.0)
      {
        const double radial = DIM == 2 ? s * std::cyl_bessel_k(1.0, sr) / (2.0 * M_PI * r)
                                       : std::exp(-sr) * (1.0 + sr) / (4.0 * M_PI * r * r * r);
        EXPECT_LT(RelativeError(gradient[0], radial * r), 1e-13) << r;
      }
    }
    for (const double r : { 0.9, 0.999, 0.999999 })
    {
      EXPECT_TRUE(g.Value(r) >= 0.0 && std::isfinite(g.Value(r)));
      EXPECT_TRUE(std::isfinite(g.Gradient(r * Vec<DIM>::Unit(1)).norm()));
    }
  }
}
} // namespace

TEST(YukawaGreensFunction, LargeScreeningIsFiniteAndFreeSpaceNearPole2D)
{
  CheckLargeScreening<2>();
}

TEST(YukawaGreensFunction, LargeScreeningIsFiniteAndFreeSpaceNearPole3D)
{
  CheckLargeScreening<3>();
}
