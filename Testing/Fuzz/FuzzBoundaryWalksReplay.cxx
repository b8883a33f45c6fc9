// Replays inputs through the fuzz body without libFuzzer: each argument is a
// file or a directory of files. Exits nonzero if an argument cannot be read;
// a finding aborts (or is reported by the sanitizers).
#include "FuzzBoundaryWalks.h"

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

namespace
{
bool Replay(const std::filesystem::path& file)
{
  std::ifstream in(file, std::ios::binary);
  if (!in)
  {
    std::fprintf(stderr, "cannot read %s\n", file.c_str());
    return false;
  }
  const std::vector<std::uint8_t> bytes(
    (std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::printf("%s (%zu bytes)\n", file.c_str(), bytes.size());
  std::fflush(stdout);
  gridfree::fuzz::RunBoundaryWalks(bytes.data(), bytes.size());
  return true;
}
} // namespace

int main(int argc, char* argv[])
{
  bool ok = true;
  int count = 0;
  for (int i = 1; i < argc; ++i)
  {
    const std::filesystem::path arg(argv[i]);
    if (std::filesystem::is_directory(arg))
    {
      for (const auto& entry : std::filesystem::directory_iterator(arg))
      {
        if (entry.is_regular_file())
        {
          ok = Replay(entry.path()) && ok;
          ++count;
        }
      }
    }
    else
    {
      ok = Replay(arg) && ok;
      ++count;
    }
  }
  std::printf("replayed %d inputs\n", count);
  return ok ? 0 : 1;
}
