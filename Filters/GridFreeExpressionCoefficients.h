// Coefficients α, σ, f of the equation with varying coefficients
// (VaryingCoefficients.h) given as expressions in x, y and z, in the syntax
// of ParaView's Calculator, over a base field (the image's arrays or the
// constants) that gives the coefficients without an expression.
//
// An expression for α or σ replaces the base's; an expression for f adds to
// the base's f, as SourceExpression does for the other equations. α's
// gradient and Laplacian, which σ′ needs, are central differences of the
// expression with the step `step` (the callers take 1e-4 of the domain's
// diagonal: the second difference's rounding, about 1e-16·α/step², and its
// truncation, about step²·α⁗/12, then both stay near 1e-8 of α over the
// diagonal squared). Each thread evaluates with its own parsers, made the
// first time it evaluates. Private to the GridFree::Filters module.
#ifndef GridFreeExpressionCoefficients_h
#define GridFreeExpressionCoefficients_h

#include <gridfree/coefficients/VaryingCoefficients.h>

#include <array>
#include <memory>
#include <string>

namespace gridfree
{
template <int DIM>
class ExpressionCoefficients final : public CoefficientField<DIM>
{
public:
  // `expressions` holds α, σ and f (empty: the base's); in 2D they are
  // evaluated in the plane z = planeZ. The expressions must parse to
  // numbers (CheckSourceExpression).
  ExpressionCoefficients(std::shared_ptr<const CoefficientField<DIM>> base,
    const std::array<std::string, 3>& expressions, double planeZ, double step);
  ~ExpressionCoefficients() override;

  void Evaluate(const Vec<DIM>& x, CoefficientSample<DIM>& out) const override;
  bool HasSource() const override;

private:
  struct PerThread;
  std::shared_ptr<const CoefficientField<DIM>> Base;
  std::array<std::string, 3> Expressions;
  double PlaneZ;
  double Step;
  std::unique_ptr<PerThread> Parsers;
};

extern template class ExpressionCoefficients<2>;
extern template class ExpressionCoefficients<3>;
} // namespace gridfree

#endif
