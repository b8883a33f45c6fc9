#include "pqGridFreeRefineUntilTargetWidget.h"

#include "pqApplicationCore.h"
#include "pqPipelineSource.h"
#include "pqProxy.h"
#include "pqServerManagerModel.h"
#include "pqView.h"

#include "vtkAlgorithm.h"
#include "vtkOutputWindow.h"
#include "vtkSMIdTypeVectorProperty.h"
#include "vtkSMIntVectorProperty.h"
#include "vtkSMProperty.h"
#include "vtkSMPropertyHelper.h"
#include "vtkSMSourceProxy.h"
#include "vtkSmartPointer.h"

#include <QCoreApplication>
#include <QEventLoop>
#include <QVBoxLayout>
#include <QPointer>
#include <QPushButton>

#include <sstream>

namespace
{
// An information property's first element after refreshing it (-1 if the
// proxy has no such property).
long long InformationValue(vtkSMProxy* proxy, const char* name)
{
  vtkSMProperty* property = proxy->GetProperty(name);
  if (!property)
  {
    return -1;
  }
  proxy->UpdatePropertyInformation(property);
  if (auto ids = vtkSMIdTypeVectorProperty::SafeDownCast(property))
  {
    return ids->GetNumberOfElements() > 0 ? static_cast<long long>(ids->GetElement(0)) : -1;
  }
  if (auto ints = vtkSMIntVectorProperty::SafeDownCast(property))
  {
    return ints->GetNumberOfElements() > 0 ? ints->GetElement(0) : -1;
  }
  return -1;
}

void Warn(vtkSMProxy* proxy, const std::string& text)
{
  std::ostringstream msg;
  msg << (proxy->GetXMLLabel() ? proxy->GetXMLLabel() : "Walk On Spheres Solver") << ": " << text;
  vtkOutputWindowDisplayWarningText(msg.str().c_str());
}
} // namespace

//-----------------------------------------------------------------------------
pqGridFreeRefineUntilTargetWidget::pqGridFreeRefineUntilTargetWidget(
  vtkSMProxy* proxy, vtkSMProperty* property, QWidget* parent)
  : Superclass(proxy, parent)
{
  this->setProperty(property);
  this->Label = QString::fromUtf8(
    property && property->GetXMLLabel() ? property->GetXMLLabel() : "Refine Until Target");
  this->Button = new QPushButton(this->Label, this);
  this->Button->setObjectName("RefineUntilTargetButton");
  // Let through while a solve runs (pqGridFreeResponsiveSolves), to stop
  // the rounds.
  this->Button->setProperty("gridfreeClickableDuringSolves", true);
  QObject::connect(this->Button, &QPushButton::clicked, this,
    &pqGridFreeRefineUntilTargetWidget::onClicked);
  // The full width of the panel, as ParaView's command buttons (Refine).
  auto layout = new QVBoxLayout(this);
  layout->setMargin(0);
  layout->setSpacing(0);
  layout->addWidget(this->Button);
  this->setShowLabel(false);
}

//-----------------------------------------------------------------------------
pqGridFreeRefineUntilTargetWidget::~pqGridFreeRefineUntilTargetWidget() = default;

//-----------------------------------------------------------------------------
void pqGridFreeRefineUntilTargetWidget::onClicked()
{
  if (this->Running)
  {
    // Clicked again: no further round. The round in progress completes, so
    // the output stays that of a whole round (Abort stops it at once).
    this->StopRequested = true;
    this->Button->setText(tr("Stopping After This Round"));
    this->Button->setEnabled(false);
    return;
  }
  this->RunRounds();
}

//-----------------------------------------------------------------------------
void pqGridFreeRefineUntilTargetWidget::RunRounds()
{
  vtkSmartPointer<vtkSMProxy> proxy = this->proxy();
  pqServerManagerModel* model = pqApplicationCore::instance()->getServerManagerModel();
  QPointer<pqPipelineSource> source =
    model && proxy ? model->findItem<pqPipelineSource*>(proxy.GetPointer()) : nullptr;
  auto sourceProxy = vtkSMSourceProxy::SafeDownCast(proxy);
  vtkSMProperty* command = this->property();
  const char* commandName = command ? proxy->GetPropertyName(command) : nullptr;
  if (!source || !sourceProxy || !commandName)
  {
    return;
  }
  if (vtkSMPropertyHelper(proxy, "TargetStandardError", /*quiet=*/true).GetAsDouble() <= 0.0)
  {
    Warn(proxy, "set a Target Standard Error first: Refine Until Target refines until every "
                "point's standard error is at most that target.");
    return;
  }
  if (source->modifiedState() != pqProxy::UNMODIFIED)
  {
    Warn(proxy, "press Apply first: Refine Until Target continues the solve that was applied.");
    return;
  }

  QPointer<pqGridFreeRefineUntilTargetWidget> self(this);
  this->Running = true;
  this->StopRequested = false;
  this->Button->setText(tr("Stop Refining"));
  long long shortOfTarget = InformationValue(proxy, "PointsShortOfTarget");
  long long walks = InformationValue(proxy, "WalksPerPointInUse");
  bool aborted = false;
  while (shortOfTarget > 0 && walks < kMostWalksPerPoint && !this->StopRequested)
  {
    // One round: Refine (twice the most walks a point may take), update the
    // solver, then show it in every view.
    proxy->InvokeCommand(commandName);
    sourceProxy->UpdatePipelineInformation();
    sourceProxy->UpdatePipeline();
    if (!self)
    {
      return; // the panel went away with the filter
    }
    for (pqView* view : model->findItems<pqView*>())
    {
      view->forceRender();
    }
    // Repaint (the panel's Walks Per Point, the progress bar) without user
    // input: a click waits for the next round's progress events, where only
    // Abort and this button get through.
    QCoreApplication::processEvents(
      QEventLoop::ExcludeUserInputEvents | QEventLoop::X11ExcludeTimers);
    if (!self)
    {
      return;
    }
    // (The flag itself is cleared once the aborted update has ended.)
    aborted = InformationValue(proxy, "LastSolveAborted") > 0;
    if (aborted)
    {
      break;
    }
    shortOfTarget = InformationValue(proxy, "PointsShortOfTarget");
    walks = InformationValue(proxy, "WalksPerPointInUse");
  }
  this->Running = false;
  this->Button->setText(this->Label);
  this->Button->setEnabled(true);
  if (!aborted && shortOfTarget == 0)
  {
    std::ostringstream msg;
    msg << (proxy->GetXMLLabel() ? proxy->GetXMLLabel() : "Walk On Spheres Solver")
        << ": Refine Until Target is done: every point is at the target standard error "
        << vtkSMPropertyHelper(proxy, "TargetStandardError", /*quiet=*/true).GetAsDouble()
        << (vtkSMPropertyHelper(proxy, "TargetErrorIsRelative", /*quiet=*/true).GetAsInt()
               ? " (relative)"
               : "")
        << ", with at most " << walks << " walks per point (array WalkCount).\n";
    vtkOutputWindowDisplayText(msg.str().c_str());
  }
  if (!aborted && !this->StopRequested && shortOfTarget > 0)
  {
    std::ostringstream msg;
    msg << "stopped refining at " << walks << " walks per point (Refine Until Target goes up to "
        << kMostWalksPerPoint << "): " << shortOfTarget
        << " points are still above the target standard error; raise the target.";
    Warn(proxy, msg.str());
  }
}
