// The source of w = u − P (PolynomialShift.h): f − (ΔP − c·P), with its
// exact gradient, and the source set of a shifted problem.
#ifndef GRIDFREE_SOURCES_SHIFTED_SOURCE_H
#define GRIDFREE_SOURCES_SHIFTED_SOURCE_H

#include <gridfree/sources/PolynomialShift.h>
#include <gridfree/sources/SourceSet.h>
#include <gridfree/sources/SourceTerms.h>

#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

namespace gridfree
{
template <int DIM>
class ShiftedVolumeSource final : public VolumeSource<DIM>
{
public:
  // `inner` may be null (no source: f = 0).
  ShiftedVolumeSource(std::unique_ptr<VolumeSource<DIM>> inner,
    std::shared_ptr<const PolynomialShift<DIM>> shift)
    : Inner(std::move(inner))
    , Shift(std::move(shift))
  {
    if (!this->Shift)
    {
      throw std::invalid_argument("a shifted source needs its polynomial");
    }
  }

  void Evaluate(const Vec<DIM>& y, double* f) override
  {
    double inner = 0.0;
    if (this->Inner)
    {
      this->Inner->Evaluate(y, &inner);
    }
    f[0] = inner - this->Shift->Operator(y);
  }

  // Where the walks go (inside the boundary) ΔP − c·P is not zero: the
  // support is the inner source's box only for the sampling maps that read
  // it; interior problems never leave the boundary.
  bool SupportBounds(Vec<DIM>& boxMin, Vec<DIM>& boxMax) const override
  {
    return this->Inner && this->Inner->SupportBounds(boxMin, boxMax);
  }

  void EvaluateGradient(const Vec<DIM>& y, int components, double* f, double* gradient) override
  {
    double inner = 0.0;
    double innerGradient[DIM] = {};
    if (this->Inner)
    {
      this->Inner->EvaluateGradient(y, components, &inner, innerGradient);
    }
    f[0] = inner - this->Shift->Operator(y);
    const Vec<DIM> g = this->Shift->OperatorGradient(y);
    for (int i = 0; i < DIM; ++i)
    {
      gradient[i] = innerGradient[i] - g[i];
    }
  }

private:
  std::unique_ptr<VolumeSource<DIM>> Inner;
  std::shared_ptr<const PolynomialShift<DIM>> Shift;
};

// The source set of w: the volume source shifted; a set with point or curve
// sources is refused (the shift is for volume sources).
template <int DIM>
std::shared_ptr<SourceSet<DIM>> ShiftedSources(
  const SourceSet<DIM>* sources, std::shared_ptr<const PolynomialShift<DIM>> shift)
{
  if (sources && (sources->Points || sources->Curves))
  {
    throw std::invalid_argument(
      "the polynomial control variate takes volume sources only: no point or curve sources");
  }
  auto out = std::make_shared<SourceSet<DIM>>();
  VolumeSourceFactory<DIM> inner = sources ? sources->MakeVolume : VolumeSourceFactory<DIM>();
  out->MakeVolume = [inner, shift](double lengthScale) -> std::unique_ptr<VolumeSource<DIM>> {
    return std::make_unique<ShiftedVolumeSource<DIM>>(
      inner ? inner(lengthScale) : nullptr, shift);
  };
  return out;
}
} // namespace gridfree

#endif
