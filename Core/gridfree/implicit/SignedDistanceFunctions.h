// Exact signed distance functions of simple solids: the leaves of implicit
// boundaries and CSG trees (CsgFunctions.h).
//
// Each function here is the true signed Euclidean distance to its surface,
// inside and outside, so its Lipschitz constant is exactly 1 and the empty
// ball |φ(x)| around x is as large as it can be: walk on spheres takes the
// longest possible steps, and near the surface x − φ(x) ∇φ(x) is the closest
// surface point. The gradients are analytic: the closest-point projection
// and the boundary normals depend on them, and finite differences would be
// both slower and wrong near edges. Where φ is not differentiable (centers,
// medial axes, the core circle of a torus) any unit vector is returned, so
// callers never see NaN.
//
// Bounds() is the tight axis-aligned box of the zero set; it is empty for the
// unbounded half-space, as the interface asks.
#ifndef GRIDFREE_IMPLICIT_SIGNED_DISTANCE_FUNCTIONS_H
#define GRIDFREE_IMPLICIT_SIGNED_DISTANCE_FUNCTIONS_H

#include <gridfree/geometry/BoundingBox.h>
#include <gridfree/implicit/SignedDistance.h>
#include <gridfree/math/Vector.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace gridfree
{
namespace detail
{
template <int DIM>
void RequireFinite(const Vec<DIM>& v, const char* what)
{
  if (!v.allFinite())
  {
    throw std::invalid_argument(std::string(what) + " must be finite");
  }
}

inline void RequirePositive(double value, const char* what)
{
  if (!(value > 0.0) || !std::isfinite(value))
  {
    throw std::invalid_argument(std::string(what) + " must be positive and finite");
  }
}

// v / |v|, refusing zero and non-finite vectors. stableNorm() so that tiny
// but valid directions (components near 1e-200) are not taken for zero.
template <int DIM>
Vec<DIM> RequireDirection(const Vec<DIM>& v, const char* what)
{
  RequireFinite<DIM>(v, what);
  const double length = v.stableNorm();
  if (!(length > 0.0) || !std::isfinite(length))
  {
    throw std::invalid_argument(std::string(what) + " must be a non-zero direction");
  }
  return v / length;
}

// The direction returned where φ has no gradient.
template <int DIM>
Vec<DIM> AnyUnitVector()
{
  return Vec<DIM>::Unit(0);
}

// A unit vector orthogonal to the non-zero vector u. In 3D, crossing with
// the axis u is least aligned with keeps the result well conditioned.
template <int DIM>
Vec<DIM> PerpendicularUnit(const Vec<DIM>& u)
{
  if constexpr (DIM == 2)
  {
    return Vec2(-u[1], u[0]).normalized();
  }
  else
  {
    int axis = 0;
    u.cwiseAbs().minCoeff(&axis);
    return u.cross(Vec3::Unit(axis)).normalized();
  }
}

// The part of d orthogonal to the unit vector u, by two Gram–Schmidt passes.
// On the axis the first pass leaves only rounding noise, which may point
// anywhere, along u included; the second pass makes the noise orthogonal,
// so that a radial direction taken from it is still a valid one.
inline Vec3 RadialPart(const Vec3& d, const Vec3& u)
{
  Vec3 radial = d - d.dot(u) * u;
  radial -= radial.dot(u) * u;
  return radial;
}

// Signed distance from offset d (point minus center) to the box
// [−half, half]. Outside, the distance to the box is the length of the
// positive part of |d| − half; inside, the nearest face is the one with the
// largest (least negative) gap. Both terms are zero on the surface, so the
// two formulas add without a branch.
template <int DIM>
double BoxValue(const Vec<DIM>& d, const Vec<DIM>& half)
{
  const Vec<DIM> q = d.cwiseAbs() - half;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

template <int DIM>
Vec<DIM> BoxGradient(const Vec<DIM>& d, const Vec<DIM>& half)
{
  const Vec<DIM> q = d.cwiseAbs() - half;
  Vec<DIM> g = q.cwiseMax(0.0);
  const double outside = g.norm();
  if (outside > 0.0)
  {
    // Outside: from the closest box point towards x (signs restored per axis).
    for (int i = 0; i < DIM; ++i)
    {
      g[i] = std::copysign(g[i] / outside, d[i]);
    }
    return g;
  }
  // Inside or on the surface: the normal of the nearest face. Ties (the
  // medial planes) have no gradient; the first axis is as good as any.
  int axis = 0;
  q.maxCoeff(&axis);
  g.setZero();
  g[axis] = d[axis] < 0.0 ? -1.0 : 1.0;
  return g;
}
} // namespace detail

//------------------------------------------------------------------------------
// Ball (disk in 2D): φ(x) = |x − c| − r.
template <int DIM>
class SphereDistance final : public SignedDistanceFunction<DIM>
{
public:
  SphereDistance(const Vec<DIM>& center, double radius)
    : Center(center)
    , Radius(radius)
  {
    detail::RequireFinite<DIM>(center, "SphereDistance: center");
    detail::RequirePositive(radius, "SphereDistance: radius");
  }

  double Value(const Vec<DIM>& x) const override { return (x - this->Center).norm() - this->Radius; }

  Vec<DIM> Gradient(const Vec<DIM>& x) const override
  {
    const Vec<DIM> d = x - this->Center;
    const double length = d.norm();
    return length > 0.0 ? Vec<DIM>(d / length) : detail::AnyUnitVector<DIM>();
  }

  BoundingBox<DIM> Bounds() const override
  {
    const Vec<DIM> r = Vec<DIM>::Constant(this->Radius);
    return BoundingBox<DIM>(this->Center - r, this->Center + r);
  }

  const Vec<DIM>& GetCenter() const { return this->Center; }
  double GetRadius() const { return this->Radius; }

private:
  Vec<DIM> Center;
  double Radius;
};

//------------------------------------------------------------------------------
// Axis-aligned box [c − h, c + h], exact inside and outside.
template <int DIM>
class BoxDistance final : public SignedDistanceFunction<DIM>
{
public:
  BoxDistance(const Vec<DIM>& center, const Vec<DIM>& halfExtents)
    : Center(center)
    , HalfExtents(halfExtents)
  {
    detail::RequireFinite<DIM>(center, "BoxDistance: center");
    for (int i = 0; i < DIM; ++i)
    {
      detail::RequirePositive(halfExtents[i], "BoxDistance: half extent");
    }
  }

  double Value(const Vec<DIM>& x) const override
  {
    return detail::BoxValue<DIM>(x - this->Center, this->HalfExtents);
  }

  Vec<DIM> Gradient(const Vec<DIM>& x) const override
  {
    return detail::BoxGradient<DIM>(x - this->Center, this->HalfExtents);
  }

  BoundingBox<DIM> Bounds() const override
  {
    return BoundingBox<DIM>(this->Center - this->HalfExtents, this->Center + this->HalfExtents);
  }

  const Vec<DIM>& GetCenter() const { return this->Center; }
  const Vec<DIM>& GetHalfExtents() const { return this->HalfExtents; }

private:
  Vec<DIM> Center;
  Vec<DIM> HalfExtents;
};

//------------------------------------------------------------------------------
// Box with rounded edges and corners, of outer half extents h: the inner box
// of half extents h − ρ grown by a ball of radius ρ. Growing a convex set by
// ρ adds ρ to the distance everywhere, inside included (the support function
// grows by ρ in every direction), so φ = box(h − ρ) − ρ stays exact. ρ is
// clamped to [0, min h]: at the upper end the inner box is flat along its
// thinnest axis, which the box formula handles as is.
template <int DIM>
class RoundedBoxDistance final : public SignedDistanceFunction<DIM>
{
public:
  RoundedBoxDistance(const Vec<DIM>& center, const Vec<DIM>& halfExtents, double rounding)
    : Center(center)
    , HalfExtents(halfExtents)
  {
    detail::RequireFinite<DIM>(center, "RoundedBoxDistance: center");
    for (int i = 0; i < DIM; ++i)
    {
      detail::RequirePositive(halfExtents[i], "RoundedBoxDistance: half extent");
    }
    if (!std::isfinite(rounding))
    {
      throw std::invalid_argument("RoundedBoxDistance: rounding must be finite");
    }
    this->Rounding = std::clamp(rounding, 0.0, halfExtents.minCoeff());
    this->InnerHalfExtents = (halfExtents.array() - this->Rounding).cwiseMax(0.0);
  }

  double Value(const Vec<DIM>& x) const override
  {
    return detail::BoxValue<DIM>(x - this->Center, this->InnerHalfExtents) - this->Rounding;
  }

  Vec<DIM> Gradient(const Vec<DIM>& x) const override
  {
    return detail::BoxGradient<DIM>(x - this->Center, this->InnerHalfExtents);
  }

  BoundingBox<DIM> Bounds() const override
  {
    return BoundingBox<DIM>(this->Center - this->HalfExtents, this->Center + this->HalfExtents);
  }

  const Vec<DIM>& GetCenter() const { return this->Center; }
  const Vec<DIM>& GetHalfExtents() const { return this->HalfExtents; }
  // The rounding radius after clamping.
  double GetRounding() const { return this->Rounding; }

private:
  Vec<DIM> Center;
  Vec<DIM> HalfExtents;
  Vec<DIM> InnerHalfExtents;
  double Rounding = 0.0;
};

//------------------------------------------------------------------------------
// Capsule: the segment a–b swept by a ball of radius r. a = b is allowed (a
// ball).
template <int DIM>
class CapsuleDistance final : public SignedDistanceFunction<DIM>
{
public:
  CapsuleDistance(const Vec<DIM>& a, const Vec<DIM>& b, double radius)
    : A(a)
    , B(b)
    , Radius(radius)
  {
    detail::RequireFinite<DIM>(a, "CapsuleDistance: a");
    detail::RequireFinite<DIM>(b, "CapsuleDistance: b");
    detail::RequirePositive(radius, "CapsuleDistance: radius");
    const double length2 = (b - a).squaredNorm();
    this->InverseLength2 = length2 > 0.0 ? 1.0 / length2 : 0.0;
    this->Perpendicular = length2 > 0.0 ? detail::PerpendicularUnit<DIM>(b - a)
                                        : detail::AnyUnitVector<DIM>();
  }

  double Value(const Vec<DIM>& x) const override
  {
    return (x - this->ClosestOnAxis(x)).norm() - this->Radius;
  }

  Vec<DIM> Gradient(const Vec<DIM>& x) const override
  {
    const Vec<DIM> ab = this->B - this->A;
    const double t = std::clamp((x - this->A).dot(ab) * this->InverseLength2, 0.0, 1.0);
    Vec<DIM> d = x - (this->A + t * ab);
    if (t > 0.0 && t < 1.0)
    {
      // Exactly orthogonal to the axis in exact arithmetic; removing the
      // rounding along it keeps x − φ∇φ on the surface near the axis.
      d -= (d.dot(ab) * this->InverseLength2) * ab;
    }
    const double length = d.norm();
    // On the segment every direction orthogonal to it reaches a closest
    // surface point.
    return length > 0.0 ? Vec<DIM>(d / length) : this->Perpendicular;
  }

  BoundingBox<DIM> Bounds() const override
  {
    // The end balls reach ±r along every axis, so this box is tight.
    const Vec<DIM> r = Vec<DIM>::Constant(this->Radius);
    return BoundingBox<DIM>(this->A.cwiseMin(this->B) - r, this->A.cwiseMax(this->B) + r);
  }

  const Vec<DIM>& GetA() const { return this->A; }
  const Vec<DIM>& GetB() const { return this->B; }
  double GetRadius() const { return this->Radius; }

private:
  Vec<DIM> ClosestOnAxis(const Vec<DIM>& x) const
  {
    const Vec<DIM> ab = this->B - this->A;
    const double t = std::clamp((x - this->A).dot(ab) * this->InverseLength2, 0.0, 1.0);
    return this->A + t * ab;
  }

  Vec<DIM> A;
  Vec<DIM> B;
  Vec<DIM> Perpendicular;
  double Radius;
  double InverseLength2 = 0.0;
};

//------------------------------------------------------------------------------
// Half-space {(x − p)·n ≤ 0}: the normal points outside. Unbounded, so
// Bounds() is empty; use it inside an intersection or difference.
template <int DIM>
class PlaneDistance final : public SignedDistanceFunction<DIM>
{
public:
  PlaneDistance(const Vec<DIM>& point, const Vec<DIM>& normal)
    : Point(point)
  {
    detail::RequireFinite<DIM>(point, "PlaneDistance: point");
    this->Normal = detail::RequireDirection<DIM>(normal, "PlaneDistance: normal");
  }

  double Value(const Vec<DIM>& x) const override { return (x - this->Point).dot(this->Normal); }

  Vec<DIM> Gradient(const Vec<DIM>&) const override { return this->Normal; }

  BoundingBox<DIM> Bounds() const override { return BoundingBox<DIM>(); }

  const Vec<DIM>& GetPoint() const { return this->Point; }
  // The unit normal.
  const Vec<DIM>& GetNormal() const { return this->Normal; }

private:
  Vec<DIM> Point;
  Vec<DIM> Normal;
};

//------------------------------------------------------------------------------
// Torus (3D): the circle of radius R around `axis` through c, swept by a ball
// of radius r. The distance to that circle is exact, so φ = dist − r is exact
// outside; inside it is exact only if the tube does not overlap itself,
// hence r ≤ R is required (a spindle torus, r > R, would be rejected rather
// than given a φ that is merely a lower bound).
class TorusDistance final : public SignedDistanceFunction<3>
{
public:
  TorusDistance(const Vec3& center, const Vec3& axis, double majorRadius, double minorRadius)
    : Center(center)
    , MajorRadius(majorRadius)
    , MinorRadius(minorRadius)
  {
    detail::RequireFinite<3>(center, "TorusDistance: center");
    this->Axis = detail::RequireDirection<3>(axis, "TorusDistance: axis");
    detail::RequirePositive(majorRadius, "TorusDistance: major radius");
    detail::RequirePositive(minorRadius, "TorusDistance: minor radius");
    if (minorRadius > majorRadius)
    {
      throw std::invalid_argument("TorusDistance: minor radius must not exceed the major radius");
    }
    this->Perpendicular = detail::PerpendicularUnit<3>(this->Axis);
  }

  double Value(const Vec3& x) const override
  {
    const Vec3 d = x - this->Center;
    const double z = d.dot(this->Axis);
    const double rho = (d - z * this->Axis).norm();
    return std::hypot(rho - this->MajorRadius, z) - this->MinorRadius;
  }

  Vec3 Gradient(const Vec3& x) const override
  {
    const Vec3 d = x - this->Center;
    const Vec3 radial = detail::RadialPart(d, this->Axis);
    const double rho = radial.norm();
    // On the axis every circle point is closest: any radial direction will do.
    const Vec3 e = rho > 0.0 ? Vec3(radial / rho) : this->Perpendicular;
    const Vec3 away = d - this->MajorRadius * e;
    const double length = away.norm();
    return length > 0.0 ? Vec3(away / length) : e;
  }

  BoundingBox<3> Bounds() const override
  {
    // The circle reaches R·sqrt(1 − u_k²) along axis k; the tube adds r.
    Vec3 half;
    for (int k = 0; k < 3; ++k)
    {
      const double s = std::sqrt(std::max(0.0, 1.0 - this->Axis[k] * this->Axis[k]));
      half[k] = this->MajorRadius * s + this->MinorRadius;
    }
    return BoundingBox<3>(this->Center - half, this->Center + half);
  }

  const Vec3& GetCenter() const { return this->Center; }
  // The unit axis.
  const Vec3& GetAxis() const { return this->Axis; }
  double GetMajorRadius() const { return this->MajorRadius; }
  double GetMinorRadius() const { return this->MinorRadius; }

private:
  Vec3 Center;
  Vec3 Axis;
  Vec3 Perpendicular;
  double MajorRadius;
  double MinorRadius;
};

//------------------------------------------------------------------------------
// Capped cylinder (3D): radius r around `axis` through c, |z| ≤ halfHeight.
// A solid of revolution: its distance is the 2D distance, in the meridian
// half-plane (ρ, z), to the rectangle [−r, r] × [−H, H], which the box
// formula gives exactly, rim edges included.
class CylinderDistance final : public SignedDistanceFunction<3>
{
public:
  CylinderDistance(const Vec3& center, const Vec3& axis, double radius, double halfHeight)
    : Center(center)
    , Radius(radius)
    , HalfHeight(halfHeight)
  {
    detail::RequireFinite<3>(center, "CylinderDistance: center");
    this->Axis = detail::RequireDirection<3>(axis, "CylinderDistance: axis");
    detail::RequirePositive(radius, "CylinderDistance: radius");
    detail::RequirePositive(halfHeight, "CylinderDistance: half height");
    this->Perpendicular = detail::PerpendicularUnit<3>(this->Axis);
  }

  double Value(const Vec3& x) const override
  {
    const Vec3 d = x - this->Center;
    const double z = d.dot(this->Axis);
    const Vec2 meridian((d - z * this->Axis).norm(), z);
    return detail::BoxValue<2>(meridian, Vec2(this->Radius, this->HalfHeight));
  }

  Vec3 Gradient(const Vec3& x) const override
  {
    const Vec3 d = x - this->Center;
    const double z = d.dot(this->Axis);
    const Vec3 radial = detail::RadialPart(d, this->Axis);
    const double rho = radial.norm();
    const Vec2 g =
      detail::BoxGradient<2>(Vec2(rho, z), Vec2(this->Radius, this->HalfHeight));
    // ρ = 0 only matters on the axis inside, a medial point: any radial
    // direction will do.
    const Vec3 e = rho > 0.0 ? Vec3(radial / rho) : this->Perpendicular;
    return g[0] * e + g[1] * this->Axis;
  }

  BoundingBox<3> Bounds() const override
  {
    // The cap disks reach r·sqrt(1 − u_k²) along axis k, the axis H|u_k|.
    Vec3 half;
    for (int k = 0; k < 3; ++k)
    {
      const double s = std::sqrt(std::max(0.0, 1.0 - this->Axis[k] * this->Axis[k]));
      half[k] = this->HalfHeight * std::abs(this->Axis[k]) + this->Radius * s;
    }
    return BoundingBox<3>(this->Center - half, this->Center + half);
  }

  const Vec3& GetCenter() const { return this->Center; }
  // The unit axis.
  const Vec3& GetAxis() const { return this->Axis; }
  double GetRadius() const { return this->Radius; }
  double GetHalfHeight() const { return this->HalfHeight; }

private:
  Vec3 Center;
  Vec3 Axis;
  Vec3 Perpendicular;
  double Radius;
  double HalfHeight;
};
} // namespace gridfree

#endif
