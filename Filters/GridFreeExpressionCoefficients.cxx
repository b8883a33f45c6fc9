#include "GridFreeExpressionCoefficients.h"

#include "GridFreeParsedExpression.h"

#include <tbb/enumerable_thread_specific.h>

namespace gridfree
{
// One thread's parsers of α, σ and f (null where there is no expression).
template <int DIM>
struct ExpressionCoefficients<DIM>::PerThread
{
  using Set = std::array<std::unique_ptr<ParsedExpression>, 3>;
  tbb::enumerable_thread_specific<std::unique_ptr<Set>> Sets;
};

template <int DIM>
ExpressionCoefficients<DIM>::ExpressionCoefficients(
  std::shared_ptr<const CoefficientField<DIM>> base, const std::array<std::string, 3>& expressions,
  double planeZ, double step)
  : Base(std::move(base))
  , Expressions(expressions)
  , PlaneZ(planeZ)
  , Step(step)
  , Parsers(new PerThread)
{
}

template <int DIM>
ExpressionCoefficients<DIM>::~ExpressionCoefficients() = default;

template <int DIM>
bool ExpressionCoefficients<DIM>::HasSource() const
{
  return this->Base->HasSource() || !this->Expressions[2].empty();
}

template <int DIM>
void ExpressionCoefficients<DIM>::Evaluate(const Vec<DIM>& x, CoefficientSample<DIM>& out) const
{
  this->Base->Evaluate(x, out);
  std::unique_ptr<typename PerThread::Set>& set = this->Parsers->Sets.local();
  if (!set)
  {
    set = std::make_unique<typename PerThread::Set>();
    for (std::size_t c = 0; c < 3; ++c)
    {
      if (!this->Expressions[c].empty())
      {
        (*set)[c] = std::make_unique<ParsedExpression>(this->Expressions[c]);
      }
    }
  }
  auto at = [this](const Vec<DIM>& y) -> std::array<double, 3> {
    return { y[0], y[1], DIM == 3 ? y[DIM - 1] : this->PlaneZ };
  };
  const std::array<double, 3> p = at(x);
  if (ParsedExpression* alpha = (*set)[0].get())
  {
    // α and its central differences along each axis the problem has.
    const double value = (*alpha)(p);
    const double h = this->Step;
    out.Alpha = value;
    out.AlphaLaplacian = 0.0;
    for (int i = 0; i < DIM; ++i)
    {
      Vec<DIM> y = x;
      y[i] = x[i] + h;
      const double ahead = (*alpha)(at(y));
      y[i] = x[i] - h;
      const double behind = (*alpha)(at(y));
      out.AlphaGradient[i] = (ahead - behind) / (2.0 * h);
      out.AlphaLaplacian += (ahead - 2.0 * value + behind) / (h * h);
    }
  }
  if (ParsedExpression* sigma = (*set)[1].get())
  {
    out.Absorption = (*sigma)(p);
  }
  if (ParsedExpression* source = (*set)[2].get())
  {
    out.Source += (*source)(p);
  }
}

template class ExpressionCoefficients<2>;
template class ExpressionCoefficients<3>;
} // namespace gridfree
