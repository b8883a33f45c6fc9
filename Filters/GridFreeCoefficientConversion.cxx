#include "GridFreeCoefficientConversion.h"

#include "GridFreeBoundaryAssembly.h"
#include "GridFreeExpressionCoefficients.h"
#include "GridFreeSourceConversion.h"

#include <gridfree/coefficients/ImageCoefficients.h>

#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDataSet.h"
#include "vtkImageData.h"
#include "vtkMatrix3x3.h"
#include "vtkObject.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace gridfree
{
namespace
{
struct CoefficientArray
{
  int Index;
  const char* Label;
  vtkDataArray* ProblemInputs::*Slot;
  bool SolveSettings::*FromArray;
};

const CoefficientArray kCoefficientArrays[] = {
  { 7, "diffusion coefficient (alpha)", &ProblemInputs::DiffusionArray,
    &SolveSettings::DiffusionFromArray },
  { 8, "absorption coefficient (sigma)", &ProblemInputs::AbsorptionArray,
    &SolveSettings::AbsorptionFromArray },
  { 2, "source term (f)", &ProblemInputs::CoefficientSourceArray,
    &SolveSettings::SourceTermFromArray },
};

std::vector<double> ValuesOf(vtkDataArray* array)
{
  std::vector<double> values(static_cast<std::size_t>(array->GetNumberOfTuples()));
  for (vtkIdType i = 0; i < array->GetNumberOfTuples(); ++i)
  {
    values[static_cast<std::size_t>(i)] = array->GetComponent(i, 0);
  }
  return values;
}
} // namespace

bool ResolveCoefficientArrays(vtkObject* self, const SolveSettings& settings,
  const ArraySelections& arrays, vtkDataSet* source, ProblemInputs& inputs)
{
  bool any = false;
  for (const CoefficientArray& c : kCoefficientArrays)
  {
    const ArraySelection& s = arrays.Index[static_cast<std::size_t>(c.Index)];
    // Not read from an array, or no choice.
    if (!(settings.*(c.FromArray)) || !s.Selected || (s.Name.empty() && s.AttributeType < 0))
    {
      continue;
    }
    if (!source)
    {
      vtkErrorWithObjectMacro(self, << "The " << c.Label << " array '" << s.Name
                                    << "' is chosen, but nothing is connected to the Source "
                                       "port: connect the vtkImageData that holds it.");
      return false;
    }
    int association = vtkDataObject::FIELD_ASSOCIATION_POINTS;
    std::string reason;
    vtkDataArray* array = arrays.Resolve(c.Index, source, false, association, reason);
    if (!array || association != vtkDataObject::FIELD_ASSOCIATION_POINTS)
    {
      vtkErrorWithObjectMacro(self, << "Cannot use the " << c.Label << " array '" << s.Name
                                    << "': "
                                    << (!reason.empty() ? reason
                                                        : std::string("it is not a point array "
                                                                      "of the Source input"))
                                    << ".");
      return false;
    }
    if (array->GetNumberOfComponents() != 1)
    {
      vtkErrorWithObjectMacro(self, << "The " << c.Label << " array '" << s.Name << "' has "
                                    << array->GetNumberOfComponents()
                                    << " components; a coefficient has one.");
      return false;
    }
    inputs.*(c.Slot) = array;
    any = true;
  }
  if (any)
  {
    auto* image = vtkImageData::SafeDownCast(source);
    if (!image)
    {
      vtkErrorWithObjectMacro(self, << "Coefficient arrays must lie on a vtkImageData (a CT "
                                       "volume or any image); the Source input is a "
                                    << source->GetClassName() << ".");
      return false;
    }
    if (!image->GetDirectionMatrix()->IsIdentity())
    {
      vtkErrorWithObjectMacro(self, << "The coefficient image has a direction matrix that is not "
                                       "the identity; resample it to axis-aligned voxels "
                                       "(e.g. with vtkImageReslice) first.");
      return false;
    }
    inputs.CoefficientImage = image;
    inputs.Source = source;
  }
  else if (source)
  {
    vtkWarningWithObjectMacro(self, << "The Source input is not used: with varying coefficients, "
                                       "choose its arrays for the diffusion coefficient (input "
                                       "array 7), the absorption coefficient (8) or the source "
                                       "term (2), with Diffusion From Array, Absorption From "
                                       "Array or Source Term From Array on.");
  }
  // The expressions that give a coefficient no array gives must parse to
  // numbers; those an array overrides are reported as unused.
  const struct
  {
    const char* Property;
    const std::string& Text;
    vtkDataArray* Array;
    bool Adds; // f's expression adds to the array's
  } expressions[] = {
    { "DiffusionExpression", settings.DiffusionExpression, inputs.DiffusionArray, false },
    { "AbsorptionExpression", settings.AbsorptionExpression, inputs.AbsorptionArray, false },
    { "SourceExpression", settings.SourceExpression, inputs.CoefficientSourceArray, true },
  };
  for (const auto& e : expressions)
  {
    if (e.Text.empty())
    {
      continue;
    }
    if (e.Array && !e.Adds)
    {
      vtkWarningWithObjectMacro(self, << "The " << e.Property << " '" << e.Text
                                      << "' is not used: the array '"
                                      << (e.Array->GetName() ? e.Array->GetName() : "")
                                      << "' gives that coefficient.");
      continue;
    }
    std::string reason;
    if (!CheckSourceExpression(e.Text, reason))
    {
      vtkErrorWithObjectMacro(self, << "The " << e.Property << " '" << e.Text
                                    << "' cannot be used: " << reason << ".");
      return false;
    }
  }
  const bool alphaExpression = !settings.DiffusionExpression.empty();
  const bool sigmaExpression = !settings.AbsorptionExpression.empty();
  if (!inputs.DiffusionArray && !alphaExpression &&
    !(settings.DiffusionCoefficient > 0.0 && std::isfinite(settings.DiffusionCoefficient)))
  {
    vtkErrorWithObjectMacro(self, << "DiffusionCoefficient must be positive and finite (got "
                                  << settings.DiffusionCoefficient << ").");
    return false;
  }
  if (!inputs.AbsorptionArray && !sigmaExpression &&
    !(settings.AbsorptionCoefficient >= 0.0 && std::isfinite(settings.AbsorptionCoefficient)))
  {
    vtkErrorWithObjectMacro(self, << "AbsorptionCoefficient must be finite and >= 0 (got "
                                  << settings.AbsorptionCoefficient << ").");
    return false;
  }
  return true;
}

template <int DIM>
std::shared_ptr<const CoefficientModel<DIM>> MakeCoefficientModel(const ProblemInputs& in,
  const SolveSettings& settings, const BoundingBox<DIM>& domain, std::string& reason,
  PreparationMonitor* monitor)
{
  VoxelGrid grid;
  std::array<std::string, 3> names = { "DiffusionCoefficient", "AbsorptionCoefficient",
    "source term" };
  if (in.CoefficientImage)
  {
    int dims[3];
    in.CoefficientImage->GetDimensions(dims);
    // The first point's position: the origin moved by the extent's start.
    int extent[6];
    in.CoefficientImage->GetExtent(extent);
    for (int i = 0; i < 3; ++i)
    {
      grid.Spacing[i] = in.CoefficientImage->GetSpacing()[i];
      grid.Origin[i] = in.CoefficientImage->GetOrigin()[i] + extent[2 * i] * grid.Spacing[i];
      grid.Dims[i] = dims[i];
    }
    if (DIM == 2 && dims[2] > 1)
    {
      reason = "a 2D problem takes its coefficients from a 2D image (one slice), not a volume";
      return nullptr;
    }
  }
  using Coefficient = typename ImageCoefficients<DIM>::Coefficient;
  // A constant an expression replaces is never read: 1 and 0 keep the base
  // field valid.
  std::array<std::string, 3> expressions = { in.DiffusionArray ? "" : settings.DiffusionExpression,
    in.AbsorptionArray ? "" : settings.AbsorptionExpression, settings.SourceExpression };
  Coefficient alpha{ {}, expressions[0].empty() ? settings.DiffusionCoefficient : 1.0 };
  Coefficient sigma{ {}, expressions[1].empty() ? settings.AbsorptionCoefficient : 0.0 };
  Coefficient source{ {}, 0.0 };
  vtkDataArray* chosen[3] = { in.DiffusionArray, in.AbsorptionArray, in.CoefficientSourceArray };
  Coefficient* coefficients[3] = { &alpha, &sigma, &source };
  for (int c = 0; c < 3; ++c)
  {
    if (chosen[c])
    {
      coefficients[c]->Values = ValuesOf(chosen[c]);
      names[static_cast<std::size_t>(c)] =
        std::string("array '") + (chosen[c]->GetName() ? chosen[c]->GetName() : "") + "'";
    }
  }
  try
  {
    auto field = std::make_shared<ImageCoefficients<DIM>>(grid, std::move(alpha),
      std::move(sigma), std::move(source), settings.CoefficientSmoothing, names, monitor);
    if (in.CoefficientImage && !field->Covers(domain.Min, domain.Max))
    {
      double bounds[6];
      in.CoefficientImage->GetBounds(bounds);
      std::ostringstream text;
      text << "the coefficient image (x " << bounds[0] << " to " << bounds[1] << ", y "
           << bounds[2] << " to " << bounds[3] << ", z " << bounds[4] << " to " << bounds[5]
           << ") does not cover the boundary (";
      for (int i = 0; i < DIM; ++i)
      {
        text << (i ? ", " : "") << "xyz"[i] << " " << domain.Min[i] << " to " << domain.Max[i];
      }
      text << "): every point the walks visit needs its coefficients";
      reason = text.str();
      return nullptr;
    }
    std::shared_ptr<const CoefficientField<DIM>> chosen = field;
    if (!expressions[0].empty() || !expressions[1].empty() || !expressions[2].empty())
    {
      chosen = std::make_shared<ExpressionCoefficients<DIM>>(
        field, expressions, ProblemPlaneZ<DIM>(in), 1e-4 * (domain.Max - domain.Min).norm());
    }
    auto model = std::make_shared<CoefficientModel<DIM>>();
    typename ScreeningBoundGrid<DIM>::Settings bounds;
    bounds.Monitor = monitor;
    model->Majorant =
      std::make_shared<ScreeningBoundGrid<DIM>>(*chosen, domain.Min, domain.Max, bounds);
    model->Field = std::move(chosen);
    return model;
  }
  catch (const std::invalid_argument& e)
  {
    reason = e.what();
    // Name the expression a bad value came from.
    const char* properties[3] = { "DiffusionExpression", "AbsorptionExpression",
      "SourceExpression" };
    const char* symbols[3] = { "alpha", "sigma", "the source f" };
    for (int c = 0; c < 3; ++c)
    {
      if (!expressions[static_cast<std::size_t>(c)].empty() &&
        reason.find(symbols[c]) != std::string::npos)
      {
        reason += std::string(" (") + (c == 2 ? "f" : symbols[c]) + " is the " + properties[c] + " '" +
          expressions[static_cast<std::size_t>(c)] + "')";
        break;
      }
    }
    return nullptr;
  }
}

template std::shared_ptr<const CoefficientModel<2>> MakeCoefficientModel<2>(
  const ProblemInputs&, const SolveSettings&, const BoundingBox<2>&, std::string&,
  PreparationMonitor*);
template std::shared_ptr<const CoefficientModel<3>> MakeCoefficientModel<3>(
  const ProblemInputs&, const SolveSettings&, const BoundingBox<3>&, std::string&,
  PreparationMonitor*);
} // namespace gridfree
