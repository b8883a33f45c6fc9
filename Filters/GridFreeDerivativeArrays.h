// The derivative outputs of a solve as VTK arrays, filled point by point
// from each point's running statistics.
// Private to the GridFree::Filters module.
#ifndef GridFreeDerivativeArrays_h
#define GridFreeDerivativeArrays_h

#include "GridFreeArrays.h"
#include "vtkDoubleArray.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"

#include <gridfree/estimators/DerivativeWalkOnSpheres.h>
#include <gridfree/statistics/RunningStatistics.h>

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace gridfree
{
// The derivative outputs of one solve: gradient (3 per component), Hessian
// (9 per component, row-major), directional derivative, divergence and curl,
// each with its variance, and the per-point DerivativeStatus. 2D results are
// padded with zero z derivatives so VTK's vector and tensor filters apply.
struct DerivativeArrays
{
  vtkSmartPointer<vtkDoubleArray> Gradient, GradientVariance, Hessian, HessianVariance;
  vtkSmartPointer<vtkDoubleArray> Directional, DirectionalVariance;
  vtkSmartPointer<vtkDoubleArray> Divergence, DivergenceVariance, Curl, CurlVariance;
  vtkSmartPointer<vtkUnsignedCharArray> Status;

  void Allocate(
    const std::string& name, int nc, vtkIdType n, const gridfree::DerivativeRequest& request)
  {
    if (request.Gradient)
    {
      this->Gradient = MakeArray(name + "_Gradient", 3 * nc, n);
      this->GradientVariance = MakeArray(name + "_Gradient_Variance", 3 * nc, n);
    }
    if (request.Hessian)
    {
      this->Hessian = MakeArray(name + "_Hessian", 9 * nc, n);
      this->HessianVariance = MakeArray(name + "_Hessian_Variance", 9 * nc, n);
    }
    if (request.Directional)
    {
      this->Directional = MakeArray(name + "_DirectionalDerivative", nc, n);
      this->DirectionalVariance = MakeArray(name + "_DirectionalDerivative_Variance", nc, n);
    }
    if (request.DivergenceCurl)
    {
      this->Divergence = MakeArray(name + "_Divergence", 1, n);
      this->DivergenceVariance = MakeArray(name + "_Divergence_Variance", 1, n);
      this->Curl = MakeArray(name + "_Curl", 3, n);
      this->CurlVariance = MakeArray(name + "_Curl_Variance", 3, n);
    }
    this->Status = vtkSmartPointer<vtkUnsignedCharArray>::New();
    this->Status->SetName("DerivativeStatus");
    this->Status->SetNumberOfTuples(n);
    this->Status->Fill(2);
  }

  template <int DIM>
  void Store(std::size_t i, const gridfree::RunningStatistics& stats,
    const gridfree::SampleLayout& layout, int nc, int status)
  {
    auto put = [&](vtkDoubleArray* m, vtkDoubleArray* v, vtkIdType at, int slot) {
      m->SetValue(at, slot >= 0 ? stats.GetMean(slot) : 0.0);
      v->SetValue(at, slot >= 0 ? stats.VarianceOfMean(slot) : 0.0);
    };
    const vtkIdType id = static_cast<vtkIdType>(i);
    for (int c = 0; c < nc; ++c)
    {
      for (int a = 0; a < 3; ++a)
      {
        if (this->Gradient)
        {
          put(this->Gradient, this->GradientVariance, id * 3 * nc + 3 * c + a,
            a < DIM ? layout.Gradient + c * DIM + a : -1);
        }
        for (int b = 0; this->Hessian && b < 3; ++b)
        {
          put(this->Hessian, this->HessianVariance, id * 9 * nc + 9 * c + 3 * a + b,
            a < DIM && b < DIM ? layout.Hessian + (c * DIM + a) * DIM + b : -1);
        }
      }
      if (this->Directional)
      {
        put(this->Directional, this->DirectionalVariance, id * nc + c, layout.Directional + c);
      }
    }
    if (this->Divergence)
    {
      put(this->Divergence, this->DivergenceVariance, id, layout.Divergence);
      for (int a = 0; a < 3; ++a)
      {
        put(this->Curl, this->CurlVariance, id * 3 + a, layout.Curl + a);
      }
    }
    this->Status->SetValue(id, static_cast<unsigned char>(status));
  }

  // A gradient given as numbers (the boundary cache's: nc × DIM per point,
  // with their variances), padded with zero z derivatives in 2D.
  template <int DIM>
  void StoreGradient(vtkIdType id, const std::vector<double>& gradient,
    const std::vector<double>& variance, int nc)
  {
    for (int c = 0; c < nc && this->Gradient; ++c)
    {
      for (int a = 0; a < 3; ++a)
      {
        const std::size_t at = static_cast<std::size_t>((id * nc + c) * DIM + a);
        this->Gradient->SetValue(id * 3 * nc + 3 * c + a, a < DIM ? gradient[at] : 0.0);
        this->GradientVariance->SetValue(id * 3 * nc + 3 * c + a, a < DIM ? variance[at] : 0.0);
      }
    }
    this->Status->SetValue(id, 0); // DerivativeStatus::Interior
  }

  // A cache's divergence and curl at point `id`.
  void StoreDivergenceCurl(vtkIdType id, const std::vector<double>& divergence,
    const std::vector<double>& divergenceVariance, const std::vector<double>& curl,
    const std::vector<double>& curlVariance)
  {
    if (!this->Divergence)
    {
      return;
    }
    const auto at = static_cast<std::size_t>(id);
    this->Divergence->SetValue(id, divergence[at]);
    this->DivergenceVariance->SetValue(id, divergenceVariance[at]);
    for (int a = 0; a < 3; ++a)
    {
      this->Curl->SetValue(3 * id + a, curl[3 * at + static_cast<std::size_t>(a)]);
      this->CurlVariance->SetValue(3 * id + a, curlVariance[3 * at + static_cast<std::size_t>(a)]);
    }
  }

  // A cache's directional derivative at point `id` (one per component).
  void StoreDirectional(vtkIdType id, const std::vector<double>& directional,
    const std::vector<double>& variance, int nc)
  {
    for (int c = 0; c < nc && this->Directional; ++c)
    {
      const std::size_t at = static_cast<std::size_t>(id * nc + c);
      this->Directional->SetValue(id * nc + c, directional[at]);
      this->DirectionalVariance->SetValue(id * nc + c, variance[at]);
    }
  }

  // A cache's Hessian at point `id` (components × DIM × DIM, with their
  // variances) into the 3 × 3 tuples.
  template <int DIM>
  void StoreHessian(vtkIdType id, const std::vector<double>& hessian,
    const std::vector<double>& variance, int nc)
  {
    for (int c = 0; c < nc && this->Hessian; ++c)
    {
      for (int a = 0; a < 3; ++a)
      {
        for (int b = 0; b < 3; ++b)
        {
          const bool inside = a < DIM && b < DIM;
          const std::size_t at = static_cast<std::size_t>(((id * nc + c) * DIM + a) * DIM + b);
          const vtkIdType slot = id * 9 * nc + 9 * c + 3 * a + b;
          this->Hessian->SetValue(slot, inside ? hessian[at] : 0.0);
          this->HessianVariance->SetValue(slot, inside ? variance[at] : 0.0);
        }
      }
    }
  }

  // Points without a derivative (no ball found, no walk run before an
  // abort, a probe point with NaN coordinates) get 0, not NaN, as
  // DerivativeStatus 2 says: VTK's stream tracer asserts on a NaN vector
  // (its cell search meets a NaN point) and glyphs of NaN are undefined.
  // Their variances stay NaN where unknown.
  void ZeroWhereMissing()
  {
    for (vtkDoubleArray* a :
      { this->Gradient.Get(), this->Hessian.Get(), this->Directional.Get(),
        this->Divergence.Get(), this->Curl.Get() })
    {
      if (!a)
      {
        continue;
      }
      const vtkIdType n = a->GetNumberOfTuples();
      const int components = a->GetNumberOfComponents();
      for (vtkIdType i = 0; i < n; ++i)
      {
        bool missing = false;
        for (int k = 0; k < components && !missing; ++k)
        {
          missing = !std::isfinite(a->GetTypedComponent(i, k));
        }
        if (missing)
        {
          for (int k = 0; k < components; ++k)
          {
            a->SetTypedComponent(i, k, 0.0);
          }
          this->Status->SetValue(i, 2);
        }
      }
    }
  }

  void AddTo(vtkPointData* pd, int nc)
  {
    for (vtkDataArray* a : { static_cast<vtkDataArray*>(this->Gradient),
           static_cast<vtkDataArray*>(this->GradientVariance),
           static_cast<vtkDataArray*>(this->Hessian),
           static_cast<vtkDataArray*>(this->HessianVariance),
           static_cast<vtkDataArray*>(this->Directional),
           static_cast<vtkDataArray*>(this->DirectionalVariance),
           static_cast<vtkDataArray*>(this->Divergence),
           static_cast<vtkDataArray*>(this->DivergenceVariance),
           static_cast<vtkDataArray*>(this->Curl), static_cast<vtkDataArray*>(this->CurlVariance),
           static_cast<vtkDataArray*>(this->Status) })
    {
      if (a)
      {
        pd->AddArray(a);
      }
    }
    if (nc == 1 && this->Gradient)
    {
      pd->SetActiveVectors(this->Gradient->GetName());
    }
    if (nc == 1 && this->Hessian)
    {
      pd->SetActiveTensors(this->Hessian->GetName());
    }
  }
};
} // namespace gridfree

#endif
