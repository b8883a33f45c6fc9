/**
 * @class   pqGridFreeResponsiveSolves
 * @brief   Keeps the ParaView GUI alive while a GridFree filter runs, and makes
 *          its Abort button stop the filter.
 *
 * ParaView 5.11 runs filters on the GUI thread of the built-in server and
 * does not process events while they run: the window is not repainted, and
 * the progress bar's Abort button is never enabled nor connected to anything.
 * While a GridFree filter reports progress (which its solves do every tenth
 * of a second), this auto-start component
 *  - enables the Abort button and processes pending window events, so the
 *    window repaints, progress and warnings show, and a click on Abort
 *    arrives; every other user input (clicks, keys, the wheel, closing the
 *    window) is discarded until the filter ends, so nothing can start another
 *    update in the middle of this one; timers and server sockets are not
 *    processed either;
 *  - on Abort, sets AbortExecute on the GridFree algorithms of the built-in
 *    server: the running one stops within a progress interval and reports
 *    what it did not finish. When the aborted update has ended it clears
 *    the flag again (VTK 9.2 would leave it set, and every later update
 *    would stop at once), discards the clicks and keys that queued up
 *    during the solve, and lights Apply for an aborted solver: Apply then
 *    continues its solve from the walks already run (its Resume command),
 *    even with no property changed.
 * A widget that carries the dynamic property "gridfreeClickableDuringSolves"
 * (Refine Until Target's button, to stop its rounds) is let through too.
 * With a remote server the Abort button stays as ParaView leaves it: the
 * server cannot be reached while it computes.
 *
 * It also re-selects an array when an input changes: after Change Input
 * connects a Source (or another Boundary) to a GridFree filter, each array
 * selection of that input that names no array of it (Source Array still
 * holding its XML default) takes the input's first suitable array, as it
 * would have had the input been connected when the filter was created. A
 * selection whose XML hint GridFreeSuggestedArrays lists names (Boundary
 * Condition Array: bc, Condition, ...) takes an array of one of those
 * names when the filter is created, and while it is None after Change
 * Input, so that a boundary that carries its conditions needs no pick.
 *
 * And it keeps the panel's Walks Per Point true after Refine, which doubles
 * the walks on the solver itself: once the solver has updated, the property
 * takes the solver's count (without marking the filter modified).
 *
 * For GUI tests (event playback cannot click while a filter runs: the
 * playback waits for the click that started it), the environment variable
 * GRIDFREE_TEST_ABORT_AFTER_SECONDS makes it click Abort itself once a
 * GridFree filter has run that long, printing first what the Output
 * Messages window holds at that moment.
 */
#ifndef pqGridFreeResponsiveSolves_h
#define pqGridFreeResponsiveSolves_h

#include <QElapsedTimer>
#include <QObject>
#include <QPointer>
#include <QSet>

class QToolButton;
class pqPipelineSource;
class pqProxy;
class vtkObject;
class vtkSMProxy;

class pqGridFreeResponsiveSolves : public QObject
{
  Q_OBJECT
  typedef QObject Superclass;

public:
  explicit pqGridFreeResponsiveSolves(QObject* parent = nullptr);
  ~pqGridFreeResponsiveSolves() override;

  void onStartup();
  void onShutdown();

  /// True for the progress text of a GridFree filter (its class name
  /// without the "vtk" prefix, as ParaView shows it).
  static bool IsGridFreeProgress(const QString& text);

  /// Sets AbortExecute on the GridFree algorithms of the built-in server
  /// (what Abort does); false when none was found.
  static bool AbortGridFreeFilters();

protected:
  bool eventFilter(QObject* watched, QEvent* event) override;

private Q_SLOTS:
  void onProgress(const QString& text, int percent);
  void onProgressEnd();
  void onAbort();
  void onSourceAdded(pqPipelineSource* source);
  void onPropertyModified(vtkObject* proxy, unsigned long, void* name);
  void onDataUpdated(pqPipelineSource* source);
  void onApplied(pqProxy* proxy);

private:
  void ProcessPendingEvents(bool discardAll);
  void AfterAbort();
  bool IsOnAbortButton(QObject* watched, QEvent* event) const;
  // After `input` changed: each array selection of it that names no array
  // of it (or None, where the XML suggests names) is chosen again; with
  // `onlySuggested` (a new filter), only selections with a suggested name
  // offered, which takes their place.
  static void ReselectArraysOf(vtkSMProxy* proxy, const QString& input, bool onlySuggested = false);

  QPointer<QToolButton> AbortButton;
  QElapsedTimer Running;
  double TestAbortAfterSeconds = -1.0;
  bool ProcessingEvents = false;
  bool AbortEnabled = false;
  bool Filtering = false;
  bool OnlyDiscarding = false; // no click gets through, Abort's neither
  bool AbortRequested = false;
  // Solvers whose next Apply resumes (compared, not followed: the one
  // applied is alive).
  QSet<pqPipelineSource*> Aborted;

  Q_DISABLE_COPY(pqGridFreeResponsiveSolves)
};

#endif
