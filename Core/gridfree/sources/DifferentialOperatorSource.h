// A volume source made of a vector field source X by a first-order
// differential operator: f = ∇·X, or f = ∇×X (3 components in 3D, the
// scalar ∂X_y/∂x − ∂X_x/∂y in 2D). The Helmholtz decomposition's potentials
// solve Poisson equations with these sources (paper Sec. 6.6): Δu = ∇·X,
// and ΔA' = ∇×X for A' = −A.
#ifndef GRIDFREE_SOURCES_DIFFERENTIAL_OPERATOR_SOURCE_H
#define GRIDFREE_SOURCES_DIFFERENTIAL_OPERATOR_SOURCE_H

#include <gridfree/sources/SourceOperator.h>
#include <gridfree/sources/SourceTerms.h>
#include <gridfree/math/Vector.h>

#include <memory>
#include <utility>
#include <vector>

namespace gridfree
{
// X has DIM or 3 components (∂/∂z = 0 in 2D). The derivatives are the
// field's own EvaluateGradient: exact for interpolated data (the derivative
// of the trilinear or cell interpolant), central differences for
// expressions.
template <int DIM>
class DifferentialOperatorSource : public VolumeSource<DIM>
{
public:
  DifferentialOperatorSource(
    std::unique_ptr<VolumeSource<DIM>> field, int fieldComponents, SourceOperator op)
    : Field(std::move(field))
    , FieldComponents(fieldComponents)
    , Operator(op)
    , Value(static_cast<std::size_t>(fieldComponents))
    , Gradient(static_cast<std::size_t>(fieldComponents) * DIM)
  {
  }

  static int ResultComponents(SourceOperator op)
  {
    return op == SourceOperator::Curl && DIM == 3 ? 3 : 1;
  }

  void Evaluate(const Vec<DIM>& y, double* f) override
  {
    this->Field->EvaluateGradient(y, this->FieldComponents, this->Value.data(),
      this->Gradient.data());
    // J(c, i) = ∂X_c/∂y_i; zero for i ≥ DIM (2D fields do not vary in z)
    // and for components the field does not have.
    auto J = [this](int c, int i) {
      return c < this->FieldComponents && i < DIM ? this->Gradient[c * DIM + i] : 0.0;
    };
    if (this->Operator == SourceOperator::Divergence)
    {
      f[0] = J(0, 0) + J(1, 1) + J(2, 2);
    }
    else if (DIM == 3)
    {
      f[0] = J(2, 1) - J(1, 2);
      f[1] = J(0, 2) - J(2, 0);
      f[2] = J(1, 0) - J(0, 1);
    }
    else
    {
      f[0] = J(1, 0) - J(0, 1);
    }
  }

  bool SupportBounds(Vec<DIM>& boxMin, Vec<DIM>& boxMax) const override
  {
    return this->Field->SupportBounds(boxMin, boxMax);
  }

private:
  std::unique_ptr<VolumeSource<DIM>> Field;
  int FieldComponents;
  SourceOperator Operator;
  std::vector<double> Value, Gradient;
};
} // namespace gridfree

#endif
