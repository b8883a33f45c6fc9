#include "pqGridFreeResponsiveSolves.h"

#include "pqApplicationCore.h"
#include "pqCoreUtilities.h"
#include "pqPipelineSource.h"
#include "pqOutputWidget.h"
#include "pqProgressManager.h"
#include "pqPropertiesPanel.h"
#include "pqProxy.h"
#include "pqServerManagerModel.h"

#include "vtkAlgorithm.h"
#include "vtkCommand.h"
#include "vtkSMArrayListDomain.h"
#include "vtkSMDomainIterator.h"
#include "vtkSMInputProperty.h"
#include "vtkSMIntVectorProperty.h"
#include "vtkSMPropertyIterator.h"
#include "vtkSMPropertyHelper.h"
#include "vtkSMProxy.h"
#include "vtkPVXMLElement.h"
#include "vtkSMStringVectorProperty.h"
#include "vtkSmartPointer.h"

#include <QApplication>
#include <QEvent>
#include <QEventLoop>
#include <QMouseEvent>
#include <QStringList>
#include <QTimer>
#include <QTreeView>
#include <QToolButton>
#include <QWidget>

#include <iostream>
#include <string>

namespace
{
// The class names of GridFree's filters start with one of these (after
// "vtk", which ParaView's progress text drops; "P" for the MPI subclass).
const char* const kGridFreeClassStems[] = { "WalkOnSpheres", "PWalkOnSpheres",
  "MovingLeastSquaresInterpolator" };
// Progress texts the filters set themselves (vtkAlgorithm::SetProgressText),
// which ParaView shows instead of the class name.
const char* const kGridFreeProgressTexts[] = { "Walk On Spheres", "Moving Least Squares" };

bool IsGridFreeClassName(const QString& name)
{
  const QString stem = name.startsWith("vtk") ? name.mid(3) : name;
  for (const char* gridFree : kGridFreeClassStems)
  {
    if (stem.startsWith(QLatin1String(gridFree)))
    {
      return true;
    }
  }
  return false;
}

// The first array the domain offers whose name (any case) is one of those
// the property's hint GridFreeSuggestedArrays lists, or "" (its index in
// the domain in `index`).
std::string SuggestedArray(vtkSMProperty* property, vtkSMArrayListDomain* arrays, unsigned int& index)
{
  vtkPVXMLElement* hints = property->GetHints();
  vtkPVXMLElement* suggestion =
    hints ? hints->FindNestedElementByName("GridFreeSuggestedArrays") : nullptr;
  const char* names = suggestion ? suggestion->GetAttribute("names") : nullptr;
  if (!names)
  {
    return std::string();
  }
  const QStringList wanted = QString::fromUtf8(names).split(' ', Qt::SkipEmptyParts);
  for (const QString& name : wanted)
  {
    for (unsigned int k = 0; k < arrays->GetNumberOfStrings(); ++k)
    {
      if (QString::fromUtf8(arrays->GetString(k)).compare(name, Qt::CaseInsensitive) == 0)
      {
        index = k;
        return arrays->GetString(k);
      }
    }
  }
  return std::string();
}

// For GUI tests, at the test's Abort click: prints how many messages the
// Output Messages window holds and whether one is a GridFree projection of
// a long solve, which must be there while the solve still runs.
void ReportOutputMessagesForTest()
{
  QWidget* main = pqCoreUtilities::mainWidget();
  auto* output = main ? main->findChild<pqOutputWidget*>() : nullptr;
  auto* tree = output ? output->findChild<QTreeView*>("treeView") : nullptr;
  QAbstractItemModel* model = tree ? tree->model() : nullptr;
  int rows = model ? model->rowCount() : -1;
  bool projection = false;
  for (int r = 0; r < rows && !projection; ++r)
  {
    projection = model->index(r, 0).data().toString().contains("This solve will take about");
  }
  std::cout << "gridfree test: at the Abort click Output Messages held " << rows
            << " messages, the solve's projection " << (projection ? "among them" : "not among them")
            << std::endl;
}

// User input that could start another pipeline update or close the window.
bool IsUserInput(QEvent::Type type)
{
  switch (type)
  {
    case QEvent::MouseButtonPress:
    case QEvent::MouseButtonRelease:
    case QEvent::MouseButtonDblClick:
    case QEvent::MouseMove:
    case QEvent::Wheel:
    case QEvent::KeyPress:
    case QEvent::KeyRelease:
    case QEvent::Shortcut:
    case QEvent::ShortcutOverride:
    case QEvent::ContextMenu:
    case QEvent::DragEnter:
    case QEvent::DragMove:
    case QEvent::Drop:
    case QEvent::TouchBegin:
    case QEvent::TouchUpdate:
    case QEvent::TouchEnd:
    case QEvent::TabletPress:
    case QEvent::TabletMove:
    case QEvent::TabletRelease:
    case QEvent::NonClientAreaMouseButtonPress:
    case QEvent::NonClientAreaMouseButtonRelease:
    case QEvent::NonClientAreaMouseButtonDblClick:
    case QEvent::Close:
      return true;
    default:
      return false;
  }
}
} // namespace

//-----------------------------------------------------------------------------
pqGridFreeResponsiveSolves::pqGridFreeResponsiveSolves(QObject* parent)
  : Superclass(parent)
{
}

//-----------------------------------------------------------------------------
pqGridFreeResponsiveSolves::~pqGridFreeResponsiveSolves() = default;

//-----------------------------------------------------------------------------
void pqGridFreeResponsiveSolves::onStartup()
{
  bool isNumber = false;
  const double after = qEnvironmentVariable("GRIDFREE_TEST_ABORT_AFTER_SECONDS").toDouble(&isNumber);
  this->TestAbortAfterSeconds = isNumber ? after : -1.0;
  pqProgressManager* progress = pqApplicationCore::instance()->getProgressManager();
  if (!progress)
  {
    return;
  }
  // Direct connections: the slots run inside the filter's progress event,
  // which is the only moment the GUI thread is ours during a solve.
  QObject::connect(progress, &pqProgressManager::progress, this,
    &pqGridFreeResponsiveSolves::onProgress, Qt::DirectConnection);
  QObject::connect(progress, &pqProgressManager::progressEndEvent, this,
    &pqGridFreeResponsiveSolves::onProgressEnd, Qt::DirectConnection);
  QObject::connect(progress, &pqProgressManager::abort, this,
    &pqGridFreeResponsiveSolves::onAbort, Qt::DirectConnection);
  QObject::connect(pqApplicationCore::instance()->getServerManagerModel(),
    &pqServerManagerModel::sourceAdded, this, &pqGridFreeResponsiveSolves::onSourceAdded);
}

//-----------------------------------------------------------------------------
void pqGridFreeResponsiveSolves::onSourceAdded(pqPipelineSource* source)
{
  vtkSMProxy* proxy = source ? source->getProxy() : nullptr;
  if (proxy && proxy->GetVTKClassName() && IsGridFreeClassName(proxy->GetVTKClassName()))
  {
    pqCoreUtilities::connect(proxy, vtkCommand::PropertyModifiedEvent, this,
      SLOT(onPropertyModified(vtkObject*, unsigned long, void*)));
    QObject::connect(source, QOverload<pqPipelineSource*>::of(&pqPipelineSource::dataUpdated),
      this, &pqGridFreeResponsiveSolves::onDataUpdated);
    // A filter created with its Boundary connected: suggested arrays
    // (Boundary Condition Array) are chosen as after Change Input.
    if (proxy->GetProperty("Boundary"))
    {
      vtkSmartPointer<vtkSMProxy> keep = proxy;
      QTimer::singleShot(
        0, this, [keep]() { ReselectArraysOf(keep, "Boundary", /*onlySuggested=*/true); });
    }
  }
}

//-----------------------------------------------------------------------------
void pqGridFreeResponsiveSolves::onDataUpdated(pqPipelineSource* source)
{
  vtkSMProxy* proxy = source->getProxy();
  auto solver = vtkAlgorithm::SafeDownCast(proxy->GetClientSideObject());
  if (!solver || source->modifiedState() != pqProxy::UNMODIFIED)
  {
    return;
  }
  // The walk counts the solver used (Refine doubles them on the solver
  // itself: the walks per point, and a cache's walks per sphere or per
  // cache point).
  bool followed = false;
  for (const char* name : { "WalksPerPoint", "WalksPerSphere", "WalksPerCachePoint" })
  {
    auto walks = vtkSMIntVectorProperty::SafeDownCast(proxy->GetProperty(name));
    vtkSmartPointer<vtkSMIntVectorProperty> info = vtkSMIntVectorProperty::SafeDownCast(
      proxy->GetProperty((std::string(name) + "InUse").c_str()));
    if (!walks || !info)
    {
      continue;
    }
    proxy->UpdatePropertyInformation(info);
    const int inUse = info->GetElement(0);
    if (inUse != walks->GetElement(0) && inUse > 0)
    {
      walks->SetElement(0, inUse);
      followed = true;
    }
  }
  if (followed)
  {
    proxy->UpdateVTKObjects(); // the same values: the solver is not modified
    source->setModifiedState(pqProxy::UNMODIFIED);
  }
}

//-----------------------------------------------------------------------------
void pqGridFreeResponsiveSolves::onPropertyModified(
  vtkObject* object, unsigned long, void* callData)
{
  auto proxy = vtkSMProxy::SafeDownCast(object);
  const char* name = static_cast<const char*>(callData);
  if (!proxy || !name || !vtkSMInputProperty::SafeDownCast(proxy->GetProperty(name)))
  {
    return;
  }
  // At once, so that the selection is pushed with the input (Change Input
  // updates the filter and renders right away); once more after the change
  // is complete, in case the array domain had not yet followed the input.
  ReselectArraysOf(proxy, QString::fromUtf8(name));
  vtkSmartPointer<vtkSMProxy> keep = proxy;
  const QString input = QString::fromUtf8(name);
  QTimer::singleShot(0, this, [keep, input]() { ReselectArraysOf(keep, input); });
}

//-----------------------------------------------------------------------------
void pqGridFreeResponsiveSolves::ReselectArraysOf(
  vtkSMProxy* proxy, const QString& input, bool onlySuggested)
{
  vtkSmartPointer<vtkSMPropertyIterator> it;
  it.TakeReference(proxy->NewPropertyIterator());
  for (it->Begin(); !it->IsAtEnd(); it->Next())
  {
    auto selection = vtkSMStringVectorProperty::SafeDownCast(it->GetProperty());
    // Array selections (SetInputArrayToProcess: index, port, connection,
    // association, name); one left at its XML default holds the index only.
    if (!selection || !selection->GetCommand() ||
      std::string(selection->GetCommand()) != "SetInputArrayToProcess")
    {
      continue;
    }
    vtkSmartPointer<vtkSMDomainIterator> domains;
    domains.TakeReference(selection->NewDomainIterator());
    for (domains->Begin(); !domains->IsAtEnd(); domains->Next())
    {
      auto arrays = vtkSMArrayListDomain::SafeDownCast(domains->GetDomain());
      vtkSMProperty* from = arrays ? arrays->GetRequiredProperty("Input") : nullptr;
      if (!from || from != proxy->GetProperty(input.toUtf8().data()) ||
        arrays->GetNumberOfStrings() == 0)
      {
        continue;
      }
      const char* current =
        selection->GetNumberOfElements() == 5 ? selection->GetElement(4) : nullptr;
      bool offered = false;
      for (unsigned int k = 0; k < arrays->GetNumberOfStrings() && !offered; ++k)
      {
        offered = current && std::string(current) == arrays->GetString(k);
      }
      // None, or an array the new input does not have: one of the names
      // the property suggests (XML hint GridFreeSuggestedArrays), if
      // offered, else the domain's default.
      const bool none = !current || std::string(current).empty() ||
        (arrays->GetNoneString() && std::string(current) == arrays->GetNoneString());
      unsigned int index = 0;
      const std::string suggested = SuggestedArray(selection, arrays, index);
      if (!suggested.empty() && (onlySuggested || !offered || none))
      {
        // On creation the selection is the domain's default (the active
        // scalars, say), not a choice: a suggested name wins, with its own
        // association (a cell array stays one).
        selection->SetElement(3, std::to_string(arrays->GetFieldAssociation(index)).c_str());
        selection->SetElement(4, suggested.c_str());
      }
      else if (!offered && !onlySuggested)
      {
        selection->ResetToDomainDefaults();
      }
    }
  }
}

//-----------------------------------------------------------------------------
void pqGridFreeResponsiveSolves::onShutdown()
{
  if (pqProgressManager* progress = pqApplicationCore::instance()->getProgressManager())
  {
    QObject::disconnect(progress, nullptr, this, nullptr);
  }
}

//-----------------------------------------------------------------------------
bool pqGridFreeResponsiveSolves::IsGridFreeProgress(const QString& text)
{
  const QString trimmed = text.trimmed();
  for (const char* gridFree : kGridFreeProgressTexts)
  {
    if (trimmed.startsWith(QLatin1String(gridFree)))
    {
      return true;
    }
  }
  return IsGridFreeClassName(trimmed);
}

//-----------------------------------------------------------------------------
void pqGridFreeResponsiveSolves::onProgress(const QString& text, int)
{
  if (this->ProcessingEvents || !IsGridFreeProgress(text))
  {
    return;
  }
  pqProgressManager* progress = pqApplicationCore::instance()->getProgressManager();
  if (!this->AbortButton)
  {
    if (QWidget* main = pqCoreUtilities::mainWidget())
    {
      this->AbortButton = main->findChild<QToolButton*>("AbortButton");
    }
  }
  if (!this->AbortEnabled)
  {
    this->AbortEnabled = true;
    progress->setEnableAbort(true);
    this->Running.start();
  }
  if (this->TestAbortAfterSeconds >= 0.0 && this->AbortButton &&
    this->Running.elapsed() >= 1000.0 * this->TestAbortAfterSeconds)
  {
    this->TestAbortAfterSeconds = -1.0; // once
    ReportOutputMessagesForTest();
    this->AbortButton->click();
  }

  this->ProcessPendingEvents(false);
}

//-----------------------------------------------------------------------------
// Pending window events only: repaints, the progress bar, the Output
// Messages window, and (unless `discardAll`) a click on Abort. Other input
// is discarded by eventFilter; timers (delayed renders, auto-apply) and
// server sockets wait until the filter has finished.
void pqGridFreeResponsiveSolves::ProcessPendingEvents(bool discardAll)
{
  pqProgressManager* progress = pqApplicationCore::instance()->getProgressManager();
  this->ProcessingEvents = true;
  this->Filtering = true;
  this->OnlyDiscarding = discardAll;
  qApp->installEventFilter(this);
  const bool wasUnblocked = progress->unblockEvents(true);
  QCoreApplication::processEvents(QEventLoop::X11ExcludeTimers | QEventLoop::ExcludeSocketNotifiers);
  progress->unblockEvents(wasUnblocked);
  qApp->removeEventFilter(this);
  this->OnlyDiscarding = false;
  this->Filtering = false;
  this->ProcessingEvents = false;
}

//-----------------------------------------------------------------------------
void pqGridFreeResponsiveSolves::onProgressEnd()
{
  if (!this->AbortEnabled)
  {
    return;
  }
  this->AbortEnabled = false;
  pqApplicationCore::instance()->getProgressManager()->setEnableAbort(false);
  // Clicks and keys made during the solve that have not reached the window
  // yet (those since the last progress report): discarded, not acted on
  // now that the solve is over.
  if (!this->ProcessingEvents)
  {
    this->ProcessPendingEvents(true);
  }
  if (this->AbortRequested)
  {
    this->AbortRequested = false;
    this->AfterAbort();
  }
}

//-----------------------------------------------------------------------------
// VTK 9.2 leaves AbortExecute set once a filter has been aborted, so every
// later update of it would stop at once: the flag is cleared when the
// aborted update has ended. A solver that was aborted keeps what it ran;
// Apply is lit for it, and Apply continues the solve (Resume).
void pqGridFreeResponsiveSolves::AfterAbort()
{
  pqServerManagerModel* model = pqApplicationCore::instance()->getServerManagerModel();
  if (!model)
  {
    return;
  }
  for (pqPipelineSource* source : model->findItems<pqPipelineSource*>())
  {
    vtkSMProxy* proxy = source->getProxy();
    auto algorithm = vtkAlgorithm::SafeDownCast(proxy ? proxy->GetClientSideObject() : nullptr);
    if (!algorithm || !IsGridFreeClassName(QString::fromUtf8(algorithm->GetClassName())))
    {
      continue;
    }
    // The flag alone: SetAbortExecute would mark the filter modified, and
    // the next render would run it again.
    algorithm->AbortExecute = 0;
    vtkSMProperty* aborted = proxy->GetProperty("LastSolveAborted");
    if (!aborted || !proxy->GetProperty("Resume"))
    {
      continue;
    }
    proxy->UpdatePropertyInformation(aborted);
    if (vtkSMPropertyHelper(aborted).GetAsInt() == 0)
    {
      continue;
    }
    this->Aborted.insert(source);
    if (source->modifiedState() == pqProxy::UNMODIFIED)
    {
      source->setModifiedState(pqProxy::MODIFIED);
    }
  }
  if (QWidget* main = pqCoreUtilities::mainWidget())
  {
    for (pqPropertiesPanel* panel : main->findChildren<pqPropertiesPanel*>())
    {
      QObject::connect(panel, QOverload<pqProxy*>::of(&pqPropertiesPanel::applied), this,
        &pqGridFreeResponsiveSolves::onApplied, Qt::UniqueConnection);
    }
  }
}

//-----------------------------------------------------------------------------
// Apply after an Abort: the solver's settings may be the same as those of
// the aborted solve (nothing else marks it modified), so it is told to
// continue before ParaView updates the pipeline.
void pqGridFreeResponsiveSolves::onApplied(pqProxy* applied)
{
  auto source = qobject_cast<pqPipelineSource*>(applied);
  if (!source || !this->Aborted.contains(source))
  {
    return;
  }
  this->Aborted.remove(source);
  if (vtkSMProxy* proxy = source->getProxy())
  {
    proxy->InvokeCommand("Resume");
  }
}

//-----------------------------------------------------------------------------
bool pqGridFreeResponsiveSolves::IsOnAbortButton(QObject* watched, QEvent* event) const
{
  auto stops = [this](const QObject* object) {
    return object &&
      ((object == this->AbortButton.data() && this->AbortButton->isEnabled()) ||
        object->property("gridfreeClickableDuringSolves").toBool());
  };
  if (stops(watched))
  {
    return true;
  }
  // A click reaches the window first, then the widget under the pointer.
  if (event->type() == QEvent::MouseButtonPress || event->type() == QEvent::MouseButtonRelease)
  {
    const QPoint global = static_cast<QMouseEvent*>(event)->globalPos();
    return stops(QApplication::widgetAt(global));
  }
  return false;
}

//-----------------------------------------------------------------------------
bool pqGridFreeResponsiveSolves::eventFilter(QObject* watched, QEvent* event)
{
  if (this->Filtering && IsUserInput(event->type()) &&
    (this->OnlyDiscarding || !this->IsOnAbortButton(watched, event)))
  {
    return true; // discarded: nothing may start while the filter runs
  }
  return this->Superclass::eventFilter(watched, event);
}

//-----------------------------------------------------------------------------
void pqGridFreeResponsiveSolves::onAbort()
{
  this->AbortRequested = AbortGridFreeFilters() || this->AbortRequested;
}

//-----------------------------------------------------------------------------
bool pqGridFreeResponsiveSolves::AbortGridFreeFilters()
{
  pqServerManagerModel* model = pqApplicationCore::instance()->getServerManagerModel();
  if (!model)
  {
    return false;
  }
  bool found = false;
  for (pqPipelineSource* source : model->findItems<pqPipelineSource*>())
  {
    vtkSMProxy* proxy = source->getProxy();
    // Null unless the server is built in (the algorithm lives in this process).
    auto algorithm = vtkAlgorithm::SafeDownCast(proxy ? proxy->GetClientSideObject() : nullptr);
    if (algorithm && IsGridFreeClassName(QString::fromUtf8(algorithm->GetClassName())))
    {
      // Not SetAbortExecute, which marks the filter modified: the filters
      // that do not run now would run again at the next render, and the
      // solver would forget the walks it ran.
      algorithm->AbortExecute = 1;
      found = true;
    }
  }
  return found;
}
