// Tests of the directed rounding of doubles to floats (FloatRounding.h).
//
// The hierarchy's float tests are conservative only if FloatDown never rounds
// above its argument and FloatUp never below, and they are the tightest such
// floats only if each is one of the two floats around v. The reference here
// is independent of the branch-free bit step: the float nearest v, moved by
// std::nextafter when it lies on the wrong side.
#include <gridfree/geometry/FloatRounding.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace
{
constexpr double kInf = std::numeric_limits<double>::infinity();

float ReferenceDown(double v)
{
  const float f = static_cast<float>(v);
  return static_cast<double>(f) > v ? std::nextafter(f, -std::numeric_limits<float>::infinity())
                                    : f;
}

float ReferenceUp(double v)
{
  const float f = static_cast<float>(v);
  return static_cast<double>(f) < v ? std::nextafter(f, std::numeric_limits<float>::infinity())
                                    : f;
}

std::uint32_t Bits(float f)
{
  std::uint32_t b;
  std::memcpy(&b, &f, sizeof b);
  return b;
}

// Same bits as the reference (so -0 and +0 are told apart), and on the right
// side of v.
void ExpectDirected(double v)
{
  const float down = gridfree::detail::FloatDown(v);
  const float up = gridfree::detail::FloatUp(v);
  if (std::isnan(v))
  {
    EXPECT_TRUE(std::isnan(down));
    EXPECT_TRUE(std::isnan(up));
    return;
  }
  EXPECT_EQ(Bits(down), Bits(ReferenceDown(v))) << "FloatDown(" << v << ")";
  EXPECT_EQ(Bits(up), Bits(ReferenceUp(v))) << "FloatUp(" << v << ")";
  EXPECT_LE(static_cast<double>(down), v);
  EXPECT_GE(static_cast<double>(up), v);
}
} // namespace

TEST(FloatRounding, SpecialValues)
{
  constexpr double inf = std::numeric_limits<double>::infinity();
  constexpr double fmax = std::numeric_limits<float>::max();
  constexpr double fden = std::numeric_limits<float>::denorm_min();
  constexpr double fmin = std::numeric_limits<float>::min();
  const std::vector<double> values = { 0.0, -0.0, inf, -inf, std::nan(""), 1.0, -1.0,
    fden, -fden, 0.5 * fden, -0.5 * fden, 0.25 * fden, -0.25 * fden, 1e-300, -1e-300,
    std::numeric_limits<double>::denorm_min(), -std::numeric_limits<double>::denorm_min(), fmin,
    -fmin, fmin * (1.0 - 0x1p-30), -fmin * (1.0 - 0x1p-30), fmax, -fmax, fmax * (1.0 + 0x1p-30),
    -fmax * (1.0 + 0x1p-30), fmax * 2.0, -fmax * 2.0, 1.0 + 0x1p-30, 1.0 - 0x1p-30,
    -1.0 - 0x1p-30, -1.0 + 0x1p-30, 0.1, -0.1, std::numeric_limits<double>::max(),
    -std::numeric_limits<double>::max() };
  for (double v : values)
  {
    ExpectDirected(v);
  }
  // Rounding keeps the sign of a value that rounds to zero.
  EXPECT_EQ(Bits(gridfree::detail::FloatDown(-1e-300)), Bits(-std::numeric_limits<float>::denorm_min()));
  EXPECT_EQ(Bits(gridfree::detail::FloatUp(-1e-300)), Bits(-0.0f));
  EXPECT_EQ(Bits(gridfree::detail::FloatDown(1e-300)), Bits(0.0f));
  EXPECT_EQ(Bits(gridfree::detail::FloatUp(1e-300)), Bits(std::numeric_limits<float>::denorm_min()));
}

// Random doubles of every sign and float exponent, half of them exactly
// floats or floats moved by one double ulp, where the rounding direction
// matters most.
TEST(FloatRounding, RandomValuesMatchTheReference)
{
  std::mt19937_64 rng(20261128);
  std::uniform_real_distribution<double> mantissa(1.0, 2.0);
  std::uniform_int_distribution<int> exponent(-160, 140);
  std::uniform_int_distribution<int> kind(0, 3);
  for (int i = 0; i < 200000; ++i)
  {
    double v = std::ldexp(mantissa(rng), exponent(rng));
    if (rng() & 1)
    {
      v = -v;
    }
    switch (kind(rng))
    {
      case 0:
        break;
      case 1:
        v = static_cast<float>(v);
        break;
      case 2:
        v = std::nextafter(static_cast<double>(static_cast<float>(v)), kInf);
        break;
      default:
        v = std::nextafter(static_cast<double>(static_cast<float>(v)), -kInf);
        break;
    }
    ExpectDirected(v);
    if (::testing::Test::HasFailure())
    {
      return; // one value is enough to see what went wrong
    }
  }
}

// Scaling by a power of two has std::ldexp's bits: exact, overflowing to
// infinity, or rounded once into the subnormals, for exponents within and
// beyond the normal range.
TEST(FloatRounding, ScaleByPowerOfTwoMatchesLdexp)
{
  std::mt19937_64 rng(4242);
  std::uniform_real_distribution<double> mantissa(1.0, 2.0);
  std::uniform_int_distribution<int> exponent(-1074, 1023);
  std::uniform_int_distribution<int> shift(-1100, 1100);
  auto bits = [](double d)
  {
    std::uint64_t b;
    std::memcpy(&b, &d, sizeof b);
    return b;
  };
  const std::vector<double> specials = { 0.0, -0.0, kInf, -kInf, std::nan(""),
    std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::max(),
    std::numeric_limits<double>::min(), -1.5, 3.0 };
  for (double x : specials)
  {
    for (int n : { -1100, -1075, -1074, -1023, -1022, -60, -1, 0, 1, 60, 1023, 1024, 1100 })
    {
      const double got = gridfree::detail::ScaleByPowerOfTwo(x, n);
      const double want = std::ldexp(x, n);
      if (std::isnan(want))
      {
        EXPECT_TRUE(std::isnan(got));
      }
      else
      {
        EXPECT_EQ(bits(got), bits(want)) << x << " * 2^" << n;
      }
    }
  }
  for (int i = 0; i < 200000; ++i)
  {
    double x = std::ldexp(mantissa(rng), exponent(rng));
    if (rng() & 1)
    {
      x = -x;
    }
    const int n = shift(rng);
    ASSERT_EQ(bits(gridfree::detail::ScaleByPowerOfTwo(x, n)), bits(std::ldexp(x, n)))
      << x << " * 2^" << n;
  }
}
