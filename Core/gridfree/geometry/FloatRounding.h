// Directed rounding of doubles to floats, and one-step float neighbours,
// without touching the FPU's rounding mode: the hierarchy rounds box bounds
// outward and its filter's thresholds up, so that float tests stay
// conservative (Bvh.h, BvhLeafFilter.h).
#ifndef GRIDFREE_GEOMETRY_FLOAT_ROUNDING_H
#define GRIDFREE_GEOMETRY_FLOAT_ROUNDING_H

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
inline float FloatDown(double v)
{
  const float f = static_cast<float>(v);
  return static_cast<double>(f) > v ? NextFloatDown(f) : f;
}

/// Smallest float >= v.
inline float FloatUp(double v)
{
  const float f = static_cast<float>(v);
  return static_cast<double>(f) < v ? NextFloatUp(f) : f;
}
} // namespace detail
} // namespace gridfree

#endif
