// Expressions in x, y and z, in the syntax of ParaView's Calculator
// (vtkExprTkFunctionParser): a source term, boundary values, or a
// coefficient of the equation with varying coefficients. Private to the
// GridFree::Filters module.
#ifndef GridFreeParsedExpression_h
#define GridFreeParsedExpression_h

#include "vtkExprTkFunctionParser.h"
#include "vtkNew.h"

#include <array>
#include <string>

namespace gridfree
{
// One parsed expression in x, y, z (a parser is never shared by threads):
// a scalar, or a vector written with iHat, jHat and kHat as in VTK's
// calculator.
class ParsedExpression
{
public:
  explicit ParsedExpression(const std::string& expression)
  {
    this->Parser->SetFunction(expression.c_str());
    this->Parser->SetScalarVariableValue("x", 0.0);
    this->Parser->SetScalarVariableValue("y", 0.0);
    this->Parser->SetScalarVariableValue("z", 0.0);
    // Parse once, before the walks.
    this->IsVector = this->Parser->IsVectorResult() != 0;
    this->X = this->Parser->GetScalarVariableIndex("x");
    this->Y = this->Parser->GetScalarVariableIndex("y");
    this->Z = this->Parser->GetScalarVariableIndex("z");
  }

  // 1 for a scalar expression, 3 for a vector one.
  int Components() const { return this->IsVector ? 3 : 1; }

  double operator()(const std::array<double, 3>& p)
  {
    this->SetPoint(p);
    return this->Parser->GetScalarResult();
  }

  // Writes Components() numbers.
  void Evaluate(const std::array<double, 3>& p, double* out)
  {
    this->SetPoint(p);
    if (this->IsVector)
    {
      const double* v = this->Parser->GetVectorResult();
      out[0] = v[0];
      out[1] = v[1];
      out[2] = v[2];
    }
    else
    {
      out[0] = this->Parser->GetScalarResult();
    }
  }

private:
  void SetPoint(const std::array<double, 3>& p)
  {
    this->Parser->SetScalarVariableValue(this->X, p[0]);
    this->Parser->SetScalarVariableValue(this->Y, p[1]);
    this->Parser->SetScalarVariableValue(this->Z, p[2]);
  }

  vtkNew<vtkExprTkFunctionParser> Parser;
  bool IsVector = false;
  int X = 0, Y = 1, Z = 2;
};

// Parses `expression` in x, y, z and tells whether it gives a scalar (1) or a
// vector (3, with iHat, jHat, kHat); 0 with the parser's reason when it does
// not parse.
int ExpressionComponents(const std::string& expression, std::string& reason);

// Whether `expression` reads x, y or z: false when it parses with none of
// them defined (a constant, whose value then bounds it).
bool ExpressionReadsPosition(const std::string& expression);
} // namespace gridfree

#endif
