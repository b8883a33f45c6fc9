// Choice of instruction set for the hot geometry searches, made at run time.
//
// The library is compiled for the x86-64 baseline (SSE2), so it runs on any
// 64-bit x86 CPU. The searches of Bvh.h are compiled a second and a third
// time, for AVX2 (with FMA and BMI) and for AVX-512 (F, VL, BW, DQ), through
// GCC's target attribute, and each hierarchy picks one when it is created:
// the best the CPU and the operating system support (CPUID and XGETBV, through
// __builtin_cpu_supports), unless lowered by the environment variable
// GRIDFREE_SIMD=sse2|avx2|avx512 or by Bvh::SetSimdLevel. Nothing is assumed
// about the user's CPU.
//
// All paths return bit-identical answers. The source is the same; only the
// encoding and the register allocation differ, and floating-point
// contraction is switched off in the retargeted functions (GCC would
// otherwise fuse a * b + c into one rounding where FMA exists), so every
// operation rounds as it does on the baseline. Explicit std::fma calls (the
// exact ray signs) become one instruction instead of a library call.
//
// Other compilers and architectures compile only the baseline path.
#ifndef GRIDFREE_GEOMETRY_SIMD_DISPATCH_H
#define GRIDFREE_GEOMETRY_SIMD_DISPATCH_H

#include <cstdlib>
#include <cstring>

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) &&                        \
  !defined(GRIDFREE_BVH_SCALAR) && !defined(GRIDFREE_NO_SIMD_DISPATCH)
#define GRIDFREE_SIMD_DISPATCH 1
// flatten inlines every callee, so the whole search, kernels included, is
// compiled for the target; fp-contract=off keeps the baseline's roundings.
#define GRIDFREE_TARGET_AVX2                                                                    \
  __attribute__((target("avx2,fma,bmi,bmi2,popcnt"), optimize("fp-contract=off"), flatten))
#define GRIDFREE_TARGET_AVX512                                                                  \
  __attribute__((target("avx512f,avx512vl,avx512bw,avx512dq,avx2,fma,bmi,bmi2,popcnt"),       \
    optimize("fp-contract=off"), flatten))
#endif

namespace gridfree
{
/// Instruction sets the searches are compiled for, in increasing order.
enum class SimdLevel : int
{
  Sse2 = 0,   // x86-64 baseline (or the portable code elsewhere)
  Avx2 = 1,   // AVX2 + FMA + BMI1/2
  Avx512 = 2, // AVX-512 F, VL, BW, DQ
};

inline const char* SimdLevelName(SimdLevel level)
{
  switch (level)
  {
    case SimdLevel::Avx512:
      return "avx512";
    case SimdLevel::Avx2:
      return "avx2";
    default:
      return "sse2";
  }
}

/// Parses "sse2", "avx2" or "avx512" (as GRIDFREE_SIMD takes them).
inline bool ParseSimdLevel(const char* text, SimdLevel& level)
{
  if (!text)
  {
    return false;
  }
  for (const SimdLevel l : { SimdLevel::Sse2, SimdLevel::Avx2, SimdLevel::Avx512 })
  {
    if (std::strcmp(text, SimdLevelName(l)) == 0)
    {
      level = l;
      return true;
    }
  }
  return false;
}

/// The best level this build can run on this CPU (always Sse2 when the
/// build has no dispatch).
inline SimdLevel CpuSimdLevel()
{
#ifdef GRIDFREE_SIMD_DISPATCH
  static const SimdLevel level = []()
  {
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
      __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq") &&
      __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
      __builtin_cpu_supports("bmi") && __builtin_cpu_supports("bmi2") &&
      __builtin_cpu_supports("popcnt"))
    {
      return SimdLevel::Avx512;
    }
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
      __builtin_cpu_supports("bmi") && __builtin_cpu_supports("bmi2") &&
      __builtin_cpu_supports("popcnt"))
    {
      return SimdLevel::Avx2;
    }
    return SimdLevel::Sse2;
  }();
  return level;
#else
  return SimdLevel::Sse2;
#endif
}

/// The level new hierarchies use: CpuSimdLevel(), lowered by GRIDFREE_SIMD
/// when that names a lower one (read once; an unknown value is ignored).
inline SimdLevel DefaultSimdLevel()
{
  static const SimdLevel level = []()
  {
    SimdLevel requested;
    const SimdLevel cpu = CpuSimdLevel();
    if (ParseSimdLevel(std::getenv("GRIDFREE_SIMD"), requested) && requested < cpu)
    {
      return requested;
    }
    return cpu;
  }();
  return level;
}
} // namespace gridfree

#endif
