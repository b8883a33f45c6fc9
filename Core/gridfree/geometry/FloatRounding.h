// Directed rounding of doubles to floats, one-step float neighbours, and
// scaling by powers of two, without touching the FPU's rounding mode: the
// hierarchy rounds box bounds outward and its filter's thresholds up, so that
// float tests stay conservative (Bvh.h, BvhLeafFilter.h).
#ifndef GRIDFREE_GEOMETRY_FLOAT_ROUNDING_H
#define GRIDFREE_GEOMETRY_FLOAT_ROUNDING_H

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace gridfree
{
namespace detail
{
/// The next float below a float that is not NaN: one step of its bit
/// pattern, which orders like the value within each sign. (std::nextafter
/// was a tenth of a walk step's instructions.)
inline float NextFloatDown(float f)
{
  if (f == 0.0f)
  {
    return -std::numeric_limits<float>::denorm_min();
  }
  std::uint32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  bits = f > 0.0f ? bits - 1u : bits + 1u;
  std::memcpy(&f, &bits, sizeof bits);
  return f;
}

/// The next float above a float that is not NaN.
inline float NextFloatUp(float f)
{
  return -NextFloatDown(-f);
}

/// Largest float <= v (directed rounding without touching the FPU mode).
///
/// Without a branch: whether the nearest float lies above v is a coin flip,
/// which a branch predictor loses half the time, and a ray query rounds about
/// ten values. When it does, f is not +0 (rounding keeps the sign, so a
/// negative v rounds to -0 at most) and not NaN, and one step of the bit
/// pattern (down for a positive f, up for a negative one, -0 included) gives
/// NextFloatDown(f).
inline float FloatDown(double v)
{
  const float f = static_cast<float>(v);
  std::uint32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  const std::uint32_t above = static_cast<double>(f) > v; // 0 or 1
  const std::uint32_t step = (bits >> 31) * 2u - 1u;     // +1 if negative, else -1
  bits += step & (0u - above);
  float r;
  std::memcpy(&r, &bits, sizeof bits);
  return r;
}

/// Smallest float >= v (negation is exact, in double and in float).
inline float FloatUp(double v)
{
  return -FloatDown(-v);
}

/// x * 2^n with the bits of std::ldexp(x, n): where 2^n is a normal double
/// the product is exact or rounded once, as ldexp is, so one multiplication
/// replaces the library call (a ray query made five of them, at about fifty
/// instructions each).
inline double ScaleByPowerOfTwo(double x, int n)
{
  if (n >= -1022 && n <= 1023)
  {
    const std::uint64_t bits = static_cast<std::uint64_t>(n + 1023) << 52;
    double power;
    std::memcpy(&power, &bits, sizeof bits);
    return x * power;
  }
  return std::ldexp(x, n);
}
} // namespace detail
} // namespace gridfree

#endif
