#include "vtkWalkOnSpheresHelmholtzDecomposition.h"

#include "GridFreeArrays.h"
#include "vtkCellData.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkExprTkFunctionParser.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkProbeFilter.h"
#include "vtkSmartPointer.h"
#include "GridFreeArraySelection.h"
#include "GridFreeCacheSummary.h"
#include "GridFreeSettingAccessors.h"
#include "GridFreeSolveSettings.h"

#include <cstdint>
#include <string>

vtkStandardNewMacro(vtkWalkOnSpheresHelmholtzDecomposition);
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresHelmholtzDecomposition, ControlVariates, bool, false, true)
GRIDFREE_SETTING_ACCESSORS(vtkWalkOnSpheresHelmholtzDecomposition, AntitheticPairs, bool, false, true)

namespace
{
// Names of the zero boundary values the two potentials are solved with;
// the solver names its outputs after them.
const char* const kScalarPotential = "HelmholtzScalarPotential";
const char* const kVectorPotential = "HelmholtzVectorPotential";

vtkSmartPointer<vtkDoubleArray> ZeroPointArray(const char* name, int components, vtkIdType n)
{
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName(name);
  array->SetNumberOfComponents(components);
  array->SetNumberOfTuples(n);
  array->Fill(0.0);
  return array;
}

// A copy of `array` under another name.
vtkSmartPointer<vtkDoubleArray> Renamed(vtkDataArray* array, const std::string& name)
{
  auto copy = vtkSmartPointer<vtkDoubleArray>::New();
  copy->DeepCopy(array);
  copy->SetName(name.c_str());
  return copy;
}
} // namespace

vtkWalkOnSpheresHelmholtzDecomposition::vtkWalkOnSpheresHelmholtzDecomposition()
{
  this->SetNumberOfInputPorts(3);
  // Default field: the active vectors of the Field input.
  this->SetInputArrayToProcess(
    0, FieldPort, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkDataSetAttributes::VECTORS);
}

vtkWalkOnSpheresHelmholtzDecomposition::~vtkWalkOnSpheresHelmholtzDecomposition()
{
  this->SetFieldExpression(nullptr);
  this->SetFieldName(nullptr);
}

void vtkWalkOnSpheresHelmholtzDecomposition::SetFieldConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(FieldPort, output);
}

void vtkWalkOnSpheresHelmholtzDecomposition::SetFieldData(vtkDataObject* data)
{
  this->SetInputData(FieldPort, data);
}

int vtkWalkOnSpheresHelmholtzDecomposition::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  this->LastNumberOfWalks = 0;
  this->LastSolveSeconds = 0.0;
  vtkPolyData* boundary = vtkPolyData::GetData(inputVector[BoundaryPort], 0);
  vtkDataSet* probe = vtkDataSet::GetData(inputVector[ProbePort], 0);
  vtkDataSet* field = vtkDataSet::GetData(inputVector[FieldPort], 0);
  vtkDataSet* output = vtkDataSet::GetData(outputVector, 0);
  if (!boundary || boundary->GetNumberOfPoints() == 0)
  {
    vtkErrorMacro(<< "No Boundary: connect a vtkPolyData with triangles (3D) or lines (2D) "
                     "to port 0.");
    return 0;
  }
  if (!probe || !output)
  {
    vtkErrorMacro(<< "No Probe: connect the dataset to evaluate the parts on to port 1.");
    return 0;
  }
  output->CopyStructure(probe);
  output->GetPointData()->PassData(probe->GetPointData());
  output->GetCellData()->PassData(probe->GetCellData());
  output->GetFieldData()->PassData(probe->GetFieldData());

  // The vector field: a point array of the Field input, or the expression.
  const bool hasExpression = this->FieldExpression && *this->FieldExpression;
  vtkDataArray* fieldArray = nullptr;
  if (field && field->GetNumberOfPoints() > 0)
  {
    int association = vtkDataObject::FIELD_ASSOCIATION_POINTS;
    fieldArray = this->GetInputArrayToProcess(0, field, association);
    if (!fieldArray)
    {
      vtkPointData* pd = field->GetPointData();
      for (int i = 0; i < pd->GetNumberOfArrays() && !fieldArray; ++i)
      {
        vtkDataArray* candidate = pd->GetArray(i);
        fieldArray = candidate && candidate->GetNumberOfComponents() == 3 ? candidate : nullptr;
      }
    }
    if (!fieldArray || association != vtkDataObject::FIELD_ASSOCIATION_POINTS)
    {
      vtkErrorMacro(<< "The Field input has no vector point array to decompose: select one "
                       "(3 components; 2 or 3 in 2D).");
      return 0;
    }
    if (hasExpression)
    {
      vtkWarningMacro(<< "FieldExpression is ignored: the Field input's array '"
                      << (fieldArray->GetName() ? fieldArray->GetName() : "") << "' is used.");
    }
  }
  else if (!hasExpression)
  {
    vtkErrorMacro(<< "No vector field: connect a Field input with a vector point array to "
                     "port 2, or set FieldExpression (e.g. \"-y*iHat + x*jHat\").");
    return 0;
  }
  std::string name = this->FieldName && *this->FieldName ? this->FieldName : "";
  if (name.empty())
  {
    name = fieldArray && fieldArray->GetName() && *fieldArray->GetName() ? fieldArray->GetName()
                                                                         : "X";
  }
  const vtkIdType n = probe->GetNumberOfPoints();
  if (n == 0)
  {
    vtkWarningMacro(<< "The Probe input has no points: there is nothing to decompose.");
    return 1;
  }

  if (this->GetEstimator() == BOUNDARY_CACHE)
  {
    // The boundary cache gives values and gradients, not the curl the
    // solenoidal part is made of; and on the square's potentials (2D, where
    // gradients would do) its gradients' error bars were far too short
    // (mean z² 3.9).
    vtkErrorMacro(<< "The Helmholtz decomposition takes the Pointwise Walks or the Sphere Cache "
                     "estimator, not the Boundary Cache (it gives no curl, and its gradients' "
                     "error bars are too short here).");
    return 0;
  }
  // Both potentials vanish on the boundary: zero boundary values.
  const bool threeD = boundary->GetNumberOfPolys() + boundary->GetNumberOfStrips() > 0;
  vtkNew<vtkPolyData> zeroBoundary;
  zeroBoundary->ShallowCopy(boundary);
  zeroBoundary->GetPointData()->Initialize();
  zeroBoundary->GetCellData()->PassData(boundary->GetCellData()); // Bézier markers
  const vtkIdType bn = boundary->GetNumberOfPoints();
  zeroBoundary->GetPointData()->AddArray(ZeroPointArray(kScalarPotential, 1, bn));
  zeroBoundary->GetPointData()->AddArray(ZeroPointArray(kVectorPotential, threeD ? 3 : 1, bn));

  // One Poisson solve per potential; `operation` makes its source ∇·X or ∇×X.
  auto solve = [&](const char* potential, gridfree::SourceOperator operation, int seed, double begin, double end,
                 vtkSmartPointer<vtkDataSet>& result) {
    // The properties this filter keeps (the sampling settings and its own),
    // the solver's defaults for the rest; the solve's own choices below.
    gridfree::SolveSettings settings = this->GetSettings();
    settings.Seed = seed;
    settings.Equation = gridfree::Equation::Poisson;
    settings.SourceOperator = operation;
    settings.ComputeGradient = true;
    // (ControlVariates and AntitheticPairs: the properties, in the settings.)
    gridfree::ArraySelections arrays;
    arrays.Select(0, vtkDataObject::FIELD_ASSOCIATION_POINTS, potential);
    if (fieldArray)
    {
      arrays.Select(2, vtkDataObject::FIELD_ASSOCIATION_POINTS, fieldArray->GetName());
    }
    else if (this->FieldExpression)
    {
      settings.SourceExpression = this->FieldExpression;
    }
    bool aborted = false;
    // Each potential's problem keeps its boundary (they differ in its
    // values' array) for the next execution.
    const int problem = operation == gridfree::SourceOperator::Divergence ? 0 : 1;
    if (!this->Solve(settings, arrays, zeroBoundary, fieldArray ? field : nullptr, probe, begin,
          end, result, aborted, problem))
    {
      if (aborted)
      {
        vtkWarningMacro(<< "Helmholtz decomposition aborted: the output has the probe only.");
      }
      return false;
    }
    return true;
  };
  vtkSmartPointer<vtkDataSet> scalarSolve, vectorSolve;
  // Seed + 1 for the second potential, wrapping around: independent walks.
  const int secondSeed =
    static_cast<int>(static_cast<std::uint32_t>(this->GetSeed()) + std::uint32_t(1));
  if (!solve(kScalarPotential, gridfree::SourceOperator::Divergence, this->GetSeed(), 0.0, 0.5,
        scalarSolve) ||
    !solve(kVectorPotential, gridfree::SourceOperator::Curl, secondSeed, 0.5, 1.0,
      vectorSolve))
  {
    return this->CheckAbort() ? 1 : 0;
  }
  vtkPointData* sp = scalarSolve->GetPointData();
  vtkPointData* vp = vectorSolve->GetPointData();
  const std::string s = kScalarPotential, v = kVectorPotential;
  vtkDataArray* potential = sp->GetArray(kScalarPotential);
  vtkDataArray* potentialVariance = sp->GetArray((s + "_Variance").c_str());
  vtkDataArray* gradient = sp->GetArray((s + "_Gradient").c_str());
  vtkDataArray* gradientVariance = sp->GetArray((s + "_Gradient_Variance").c_str());
  vtkDataArray* vector = vp->GetArray(kVectorPotential);
  vtkDataArray* vectorVariance = vp->GetArray((v + "_Variance").c_str());
  vtkDataArray* rotational = vp->GetArray((v + (threeD ? "_Curl" : "_Gradient")).c_str());
  vtkDataArray* rotationalVariance =
    vp->GetArray((v + (threeD ? "_Curl_Variance" : "_Gradient_Variance")).c_str());
  if (!potential || !potentialVariance || !gradient || !gradientVariance || !vector ||
    !vectorVariance || !rotational || !rotationalVariance)
  {
    vtkErrorMacro(<< "The internal solves did not give the potentials' derivatives.");
    return 0;
  }

  // X at the probe points, as the solves saw it.
  auto sampled = gridfree::MakeArray(name, 3, n);
  if (fieldArray)
  {
    vtkNew<vtkProbeFilter> sampler;
    sampler->SetInputData(probe);
    sampler->SetSourceData(field);
    sampler->PassPointArraysOff();
    sampler->PassCellArraysOff();
    sampler->PassFieldArraysOff();
    sampler->Update();
    vtkDataArray* values =
      sampler->GetOutput()->GetPointData()->GetArray(fieldArray->GetName());
    for (vtkIdType i = 0; i < n; ++i)
    {
      for (int c = 0; c < 3; ++c)
      {
        const bool has = values && c < values->GetNumberOfComponents();
        sampled->SetComponent(i, c, has ? values->GetComponent(i, c) : 0.0);
      }
    }
  }
  else
  {
    vtkNew<vtkExprTkFunctionParser> parser;
    parser->SetFunction(this->FieldExpression);
    double p[3];
    for (vtkIdType i = 0; i < n; ++i)
    {
      probe->GetPoint(i, p);
      parser->SetScalarVariableValue("x", p[0]);
      parser->SetScalarVariableValue("y", p[1]);
      parser->SetScalarVariableValue("z", p[2]);
      const double* x = parser->GetVectorResult();
      sampled->SetTuple(i, x);
    }
  }

  auto curlFree = gridfree::MakeArray(name + "_CurlFree", 3, n);
  auto curlFreeVariance = gridfree::MakeArray(name + "_CurlFree_Variance", 3, n);
  auto divergenceFree = gridfree::MakeArray(name + "_DivergenceFree", 3, n);
  auto divergenceFreeVariance = gridfree::MakeArray(name + "_DivergenceFree_Variance", 3, n);
  auto harmonic = gridfree::MakeArray(name + "_Harmonic", 3, n);
  auto harmonicVariance = gridfree::MakeArray(name + "_Harmonic_Variance", 3, n);
  auto vectorPotential = Renamed(vector, name + (threeD ? "_VectorPotential" : "_StreamFunction"));
  auto vectorPotentialVariance = Renamed(
    vectorVariance, name + (threeD ? "_VectorPotential_Variance" : "_StreamFunction_Variance"));
  for (vtkIdType i = 0; i < n; ++i)
  {
    double cf[3], cfv[3], df[3], dfv[3];
    for (int c = 0; c < 3; ++c)
    {
      cf[c] = gradient->GetComponent(i, c);
      cfv[c] = gradientVariance->GetComponent(i, c);
    }
    if (threeD)
    {
      // The solve gave A' = −A (ΔA' = ∇×X): the solenoidal part is −∇×A'.
      for (int c = 0; c < 3; ++c)
      {
        df[c] = -rotational->GetComponent(i, c);
        dfv[c] = rotationalVariance->GetComponent(i, c);
        vectorPotential->SetComponent(i, c, -vectorPotential->GetComponent(i, c));
      }
    }
    else
    {
      // J∇a = (−∂a/∂y, ∂a/∂x); X's z component is not part of a 2D split.
      df[0] = -rotational->GetComponent(i, 1);
      df[1] = rotational->GetComponent(i, 0);
      dfv[0] = rotationalVariance->GetComponent(i, 1);
      dfv[1] = rotationalVariance->GetComponent(i, 0);
      cf[2] = cfv[2] = df[2] = dfv[2] = 0.0;
      sampled->SetComponent(i, 2, 0.0);
    }
    curlFree->SetTuple(i, cf);
    curlFreeVariance->SetTuple(i, cfv);
    divergenceFree->SetTuple(i, df);
    divergenceFreeVariance->SetTuple(i, dfv);
    for (int c = 0; c < 3; ++c)
    {
      harmonic->SetComponent(i, c, sampled->GetComponent(i, c) - cf[c] - df[c]);
      // Independent solves: the variances add.
      harmonicVariance->SetComponent(i, c, cfv[c] + dfv[c]);
    }
  }

  vtkPointData* out = output->GetPointData();
  out->AddArray(sampled);
  out->AddArray(curlFree);
  out->AddArray(curlFreeVariance);
  out->AddArray(divergenceFree);
  out->AddArray(divergenceFreeVariance);
  out->AddArray(harmonic);
  out->AddArray(harmonicVariance);
  out->AddArray(Renamed(potential, name + "_Potential"));
  out->AddArray(Renamed(potentialVariance, name + "_Potential_Variance"));
  out->AddArray(vectorPotential);
  out->AddArray(vectorPotentialVariance);
  if (this->GetEstimator() == SPHERE_CACHE)
  {
    // Both potentials answer the same points, each from its own cache.
    gridfree::AddCacheSummary({ scalarSolve, vectorSolve }, output);
  }
  this->AddSummary(output);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkWalkOnSpheresHelmholtzDecomposition::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FieldExpression: " << (this->FieldExpression ? this->FieldExpression : "(none)")
     << "\n";
  os << indent << "FieldName: " << (this->FieldName ? this->FieldName : "(none)") << "\n";
  os << indent << "ControlVariates: " << this->GetSettings().ControlVariates << "\n";
  os << indent << "AntitheticPairs: " << this->GetSettings().AntitheticPairs << "\n";
}
