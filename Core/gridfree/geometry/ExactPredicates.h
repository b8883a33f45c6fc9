// Exact sign arithmetic: the signs of a * b - c * d and of a triple
// product decided exactly where rounding could flip them (error-free
// transformations and Shewchuk's expansions). The ray kernels
// (RayKernels.h) use them so that a ray through a shared edge or vertex of a
// closed mesh always hits one of the primitives around it.
#ifndef GRIDFREE_GEOMETRY_EXACT_PREDICATES_H
#define GRIDFREE_GEOMETRY_EXACT_PREDICATES_H

#include <gridfree/math/Vector.h>

#include <cmath>

namespace gridfree
{
namespace detail
{
// Exact sign arithmetic for the ray kernels. All of it is exact for finite
// inputs whose products neither overflow nor underflow (magnitudes between
// about 1e-150 and 1e150); the fused multiply-add gives the rounding error of
// a product, and sums never need fused operations.

/// Sign of a * b - c * d, exact. Rounding is monotone, so distinct rounded
/// products order the exact ones; equal rounded products differ only by
/// their (exactly representable) rounding errors.
inline int SignOfDifferenceOfProducts(double a, double b, double c, double d)
{
  const double p = a * b;
  const double q = c * d;
  if (p != q)
  {
    return p > q ? 1 : -1;
  }
  const double ep = std::fma(a, b, -p);
  const double eq = std::fma(c, d, -q);
  return (ep > eq) - (ep < eq);
}

/// a * b - c * d in double, with its sign made exact: when rounding could
/// have flipped or zeroed the sign, the magnitude is kept and the sign is
/// recomputed exactly (0 if the exact value is 0). Two primitives sharing an
/// edge evaluate the same products, so they always agree on which side of
/// that edge the ray passes, whatever the compiler fuses.
inline double ExactSignedDifferenceOfProducts(double a, double b, double c, double d)
{
  const double p = a * b;
  const double q = c * d;
  const double e = p - q;
  // The computed difference is within 2^-51 (|p| + |q|) of the exact one.
  if (std::abs(e) > 0x1p-50 * (std::abs(p) + std::abs(q)))
  {
    return e;
  }
  const int s = SignOfDifferenceOfProducts(a, b, c, d);
  return s > 0 ? std::abs(e) : (s < 0 ? -std::abs(e) : 0.0);
}

/// Error-free sum (Knuth): s + e == a + b exactly.
inline void TwoSum(double a, double b, double& s, double& e)
{
  s = a + b;
  const double bv = s - a;
  e = (a - (s - bv)) + (b - bv);
}

/// Adds x to the nonoverlapping expansion e[0..n) (increasing magnitude),
/// dropping zero components (Shewchuk's grow-expansion).
inline void GrowExpansion(double* e, int& n, double x)
{
  int m = 0;
  for (int i = 0; i < n; ++i)
  {
    double s, err;
    TwoSum(x, e[i], s, err);
    x = s;
    if (err != 0.0)
    {
      e[m++] = err;
    }
  }
  if (x != 0.0)
  {
    e[m++] = x;
  }
  n = m;
}

/// Adds the exact product a * b * c (four doubles) to an expansion.
inline void GrowExpansionByProduct(double* e, int& n, double a, double b, double c)
{
  if (a == 0.0 || b == 0.0 || c == 0.0)
  {
    return;
  }
  const double p = a * b;
  const double pe = std::fma(a, b, -p);
  const double q = p * c;
  GrowExpansion(e, n, std::fma(p, c, -q));
  GrowExpansion(e, n, q);
  if (pe != 0.0)
  {
    const double r = pe * c;
    GrowExpansion(e, n, std::fma(pe, c, -r));
    GrowExpansion(e, n, r);
  }
}

/// True unless the direction d is exactly parallel to the plane of the
/// triangle (v0, v1, v2), i.e. d . ((v1 - v0) x (v2 - v0)) == 0 exactly; a
/// zero-area triangle is parallel to every direction. Rounded first, exact
/// (expansion arithmetic on the exact edge vectors) only when ambiguous.
inline bool CrossesPlane(const Vec3& v0, const Vec3& v1, const Vec3& v2, const Vec3& d)
{
  const Vec3 e1 = v1 - v0;
  const Vec3 e2 = v2 - v0;
  double dot = 0.0;
  double bound = 0.0;
  for (int k = 0; k < 3; ++k)
  {
    const int i = (k + 1) % 3;
    const int j = (k + 2) % 3;
    const double p = e1[i] * e2[j];
    const double q = e1[j] * e2[i];
    dot += d[k] * (p - q);
    bound += std::abs(d[k]) * (std::abs(p) + std::abs(q));
  }
  // Rounding of the edge vectors, products, differences and sums stays far
  // below 2^-45 of the sum of the magnitudes.
  if (std::abs(dot) > 0x1p-45 * bound)
  {
    return true;
  }
  double hi1[3], lo1[3], hi2[3], lo2[3];
  for (int k = 0; k < 3; ++k)
  {
    TwoSum(v1[k], -v0[k], hi1[k], lo1[k]);
    TwoSum(v2[k], -v0[k], hi2[k], lo2[k]);
  }
  double e[100]; // at most 3 axes * 2 products * 4 parts * 4 terms components
  int n = 0;
  for (int k = 0; k < 3; ++k)
  {
    const int i = (k + 1) % 3;
    const int j = (k + 2) % 3;
    const double a[2] = { hi1[i], lo1[i] };
    const double b[2] = { hi2[j], lo2[j] };
    const double c[2] = { hi1[j], lo1[j] };
    const double f[2] = { hi2[i], lo2[i] };
    for (int x = 0; x < 2; ++x)
    {
      for (int y = 0; y < 2; ++y)
      {
        GrowExpansionByProduct(e, n, d[k], a[x], b[y]);
        GrowExpansionByProduct(e, n, -d[k], c[x], f[y]);
      }
    }
  }
  return n > 0; // the largest component of a nonzero expansion is nonzero
}
} // namespace detail
} // namespace gridfree

#endif
