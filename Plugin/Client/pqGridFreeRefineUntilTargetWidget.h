/**
 * @class   pqGridFreeRefineUntilTargetWidget
 * @brief   The solver's Refine Until Target button: a progressive preview that
 *          refines round after round, shows each round, and stops at the
 *          target or when the user stops it.
 *
 * For a property with panel_widget="gridfree_refine_until_target" whose
 * command refines the solver (Refine: doubles WalksPerPoint). In the
 * target-error mode a refined solve keeps the points that reached the target
 * and continues the others (vtkWalkOnSpheresSolver::SetTargetStandardError),
 * so each round costs only the walks of the points still above the target.
 *
 * A click runs rounds until the solver's information property
 * PointsShortOfTarget is 0 (every point at or below the target), the walks
 * per point reach kMostWalksPerPoint, a solve is aborted (the progress
 * bar's Abort), or the button, which reads "Stop Refining" meanwhile, is
 * clicked again: then the round in progress completes and no other starts,
 * so the output stays that of a whole round. Each round invokes the
 * command, updates the solver and renders every view, so the picture
 * sharpens round by round. The button is let through while a solve runs
 * (pqGridFreeResponsiveSolves).
 */
#ifndef pqGridFreeRefineUntilTargetWidget_h
#define pqGridFreeRefineUntilTargetWidget_h

#include "pqPropertyWidget.h"

class QPushButton;

class pqGridFreeRefineUntilTargetWidget : public pqPropertyWidget
{
  Q_OBJECT
  typedef pqPropertyWidget Superclass;

public:
  pqGridFreeRefineUntilTargetWidget(
    vtkSMProxy* proxy, vtkSMProperty* property, QWidget* parent = nullptr);
  ~pqGridFreeRefineUntilTargetWidget() override;

  /// Rounds stop once the walks per point reach this many.
  static constexpr int kMostWalksPerPoint = 1 << 20;

private Q_SLOTS:
  void onClicked();

private:
  void RunRounds();
  bool Refine();

  QPushButton* Button = nullptr;
  QString Label;
  bool Running = false;
  bool StopRequested = false;

  Q_DISABLE_COPY(pqGridFreeRefineUntilTargetWidget)
};

#endif
