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
//
// Trees of meshes step at mesh speed. A mesh operand's Value() searches its
// hierarchy and takes a sign, several times a mesh walk's relaxed, cached
// step. But at most points one operand alone decides the value: near the
// big sphere of union(big sphere, small sphere inside it) the small one is
// far away. Children that cache bounds (CachesBounds()) give a cheap
// interval for their value (Range()); when the intervals show that one
// child decides (union: a ≤ b everywhere in them, by at least k for a
// blend, where h = 1 and smin(a, b) = a exactly), φ(x) equals that child's
// normalized value, so any step bound of that child is one of φ
// (StepBound()), and the other child is never evaluated. Otherwise both are
// evaluated exactly, as before.
#ifndef GRIDFREE_IMPLICIT_CSG_FUNCTIONS_H
#define GRIDFREE_IMPLICIT_CSG_FUNCTIONS_H

#include <gridfree/implicit/CsgOperation.h>
#include <gridfree/geometry/BoundingBox.h>
#include <gridfree/implicit/SignedDistance.h>
#include <gridfree/math/Vector.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <stdexcept>

namespace gridfree
{
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
    this->Cached = this->ChildA->CachesBounds() || this->ChildB->CachesBounds();
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

  bool CachesBounds() const override { return this->Cached; }

  // The children's ranges combined: min and max are monotone, the smooth
  // minimum lies in [min − k/4, min] and the smooth maximum in
  // [max, max + k/4].
  ImplicitRange Range(const Vec<DIM>& x) const override
  {
    if (!this->Cached)
    {
      const double v = this->Value(x);
      return { v, v };
    }
    const ImplicitRange a = this->RangeA(x);
    const ImplicitRange b = this->RangeB(x);
    const double blend = 0.25 * this->BlendRadius;
    if (this->Operation == CsgOperation::Union)
    {
      return { std::min(a.Low, b.Low) - blend, std::min(a.High, b.High) };
    }
    return { std::max(a.Low, b.Low), std::max(a.High, b.High) + blend };
  }

  // A hard operation's zero set near x, where one child decides φ(x) (by
  // the ranges), is that child's zero set where the other child keeps the
  // point in (union: ψ_b ≥ 0 there; intersection: ψ_b ≤ 0). The child's
  // projection p is then on the tree's zero set at |φ(x)| from x, and so a
  // nearest point (none is nearer than |φ(x)|, φ being 1-Lipschitz).
  bool Project(const Vec<DIM>& x, Vec<DIM>& point, std::int64_t& part) const override
  {
    if (!this->Cached || this->BlendRadius > 0.0)
    {
      return false;
    }
    const bool union_ = this->Operation == CsgOperation::Union;
    ImplicitRange a = this->RangeA(x);
    ImplicitRange b = this->RangeB(x);
    const bool decided = a.High <= b.Low || b.High <= a.Low;
    const bool bothNegative = a.High < 0.0 && b.High < 0.0;
    const bool bothPositive = a.Low > 0.0 && b.Low > 0.0;
    if (!decided && (union_ ? bothPositive : bothNegative))
    {
      // x on one side of both surfaces, where the tree's value is the one
      // nearer 0 (union of positives, intersection of negatives): the
      // nearer surface decides, and the unsigned distances (no sign
      // needed) tell which. The other child keeps its sign within its
      // distance of x, so a projection nearer than that stays on the tree's
      // zero set.
      const double inf = std::numeric_limits<double>::infinity();
      const double da = a.Low == a.High ? std::abs(a.Low) : this->ChildA->StepBound(x, 0.0, inf);
      const double db = b.Low == b.High ? std::abs(b.Low) : this->ChildB->StepBound(x, 0.0, inf);
      if (da <= db && this->ChildA->Project(x, point, part))
      {
        return (x - point).norm() < db ||
          this->KeepsIn(this->RangeB(point), *this->ChildB, point, this->ScaleB);
      }
      if (db < da && this->ChildB->Project(x, point, part))
      {
        part += this->PartsA;
        return (x - point).norm() < da ||
          this->KeepsIn(this->RangeA(point), *this->ChildA, point, this->InverseLipschitzA);
      }
      return false;
    }
    if (!decided)
    {
      // The ranges cannot tell (near both operands): their exact values can.
      const double va = this->ChildA->Value(x) * this->InverseLipschitzA;
      const double vb = this->ChildB->Value(x) * this->ScaleB;
      a = { va, va };
      b = { vb, vb };
    }
    const bool aDecides = union_ ? a.High <= b.Low : b.High <= a.Low;
    const bool bDecides = !aDecides && (union_ ? b.High <= a.Low : a.High <= b.Low);
    if (aDecides && this->ChildA->Project(x, point, part))
    {
      return this->KeepsIn(this->RangeB(point), *this->ChildB, point, this->ScaleB);
    }
    if (bDecides && this->ChildB->Project(x, point, part))
    {
      part += this->PartsA;
      return this->KeepsIn(this->RangeA(point), *this->ChildA, point, this->InverseLipschitzA);
    }
    return false;
  }

  // The step bound of the child that decides φ(x), when the ranges show
  // one. Otherwise, for a hard operation on two values whose signs the
  // ranges tell alike (near both surfaces, on one side of both), |φ| is the
  // larger or the smaller of |ψa| and |ψb| (union of negatives or
  // intersection of positives: the larger), and so is the step from the two
  // children's step bounds: each lies in [|ψ| / (1 + relaxation), |ψ|], and
  // so do their maximum and minimum of the |ψ|'s; below epsilon the one
  // returned is exact (a bound below epsilon is exact, and the minimum is
  // below epsilon only if the smaller |ψ| is). Else |φ(x)|.
  double StepBound(const Vec<DIM>& x, double relaxation, double epsilon) const override
  {
    if (!this->Cached)
    {
      return std::abs(this->Value(x));
    }
    const ImplicitRange a = this->RangeA(x);
    const ImplicitRange b = this->RangeB(x);
    const double k = this->BlendRadius;
    const bool aBelow = a.High + k <= b.Low;
    const bool bBelow = b.High + k <= a.Low;
    const bool union_ = this->Operation == CsgOperation::Union;
    // A child's step bound is in units of |φ_a| / L_a = |ψ_a| already.
    auto stepA = [&]()
    { return a.Low == a.High ? std::abs(a.Low) : this->ChildA->StepBound(x, relaxation, epsilon); };
    auto stepB = [&]()
    { return b.Low == b.High ? std::abs(b.Low) : this->ChildB->StepBound(x, relaxation, epsilon); };
    // Union takes the lower child, intersection (and difference) the higher.
    if (union_ ? aBelow : bBelow)
    {
      return stepA();
    }
    if (union_ ? bBelow : aBelow)
    {
      return stepB();
    }
    const bool bothNegative = a.High < 0.0 && b.High < 0.0;
    const bool bothPositive = a.Low > 0.0 && b.Low > 0.0;
    if (k == 0.0 && (bothNegative || bothPositive))
    {
      const bool larger = union_ == bothNegative;
      return larger ? std::max(stepA(), stepB()) : std::min(stepA(), stepB());
    }
    return std::abs(this->Value(x));
  }

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

  // The children's ranges, normalized as in Value() (b negated for a
  // difference).
  ImplicitRange RangeA(const Vec<DIM>& x) const
  {
    const ImplicitRange r = this->ChildA->Range(x);
    return { r.Low * this->InverseLipschitzA, r.High * this->InverseLipschitzA };
  }
  ImplicitRange RangeB(const Vec<DIM>& x) const
  {
    const ImplicitRange r = this->ChildB->Range(x);
    const double low = r.Low * this->ScaleB;
    const double high = r.High * this->ScaleB;
    return this->ScaleB > 0.0 ? ImplicitRange{ low, high } : ImplicitRange{ high, low };
  }

  // Whether the other child keeps a point of the deciding child's zero set
  // on the tree's zero set (union: ψ ≥ 0, intersection: ψ ≤ 0), from its
  // range or else its exact value.
  bool KeepsIn(const ImplicitRange& range, const SignedDistanceFunction<DIM>& other,
    const Vec<DIM>& point, double scale) const
  {
    const bool union_ = this->Operation == CsgOperation::Union;
    if (union_ ? range.Low >= 0.0 : range.High <= 0.0)
    {
      return true;
    }
    if (union_ ? range.High < 0.0 : range.Low > 0.0)
    {
      return false;
    }
    const double v = other.Value(point) * scale;
    return union_ ? v >= 0.0 : v <= 0.0;
  }

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
  // Whether a child caches bounds, so that Range() and StepBound() pay.
  bool Cached = false;
};
} // namespace gridfree

#endif
