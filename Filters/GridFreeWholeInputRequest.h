// Asks an input connection for its whole data: piece 0 of 1, no ghost
// levels, the whole extent of structured data. Used for the inputs every
// piece of a filter's output needs entirely (the boundary, the source term,
// the samples of an interpolation). Does nothing for an unconnected input.
// Private to the GridFree::Filters module.
#ifndef GridFreeWholeInputRequest_h
#define GridFreeWholeInputRequest_h

#include "vtkInformation.h"
#include "vtkStreamingDemandDrivenPipeline.h"

namespace gridfree
{
inline void RequestWholeInput(vtkInformation* info)
{
  if (!info)
  {
    return;
  }
  info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), 0);
  info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), 1);
  info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
  if (info->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
  {
    info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(),
      info->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()), 6);
  }
}
} // namespace gridfree

#endif
