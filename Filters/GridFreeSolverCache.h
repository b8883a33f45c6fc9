// What vtkWalkOnSpheresSolver keeps between executions for progressive
// refinement: the running sums, with what they were computed from (the
// built boundary is kept by its GridFreeProblemBuilder).
// Private to the GridFree::Filters module.
#ifndef GridFreeSolverCache_h
#define GridFreeSolverCache_h

#include "GridFreeInputFingerprint.h"
#include "vtkType.h"

#include <gridfree/statistics/RunningSumsCache.h>

#include <array>
#include <cstdint>
#include <vector>

class vtkObject;

// The running sums kept for progressive refinement, with what they were
// computed from: the settings (every property but WalksPerPoint), and the
// inputs and the implicit function by their fingerprints.
struct vtkWalkOnSpheresSolverCache
{
  gridfree::RunningSumsCache Sums;
  vtkMTimeType Settings = 0;
  std::vector<std::uint64_t> Inputs;

  // `gathered`: the signature of the pieces gathered from other ranks (0 in
  // a serial run).
  static std::vector<std::uint64_t> Fingerprint(
    const std::array<vtkObject*, 4>& objects, std::uint64_t gathered)
  {
    std::vector<std::uint64_t> print{ gathered };
    for (vtkObject* object : objects)
    {
      gridfree::AppendFingerprint(object, print);
      print.push_back(~std::uint64_t(0)); // separates the inputs
    }
    return print;
  }

  // Forgets the sums unless they were computed from these very inputs and
  // settings.
  void Validate(vtkMTimeType settings, const std::array<vtkObject*, 4>& objects,
    std::uint64_t gathered)
  {
    if (settings != this->Settings || Fingerprint(objects, gathered) != this->Inputs)
    {
      this->Sums.Clear();
    }
  }

  // Remembers what the sums just kept come from.
  void Remember(vtkMTimeType settings, const std::array<vtkObject*, 4>& objects,
    std::uint64_t gathered)
  {
    this->Settings = settings;
    this->Inputs = Fingerprint(objects, gathered);
  }
};

#endif
