// libFuzzer entry point of the boundary-soup fuzz target; the body is in
// FuzzBoundaryWalks.h so that the regression test can replay findings.
#include "FuzzBoundaryWalks.h"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  return gridfree::fuzz::RunBoundaryWalks(data, size);
}
