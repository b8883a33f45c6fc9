// The point arrays of one batch of estimates, named as the solver's output:
// the solution `T` and `T_Variance` (and the biharmonic `T_Laplacian`), the
// error bar's reliability, the walk counters, `BoundaryDistance`,
// `T_ClosestBoundaryValue` and the derivative arrays. Filled point by point
// from each point's running statistics (from worker threads, each point
// once), then handed to the output in one go.
// Private to the GridFree::Filters module.
#ifndef GridFreeEstimateArrays_h
#define GridFreeEstimateArrays_h

#include "GridFreeArrays.h"
#include "GridFreeDerivativeArrays.h"
#include "vtkDoubleArray.h"
#include "vtkIntArray.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"

#include <gridfree/cache/BoundaryValueCache.h>
#include <gridfree/problem/Problem.h>
#include <gridfree/statistics/ErrorBarReliability.h>
#include <gridfree/statistics/RunningStatistics.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <string>

namespace gridfree
{
struct EstimateArrays
{
  int Components = 1;
  bool Biharmonic = false;
  bool AnyDerivative = false;
  vtkSmartPointer<vtkDoubleArray> Mean, Variance, Laplacian, LaplacianVariance;
  // Whether each point's error bar can be trusted (ErrorBarReliability.h):
  // 1 or 0 (0 also for points an abort left out), and the variance's own
  // relative standard error, which says how far to trust it.
  vtkSmartPointer<vtkUnsignedCharArray> Reliable;
  vtkSmartPointer<vtkDoubleArray> VarianceError;
  vtkSmartPointer<vtkDoubleArray> Steps, Escaped, Truncated;
  // The walks each point took: in the output with a target (points stop
  // at different counts) and after an abort (points hold what they ran).
  vtkSmartPointer<vtkIntArray> WalkCount;
  // The distance from each point to the boundary (a lower bound for an
  // implicit boundary): where a walk starts, and how far a streamline may
  // step without crossing the boundary.
  vtkSmartPointer<vtkDoubleArray> Distance;
  // The boundary value at the closest boundary point: what a walk started
  // here would return if it ended at once. It is the "albedo" a denoiser is
  // guided by (paper Sec. 5.2.4): the solution's sharp features follow its
  // jumps, where the closest point switches between distant boundary parts.
  vtkSmartPointer<vtkDoubleArray> ClosestValue;
  DerivativeArrays Derivatives;
  // A cache estimator: 1 where the cache answered, 0 where walks did.
  vtkSmartPointer<vtkUnsignedCharArray> FromCache;
  // Points whose error bar is unreliable because their screening weights
  // are uneven, and because their walks (all, or all but one) agreed.
  std::atomic<std::int64_t> UnevenWeights{ 0 }, OneWalkSpread{ 0 };

  void Allocate(const std::string& name, int nc, vtkIdType n, bool biharmonic,
    const DerivativeRequest& request)
  {
    this->Components = nc;
    this->Biharmonic = biharmonic;
    this->Mean = MakeArray(name, nc, n);
    this->Variance = MakeArray(name + "_Variance", nc, n);
    if (biharmonic)
    {
      this->Laplacian = MakeArray(name + "_Laplacian", nc, n);
      this->LaplacianVariance = MakeArray(name + "_Laplacian_Variance", nc, n);
    }
    this->Reliable = vtkSmartPointer<vtkUnsignedCharArray>::New();
    this->Reliable->SetName((name + "_VarianceReliable").c_str());
    this->Reliable->SetNumberOfTuples(n);
    this->Reliable->Fill(0);
    this->VarianceError = MakeArray(name + "_VarianceRelativeError", 1, n);
    this->Steps = MakeArray("WalkSteps", 1, n);
    this->Escaped = MakeArray("EscapedFraction", 1, n);
    this->Truncated = MakeArray("TruncatedFraction", 1, n);
    this->Distance = MakeArray("BoundaryDistance", 1, n);
    this->ClosestValue = MakeArray(name + "_ClosestBoundaryValue", nc, n);
    this->WalkCount = vtkSmartPointer<vtkIntArray>::New();
    this->WalkCount->SetName("WalkCount");
    this->WalkCount->SetNumberOfTuples(n);
    this->WalkCount->Fill(0);
    this->AnyDerivative = request.Gradient || request.Hessian || request.Directional;
    if (this->AnyDerivative)
    {
      this->Derivatives.Allocate(name, nc, n, request);
    }
  }

  // One finished point's statistics (called for distinct points at once
  // from worker threads).
  template <int DIM>
  void Store(std::size_t at, const RunningStatistics& stats, const WalkCounters& counters,
    const SampleLayout& layout, const ErrorBarCheck& check, DerivativeStatus status)
  {
    const auto i = static_cast<vtkIdType>(at);
    const int nc = this->Components;
    for (int c = 0; c < nc; ++c)
    {
      this->Mean->SetValue(i * nc + c, stats.GetMean(layout.Value + c));
      this->Variance->SetValue(i * nc + c, stats.VarianceOfMean(layout.Value + c));
      if (this->Biharmonic)
      {
        this->Laplacian->SetValue(i * nc + c, stats.GetMean(layout.Laplacian + c));
        this->LaplacianVariance->SetValue(i * nc + c, stats.VarianceOfMean(layout.Laplacian + c));
      }
    }
    this->Reliable->SetValue(i, check.Reliable ? 1 : 0);
    this->VarianceError->SetValue(i, check.VarianceRelativeError);
    // The reasons of unreliable points only (uneven weights that the walk
    // values' bounds clear are no reason).
    if (!check.Reliable)
    {
      (check.UnevenWeights ? this->UnevenWeights : this->OneWalkSpread)
        .fetch_add(1, std::memory_order_relaxed);
    }
    this->Steps->SetValue(i, counters.MeanSteps());
    this->WalkCount->SetValue(
      i, static_cast<int>(std::min<std::uint64_t>(counters.Walks, VTK_INT_MAX)));
    this->Escaped->SetValue(i, counters.EscapedFraction());
    this->Truncated->SetValue(i, counters.TruncatedFraction());
    if (this->AnyDerivative)
    {
      this->Derivatives.Store<DIM>(at, stats, layout, nc, static_cast<int>(status));
    }
  }

  // A cache's answers (GridFreeCacheAnswers.h) at the points it answered:
  // no walks, an error bar of relative error `varianceError`.
  template <int DIM>
  void StoreCached(const CacheEvaluation& e, double varianceError)
  {
    const int nc = this->Components;
    this->FromCache = vtkSmartPointer<vtkUnsignedCharArray>::New();
    this->FromCache->SetName("FromBoundaryCache");
    this->FromCache->SetNumberOfTuples(this->Mean->GetNumberOfTuples());
    this->FromCache->Fill(0);
    for (vtkIdType i = 0; i < this->Mean->GetNumberOfTuples(); ++i)
    {
      if (!std::isfinite(e.Value[static_cast<std::size_t>(i * nc)]))
      {
        continue;
      }
      this->FromCache->SetValue(i, 1);
      for (int c = 0; c < nc; ++c)
      {
        this->Mean->SetValue(i * nc + c, e.Value[static_cast<std::size_t>(i * nc + c)]);
        this->Variance->SetValue(i * nc + c, e.ValueVariance[static_cast<std::size_t>(i * nc + c)]);
      }
      this->Reliable->SetValue(i, 1);
      this->VarianceError->SetValue(i, varianceError);
      this->Steps->SetValue(i, 0.0);
      this->WalkCount->SetValue(i, 0);
      this->Escaped->SetValue(i, 0.0);
      this->Truncated->SetValue(i, 0.0);
      if (this->AnyDerivative)
      {
        if (!e.Gradient.empty())
        {
          this->Derivatives.StoreGradient<DIM>(i, e.Gradient, e.GradientVariance, nc);
        }
        if (!e.Hessian.empty())
        {
          this->Derivatives.StoreHessian<DIM>(i, e.Hessian, e.HessianVariance, nc);
        }
        if (!e.Directional.empty())
        {
          this->Derivatives.StoreDirectional(i, e.Directional, e.DirectionalVariance, nc);
        }
        if (!e.Divergence.empty())
        {
          this->Derivatives.StoreDivergenceCurl(
            i, e.Divergence, e.DivergenceVariance, e.Curl, e.CurlVariance);
        }
      }
    }
  }

  // Derivatives a point lacks become 0 (their DerivativeStatus says so).
  void Finish()
  {
    if (this->AnyDerivative)
    {
      this->Derivatives.ZeroWhereMissing();
    }
  }

  // Adds the arrays to `pd` (WalkCount only when points may differ in their
  // walks), the solution as the active scalars, finished.
  void AddTo(vtkPointData* pd, bool withWalkCount)
  {
    pd->AddArray(this->Mean);
    pd->AddArray(this->Variance);
    if (this->Biharmonic)
    {
      pd->AddArray(this->Laplacian);
      pd->AddArray(this->LaplacianVariance);
    }
    pd->AddArray(this->Reliable);
    pd->AddArray(this->VarianceError);
    pd->AddArray(this->Steps);
    if (withWalkCount)
    {
      pd->AddArray(this->WalkCount);
    }
    pd->AddArray(this->Escaped);
    pd->AddArray(this->Truncated);
    pd->AddArray(this->Distance);
    pd->AddArray(this->ClosestValue);
    if (this->FromCache)
    {
      pd->AddArray(this->FromCache);
    }
    pd->SetActiveScalars(this->Mean->GetName());
    this->Finish();
    if (this->AnyDerivative)
    {
      this->Derivatives.AddTo(pd, this->Components);
    }
  }
};
} // namespace gridfree

#endif
