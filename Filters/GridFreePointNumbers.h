// One batch's estimates as numbers, for a filter that uses them itself (the
// stream tracer steps along the gradient): the core's collected estimates
// (Problem::EstimateAll's BatchEstimates) and each point's distance to the
// boundary, read through the same rules as the output arrays
// (GridFreeEstimateArrays.h, GridFreeDerivativeArrays.h): a derivative a
// point lacks is 0 with DerivativeStatus Unavailable, axes beyond the
// problem's dimension are 0.
// Private to the GridFree::Filters module.
#ifndef GridFreePointNumbers_h
#define GridFreePointNumbers_h

#include <gridfree/problem/Problem.h>

#include <cmath>
#include <cstddef>
#include <vector>

namespace gridfree
{
struct PointNumbers
{
  BatchEstimates Batch;
  int Dimension = 3;
  int Components = 1;
  // The derivatives asked for: those a point can lack.
  DerivativeRequest Request = BatchRequest::NoDerivatives();
  // To the boundary (NaN at points with a coordinate that is not finite).
  std::vector<double> Distance;

  std::size_t Size() const { return this->Batch.Points; }
  double Value(std::size_t i, int c = 0) const { return this->Batch.Value(i, c); }
  double ValueVariance(std::size_t i, int c = 0) const { return this->Batch.ValueVariance(i, c); }
  bool HasGradient() const { return this->Request.Gradient; }

  // Interior, OneSided, or Unavailable: also for a finished point whose
  // derivative estimates are not all finite.
  DerivativeStatus Status(std::size_t i) const
  {
    if (!this->Batch.Finished[i] || this->DerivativesMissing(i))
    {
      return DerivativeStatus::Unavailable;
    }
    return this->Batch.Status[i];
  }

  // ∂u_c/∂x_a: 0 beyond the dimension and where the gradient is missing.
  double Gradient(std::size_t i, int c, int a) const
  {
    const int slot = this->GradientSlot(c, a);
    return slot < 0 ||
        this->Missing(i, this->Batch.Summary.Layout.Gradient, this->GradientSize(), this->Request.Gradient)
      ? 0.0
      : this->Batch.Mean(i, slot);
  }
  // Its variance of the mean: 0 beyond the dimension, NaN where unknown.
  double GradientVariance(std::size_t i, int c, int a) const
  {
    const int slot = this->GradientSlot(c, a);
    return slot < 0 ? 0.0 : this->Batch.Variance(i, slot);
  }

private:
  int GradientSlot(int c, int a) const
  {
    const int first = this->Batch.Summary.Layout.Gradient;
    return first < 0 || a >= this->Dimension ? -1 : first + c * this->Dimension + a;
  }
  int GradientSize() const { return this->Components * this->Dimension; }

  // Whether any of `count` slots from `first` is not finite (a group not
  // asked for, or absent from the layout, first < 0, is never missing).
  bool Missing(std::size_t i, int first, int count, bool asked = true) const
  {
    for (int s = 0; asked && first >= 0 && s < count; ++s)
    {
      if (!std::isfinite(this->Batch.Mean(i, first + s)))
      {
        return true;
      }
    }
    return false;
  }

  // As the output arrays: any derivative group (gradient, Hessian,
  // directional derivative, divergence, curl) not finite.
  bool DerivativesMissing(std::size_t i) const
  {
    const SampleLayout& layout = this->Batch.Summary.Layout;
    const int d = this->Dimension;
    const int nc = this->Components;
    const DerivativeRequest& r = this->Request;
    return this->Missing(i, layout.Gradient, nc * d, r.Gradient) ||
      this->Missing(i, layout.Hessian, nc * d * d, r.Hessian) ||
      this->Missing(i, layout.Directional, nc, r.Directional) ||
      this->Missing(i, layout.Divergence, 1, r.DivergenceCurl) ||
      this->Missing(i, layout.Curl, 3, r.DivergenceCurl);
  }
};
} // namespace gridfree

#endif
