// Distributed runs: every rank of a vtkMultiProcessController holds a piece
// of the boundary (and of the source), and every rank needs all of it, since
// a walk may reach any part of the boundary. RequestPiece asks an input for
// this rank's piece; GatherPieces exchanges the pieces and merges them, in
// rank order, into the whole on every rank.
//
// Pieces that are empty, or byte for byte equal to the piece of a lower rank,
// are left out: an upstream that ignores piece requests (a vtkTrivialProducer,
// a legacy reader) gives every rank the whole dataset, which must count once.
// Merging in rank order makes the whole equal to the serial dataset when the
// serial dataset is the concatenation of the pieces in piece order (a .pvtp
// or .pvti file, a piece-aware source), so results stay bit-identical.
// Private to the GridFree::Filters module.
#ifndef GridFreePieceGather_h
#define GridFreePieceGather_h

#include "vtkSmartPointer.h"

#include <cstdint>
#include <string>

class vtkDataObject;
class vtkInformation;
class vtkMultiProcessController;

namespace gridfree
{
// Asks an input connection for piece `piece` of `pieces`, no ghost levels
// (structured data: the block of its extent the executive derives from the
// piece). Does nothing for an unconnected input.
void RequestPiece(vtkInformation* info, int piece, int pieces);

struct GatheredPieces
{
  // The merged dataset (the type of the pieces: vtkPolyData, vtkImageData,
  // a composite of such leaves; other datasets become a vtkUnstructuredGrid).
  // Null when every rank's piece was empty or missing.
  vtkSmartPointer<vtkDataObject> Whole;
  // Ranks whose piece was used (not empty, not a copy of a lower rank's).
  int ContributingRanks = 0;
  // A hash of every rank's piece: equal only if no piece changed. Lets a
  // cache keyed on the inputs survive a re-execution with the same data.
  std::uint64_t Signature = 0;
};

// Collective: every rank of `controller` must call it, each with its own
// piece (null for none). Returns false with a reason when the pieces cannot
// be merged (different types, images on different grids, more than 2 GiB).
// The reason is the same on every rank, so every rank fails together.
bool GatherPieces(vtkMultiProcessController* controller, vtkDataObject* piece,
  GatheredPieces& out, std::string& reason);
} // namespace gridfree

// The Boundary and Source inputs a solve uses (vtkWalkOnSpheresSolver's
// GatherInputs): as received (Whole set to them, no signature), or, in a
// distributed run (vtkPWalkOnSpheresSolver), every rank's pieces merged.
struct vtkWalkOnSpheresSolverPieces
{
  bool Distributed = false; // this rank solves its piece of a distributed probe
  gridfree::GatheredPieces Boundary;
  gridfree::GatheredPieces Source;
};

#endif
