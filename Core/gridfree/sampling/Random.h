// Reproducible random streams for walk-on-spheres estimators.
//
// Every walk draws from its own stream, keyed by (global seed, probe point
// coordinates, walk number). Keying on coordinates instead of a point index
// keeps results identical when ParaView repartitions a dataset or when the
// number of threads changes: a point's estimate depends on nothing else.
#ifndef GRIDFREE_SAMPLING_RANDOM_H
#define GRIDFREE_SAMPLING_RANDOM_H

#include <pcg_random.hpp>

#include <cstdint>
#include <cstring>

namespace gridfree
{
// SplitMix64 finalizer: a bijective mixer with full avalanche, used to turn
// structured keys (small integers, nearby coordinates) into well-spread seeds.
inline std::uint64_t MixBits(std::uint64_t z)
{
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// Combines a running hash with one more 64-bit word (order-dependent).
inline std::uint64_t HashCombine(std::uint64_t hash, std::uint64_t word)
{
  return MixBits(hash ^ MixBits(word));
}

inline std::uint64_t DoubleBits(double value)
{
  // +0.0 and -0.0 are the same point; make them the same key.
  if (value == 0.0)
  {
    value = 0.0;
  }
  std::uint64_t bits;
  std::memcpy(&bits, &value, sizeof(bits));
  return bits;
}

// Hash of a probe point: the global seed and the exact bits of its three
// coordinates (2D problems pass z as given by the probe).
inline std::uint64_t PointKey(std::uint64_t seed, const double xyz[3])
{
  std::uint64_t h = MixBits(seed);
  for (int i = 0; i < 3; ++i)
  {
    h = HashCombine(h, DoubleBits(xyz[i]));
  }
  return h;
}

// A fast, statistically strong generator (PCG-XSH-RR 64/32) for one walk.
class RandomStream
{
public:
  RandomStream(std::uint64_t pointKey, std::uint64_t walkIndex)
    : Engine(HashCombine(pointKey, walkIndex), MixBits(walkIndex ^ 0x5851f42d4c957f2dULL))
  {
  }

  std::uint32_t NextUInt32() { return this->Engine(); }

  // Uniform double in [0, 1) with 53 random bits.
  double NextDouble()
  {
    const std::uint64_t hi = this->Engine();
    const std::uint64_t lo = this->Engine();
    const std::uint64_t bits53 = ((hi << 32) | lo) >> 11;
    return static_cast<double>(bits53) * 0x1.0p-53;
  }

private:
  pcg32 Engine;
};
} // namespace gridfree

#endif
