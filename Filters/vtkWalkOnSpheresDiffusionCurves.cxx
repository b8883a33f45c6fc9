#include "vtkWalkOnSpheresDiffusionCurves.h"

#include "GridFreeWholeInputRequest.h"
#include "vtkCellData.h"
#include "vtkDataSet.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkUnsignedCharArray.h"
#include "GridFreeArraySelection.h"
#include "GridFreeSettingAccessors.h"
#include "GridFreeSolveSettings.h"

#include <algorithm>
#include <cmath>
#include <string>

vtkStandardNewMacro(vtkWalkOnSpheresDiffusionCurves);
GRIDFREE_EXPRESSION_ACCESSORS(vtkWalkOnSpheresDiffusionCurves, SourceExpression)

namespace
{
// `array`'s colours as unsigned char RGB: `range` mapped to 0–255 and
// clamped; one component is repeated as grey.
vtkSmartPointer<vtkUnsignedCharArray> ToRgb(
  vtkDataArray* array, const double range[2], const std::string& name)
{
  auto rgb = vtkSmartPointer<vtkUnsignedCharArray>::New();
  rgb->SetName(name.c_str());
  rgb->SetNumberOfComponents(3);
  rgb->SetNumberOfTuples(array->GetNumberOfTuples());
  const int nc = array->GetNumberOfComponents();
  const double width = range[1] - range[0];
  for (vtkIdType i = 0; i < array->GetNumberOfTuples(); ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      const double v = array->GetComponent(i, nc == 1 ? 0 : c);
      const double t = width != 0.0 ? (v - range[0]) / width : 0.0;
      // NaN (no value) shows as black rather than as an arbitrary byte.
      const double clamped = std::isfinite(t) ? std::min(1.0, std::max(0.0, t)) : 0.0;
      rgb->SetTypedComponent(i, c, static_cast<unsigned char>(std::lround(255.0 * clamped)));
    }
  }
  return rgb;
}

bool IsSurface(vtkPolyData* boundary)
{
  return boundary->GetNumberOfPolys() + boundary->GetNumberOfStrips() > 0;
}
} // namespace

vtkWalkOnSpheresDiffusionCurves::vtkWalkOnSpheresDiffusionCurves()
{
  this->SetNumberOfInputPorts(3);
  this->SetInputArrayToProcess(
    0, BoundaryPort, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS_THEN_CELLS, "FrontColor");
  this->SetInputArrayToProcess(
    1, BoundaryPort, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS_THEN_CELLS, "BackColor");
}

vtkWalkOnSpheresDiffusionCurves::~vtkWalkOnSpheresDiffusionCurves() = default;

void vtkWalkOnSpheresDiffusionCurves::SetSourceConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(SourcePort, output);
}

void vtkWalkOnSpheresDiffusionCurves::SetSourceData(vtkDataObject* data)
{
  this->SetInputData(SourcePort, data);
}

int vtkWalkOnSpheresDiffusionCurves::FillInputPortInformation(int port, vtkInformation* info)
{
  this->Superclass::FillInputPortInformation(port, info);
  if (port == ProbePort)
  {
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  }
  return 1;
}

int vtkWalkOnSpheresDiffusionCurves::RequestDataObject(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (vtkDataSet::GetData(inputVector[ProbePort], 0))
  {
    return this->Superclass::RequestDataObject(request, inputVector, outputVector);
  }
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  if (!vtkImageData::SafeDownCast(outInfo->Get(vtkDataObject::DATA_OBJECT())))
  {
    vtkNew<vtkImageData> image;
    outInfo->Set(vtkDataObject::DATA_OBJECT(), image);
  }
  return 1;
}

int vtkWalkOnSpheresDiffusionCurves::RequestInformation(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (inputVector[ProbePort]->GetInformationObject(0))
  {
    return this->Superclass::RequestInformation(request, inputVector, outputVector);
  }
  // The image's extent depends on the resolution only; its origin and
  // spacing may depend on the boundary's bounds, known in RequestData.
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  const int extent[6] = { 0, std::max(2, this->ImageResolution[0]) - 1, 0,
    std::max(2, this->ImageResolution[1]) - 1, 0, 0 };
  outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  outInfo->Set(vtkAlgorithm::CAN_PRODUCE_SUB_EXTENT(), 1);
  return 1;
}

int vtkWalkOnSpheresDiffusionCurves::RequestUpdateExtent(
  vtkInformation* request, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  if (inputVector[ProbePort]->GetInformationObject(0))
  {
    return this->Superclass::RequestUpdateExtent(request, inputVector, outputVector);
  }
  for (int port : { static_cast<int>(BoundaryPort), static_cast<int>(SourcePort) })
  {
    if (vtkInformation* info = inputVector[port]->GetInformationObject(0))
    {
      gridfree::RequestWholeInput(info);
    }
  }
  return 1;
}

bool vtkWalkOnSpheresDiffusionCurves::MakeImage(
  vtkPolyData* boundary, const int extent[6], vtkImageData* image)
{
  double bounds[6];
  boundary->GetBounds(bounds);
  double window[4] = { this->ImageWindow[0], this->ImageWindow[1], this->ImageWindow[2],
    this->ImageWindow[3] };
  const bool unset = window[0] == 0.0 && window[1] == 0.0 && window[2] == 0.0 && window[3] == 0.0;
  if (unset)
  {
    // The boundary's box, 5% larger on each side (and square-free: a
    // degenerate side takes the other's size).
    const double sx = bounds[1] - bounds[0], sy = bounds[3] - bounds[2];
    const double padX = 0.05 * (sx > 0.0 ? sx : sy), padY = 0.05 * (sy > 0.0 ? sy : sx);
    window[0] = bounds[0] - padX;
    window[1] = bounds[1] + padX;
    window[2] = bounds[2] - padY;
    window[3] = bounds[3] + padY;
  }
  if (!(window[1] > window[0]) || !(window[3] > window[2]) ||
    !std::isfinite(window[1] - window[0]) || !std::isfinite(window[3] - window[2]))
  {
    vtkErrorMacro(<< "The image window (" << window[0] << ", " << window[1] << ", " << window[2]
                  << ", " << window[3] << ") is empty: set ImageWindow to xmin < xmax, "
                  << "ymin < ymax.");
    return false;
  }
  const int nx = std::max(2, this->ImageResolution[0]);
  const int ny = std::max(2, this->ImageResolution[1]);
  image->SetExtent(const_cast<int*>(extent));
  image->SetOrigin(window[0], window[2], bounds[4]);
  image->SetSpacing((window[1] - window[0]) / (nx - 1), (window[3] - window[2]) / (ny - 1), 1.0);
  return true;
}

int vtkWalkOnSpheresDiffusionCurves::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  this->LastNumberOfWalks = 0;
  this->LastSolveSeconds = 0.0;
  vtkPolyData* boundary = vtkPolyData::GetData(inputVector[BoundaryPort], 0);
  vtkDataSet* probe = vtkDataSet::GetData(inputVector[ProbePort], 0);
  vtkDataSet* source = vtkDataSet::GetData(inputVector[SourcePort], 0);
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkDataSet* output = vtkDataSet::GetData(outputVector, 0);
  if (!boundary || boundary->GetNumberOfPoints() == 0)
  {
    vtkErrorMacro(<< "No Boundary: connect a vtkPolyData with lines or Bézier control polygons "
                     "(2D) or a surface (3D), carrying front and back colours, to port 0.");
    return 0;
  }
  if (!output)
  {
    vtkErrorMacro(<< "The output is not a dataset.");
    return 0;
  }

  // The two colour arrays, passed on to the solver by name and association.
  int frontAssociation = vtkDataObject::FIELD_ASSOCIATION_POINTS;
  int backAssociation = vtkDataObject::FIELD_ASSOCIATION_POINTS;
  vtkDataArray* front = this->GetInputArrayToProcess(0, boundary, frontAssociation);
  vtkDataArray* back = this->GetInputArrayToProcess(1, boundary, backAssociation);
  if (!front || !back)
  {
    vtkErrorMacro(<< "The Boundary has no " << (front ? "back" : "front")
                  << " colour array: select numeric point or cell arrays with "
                     "SetInputArrayToProcess(0, ...) for the front and (1, ...) for the back "
                     "(defaults: FrontColor and BackColor).");
    return 0;
  }
  if (!front->GetName() || !back->GetName() || !*front->GetName() || !*back->GetName())
  {
    vtkErrorMacro(<< "The colour arrays must have names.");
    return 0;
  }

  // The probe, or an image of the requested extent in the curves' plane.
  vtkSmartPointer<vtkDataSet> points = probe;
  if (!probe)
  {
    if (IsSurface(boundary))
    {
      vtkErrorMacro(<< "A surface boundary (3D) needs a Probe: connect a slice plane, points "
                       "or an image to port 1.");
      return 0;
    }
    int extent[6] = { 0, std::max(2, this->ImageResolution[0]) - 1, 0,
      std::max(2, this->ImageResolution[1]) - 1, 0, 0 };
    if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT()))
    {
      outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), extent);
    }
    auto image = vtkSmartPointer<vtkImageData>::New();
    if (!this->MakeImage(boundary, extent, image))
    {
      return 0;
    }
    points = image;
  }

  // The properties this filter keeps (the sampling settings and its own),
  // the solver's defaults for the rest; the solve's own choices below.
  gridfree::SolveSettings settings = this->GetSettings();
  settings.TwoSidedBoundaryValues = true;
  gridfree::ArraySelections arrays;
  arrays.Select(0, frontAssociation, front->GetName());
  arrays.Select(3, backAssociation, back->GetName());
  // (The settings carry the SourceExpression property.)
  const bool hasExpression = !settings.SourceExpression.empty();
  if (source || hasExpression)
  {
    settings.Equation = gridfree::Equation::Poisson;
    if (source)
    {
      if (vtkInformation* info = this->GetInputArrayInformation(2))
      {
        if (info->Has(vtkDataObject::FIELD_NAME()) && info->Get(vtkDataObject::FIELD_NAME()))
        {
          arrays.Select(2, vtkDataObject::FIELD_ASSOCIATION_POINTS,
            info->Get(vtkDataObject::FIELD_NAME()));
        }
      }
    }
  }
  bool aborted = false;
  vtkSmartPointer<vtkDataSet> solved;
  if (!this->Solve(settings, arrays, boundary, source, points, 0.0, 1.0, solved, aborted))
  {
    if (aborted)
    {
      vtkWarningMacro(<< "Diffusion curves aborted: the output is empty.");
      return 1;
    }
    return 0;
  }
  output->ShallowCopy(solved);
  const std::string name = front->GetName();
  vtkDataArray* colour = output->GetPointData()->GetArray(name.c_str());
  const int nc = colour ? colour->GetNumberOfComponents() : 0;
  if (colour && (nc == 1 || nc == 3))
  {
    output->GetPointData()->AddArray(ToRgb(colour, this->ColorRange, name + "_RGB"));
  }
  output->GetPointData()->SetActiveScalars(name.c_str());
  this->AddSummary(output);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkWalkOnSpheresDiffusionCurves::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "SourceExpression: "
     << (this->GetSettings().SourceExpression.empty() ? "(none)"
                                                        : this->GetSettings().SourceExpression)
     << "\n";
  os << indent << "ImageWindow: " << this->ImageWindow[0] << ", " << this->ImageWindow[1] << ", "
     << this->ImageWindow[2] << ", " << this->ImageWindow[3] << "\n";
  os << indent << "ImageResolution: " << this->ImageResolution[0] << " x "
     << this->ImageResolution[1] << "\n";
  os << indent << "ColorRange: " << this->ColorRange[0] << ", " << this->ColorRange[1] << "\n";
}
