// Constructive solid geometry on implicit boundaries (paper "Monte Carlo
// Geometry Processing", Sec. 5.1.4): union, intersection and difference of
// two signed distance functions, hard or smoothly blended.
//
// Walk on spheres only needs a conservative distance, |φ(x)| ≤ the distance
// from x to the zero set of φ, and that holds for ANY 1-Lipschitz φ: if z is
// on the zero set, |φ(x)| = |φ(x) − φ(z)| ≤ |x − z|, and taking the nearest
// such z gives the distance. So the operators below are built to keep the
// Lipschitz constant at 1, not to be exact distances (after a hard
// intersection or difference, or any blend, they are not):
//
// * Each child φ_i is first divided by its own Lipschitz constant L_i, so
//   ψ_i = φ_i / L_i is 1-Lipschitz even when the child is not a distance.
// * min and max of 1-Lipschitz functions are 1-Lipschitz: moving x by δ moves
//   each argument by at most δ, and so the smaller (larger) of them.
// * The smooth minimum of radius k (the polynomial smooth minimum described
//   by Quilez): with h = clamp(1/2 + (b − a)/(2k), 0, 1),
//     smin(a, b) = h a + (1 − h) b − k h (1 − h),
//   and smax(a, b) = −smin(−a, −b). In the blend band |a − b| < k, write
//   b − a = k (2h − 1); differentiating with ∂h/∂a = −1/(2k) the terms in
//   ∂h cancel, (a − b) ∂h/∂a − k (1 − 2h) ∂h/∂a = 0, so
//     ∂smin/∂a = h,  ∂smin/∂b = 1 − h
//   there, and trivially outside the band (h is 0 or 1 and smin is b or a).
//   The partial derivatives are non-negative and sum to 1, so along any path
//   |Δ smin| ≤ max(|Δa|, |Δb|) ≤ |Δx|: smin is 1-Lipschitz whenever a and b
//   are, and ∇smin = h ∇a + (1 − h) ∇b. The same holds for smax with its own
//   weight. Differentiability of the children is never needed.
//
// Hence Lipschitz() is always 1, and DistanceBound() is safe for any tree.
//
// Sample() reports the leaf that decides the value, which a boundary uses to
// pick the boundary condition of that part: parts of a keep their numbers
// 0 … nA − 1, parts of b follow as nA … nA + nB − 1. In a blend the child with
// the larger weight decides (h ≥ 1/2 → a).
//
// Cost: Value() is called once per walk step, so it makes exactly one virtual
// call per child, allocates nothing, and branches only on the operation.
#ifndef GRIDFREE_IMPLICIT_CSG_FUNCTIONS_H
#define GRIDFREE_IMPLICIT_CSG_FUNCTIONS_H

#include <gridfree/geometry/BoundingBox.h>
#include <gridfree/implicit/SignedDistance.h>
#include <gridfree/math/Vector.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <stdexcept>

namespace gridfree
{
enum class CsgOperation
{
  Union,
  Intersection,
  Difference
};

template <int DIM>
class CsgDistance final : public SignedDistanceFunction<DIM>
{
public:
  using ChildPointer = std::shared_ptr<const SignedDistanceFunction<DIM>>;

  CsgDistance(CsgOperation op, ChildPointer a, ChildPointer b, double blendRadius = 0.0)
    : Operation(op)
    , ChildA(std::move(a))
    , ChildB(std::move(b))
    , BlendRadius(blendRadius)
  {
    if (!this->ChildA || !this->ChildB)
    {
      throw std::invalid_argument("CsgDistance: children must not be null");
    }
    if (!(blendRadius >= 0.0) || !std::isfinite(blendRadius))
    {
      throw std::invalid_argument("CsgDistance: blend radius must be finite and non-negative");
    }
    if (op != CsgOperation::Union && op != CsgOperation::Intersection &&
      op != CsgOperation::Difference)
    {
      throw std::invalid_argument("CsgDistance: unknown operation");
    }
    const double la = this->ChildA->Lipschitz();
    const double lb = this->ChildB->Lipschitz();
    if (!(la > 0.0) || !std::isfinite(la) || !(lb > 0.0) || !std::isfinite(lb))
    {
      throw std::invalid_argument("CsgDistance: children need a positive, finite Lipschitz bound");
    }
    this->InverseLipschitzA = 1.0 / la;
    // A difference intersects a with the complement of b: fold the sign of
    // −b into its scale so that Value() has no extra branch.
    this->ScaleB = (op == CsgOperation::Difference ? -1.0 : 1.0) / lb;
    this->PartsA = this->ChildA->NumberOfParts();
    this->PartsB = this->ChildB->NumberOfParts();
  }

  double Value(const Vec<DIM>& x) const override
  {
    return this
      ->Combine(this->ChildA->Value(x) * this->InverseLipschitzA, this->ChildB->Value(x) * this->ScaleB)
      .Value;
  }

  ImplicitSample Sample(const Vec<DIM>& x) const override
  {
    const ImplicitSample sa = this->ChildA->Sample(x);
    const ImplicitSample sb = this->ChildB->Sample(x);
    const Blend blend =
      this->Combine(sa.value * this->InverseLipschitzA, sb.value * this->ScaleB);
    if (blend.WeightA >= 0.5)
    {
      return { blend.Value, sa.part };
    }
    return { blend.Value, this->PartsA + sb.part };
  }

  Vec<DIM> Gradient(const Vec<DIM>& x) const override
  {
    const double wa =
      this->Combine(this->ChildA->Value(x) * this->InverseLipschitzA, this->ChildB->Value(x) * this->ScaleB)
        .WeightA;
    // Outside a blend band only one child matters: skip the other gradient.
    if (wa >= 1.0)
    {
      return this->InverseLipschitzA * this->ChildA->Gradient(x);
    }
    if (wa <= 0.0)
    {
      return this->ScaleB * this->ChildB->Gradient(x);
    }
    return (wa * this->InverseLipschitzA) * this->ChildA->Gradient(x) +
      ((1.0 - wa) * this->ScaleB) * this->ChildB->Gradient(x);
  }

  double Lipschitz() const override { return 1.0; }

  std::int64_t NumberOfParts() const override { return this->PartsA + this->PartsB; }

  // A box around the zero set, assuming (as for any solid) that each bounded
  // child is negative only inside its own box:
  // * union: the union of the boxes. A blend lowers the value by at most
  //   k/4 (the maximum of k h (1 − h)), so the zero set lies where
  //   min(ψa, ψb) ≤ k/4; for exact-distance children that is within k/4 of
  //   the boxes. (For children far below the distance outside their boxes
  //   the blend can reach further; such children are not supported here.)
  // * intersection: smax ≥ max, so the zero set stays inside both solids.
  //   Disjoint boxes give the empty box.
  // * difference: smax(ψa, −ψb) ≥ ψa, so it stays inside a.
  // An empty (unbounded) child makes a union unbounded; an intersection is
  // bounded by its bounded child.
  BoundingBox<DIM> Bounds() const override
  {
    const BoundingBox<DIM> ba = this->ChildA->Bounds();
    switch (this->Operation)
    {
      case CsgOperation::Union:
      {
        const BoundingBox<DIM> bb = this->ChildB->Bounds();
        if (ba.IsEmpty() || bb.IsEmpty())
        {
          return BoundingBox<DIM>();
        }
        BoundingBox<DIM> box = ba;
        box.Expand(bb);
        const Vec<DIM> margin = Vec<DIM>::Constant(0.25 * this->BlendRadius);
        return BoundingBox<DIM>(box.Min - margin, box.Max + margin);
      }
      case CsgOperation::Intersection:
      {
        const BoundingBox<DIM> bb = this->ChildB->Bounds();
        if (ba.IsEmpty())
        {
          return bb;
        }
        if (bb.IsEmpty())
        {
          return ba;
        }
        const BoundingBox<DIM> box(ba.Min.cwiseMax(bb.Min), ba.Max.cwiseMin(bb.Max));
        return box.IsEmpty() ? BoundingBox<DIM>() : box;
      }
      case CsgOperation::Difference:
      default:
        return ba;
    }
  }

  CsgOperation GetOperation() const { return this->Operation; }
  double GetBlendRadius() const { return this->BlendRadius; }
  const ChildPointer& GetChildA() const { return this->ChildA; }
  const ChildPointer& GetChildB() const { return this->ChildB; }

private:
  // The combined value and the weight of a in it (1 or 0 for hard ops).
  struct Blend
  {
    double Value;
    double WeightA;
  };

  // The smooth minimum above; h is the weight of a.
  static Blend SmoothMin(double a, double b, double k)
  {
    const double h = std::clamp(0.5 + 0.5 * (b - a) / k, 0.0, 1.0);
    return { b + h * (a - b) - k * h * (1.0 - h), h };
  }

  // a, b already normalized (and b negated for a difference).
  Blend Combine(double a, double b) const
  {
    const double k = this->BlendRadius;
    if (this->Operation == CsgOperation::Union)
    {
      if (k > 0.0)
      {
        return SmoothMin(a, b, k);
      }
      return a <= b ? Blend{ a, 1.0 } : Blend{ b, 0.0 };
    }
    // Intersection, and difference as the intersection with −b.
    if (k > 0.0)
    {
      const Blend m = SmoothMin(-a, -b, k);
      return { -m.Value, m.WeightA };
    }
    return a >= b ? Blend{ a, 1.0 } : Blend{ b, 0.0 };
  }

  CsgOperation Operation;
  ChildPointer ChildA;
  ChildPointer ChildB;
  double BlendRadius;
  double InverseLipschitzA = 1.0;
  double ScaleB = 1.0;
  std::int64_t PartsA = 1;
  std::int64_t PartsB = 1;
};
} // namespace gridfree

#endif
