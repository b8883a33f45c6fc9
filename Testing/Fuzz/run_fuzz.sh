#!/usr/bin/env bash
# Builds the libFuzzer target over the estimator core (clang, ASan + UBSan)
# in build-fuzz/ and fuzzes it for a bounded time.
#
#   Testing/Fuzz/run_fuzz.sh [seconds]     default 60
#
# Environment: FUZZ_RSS_MB (memory limit, default 2048), FUZZ_TIMEOUT (seconds
# per input, default 10), FUZZ_JOBS (build jobs, default 2),
# GRIDFREE_FUZZ_BUILD_DIR (default ./build-fuzz).
# The corpus grows in build-fuzz/corpus (seeded from the bundled CT mesh by
# make_seed_corpus.py); crashes, timeouts and OOMs are written to
# build-fuzz/artifacts/. Exits nonzero on any of them, or if the regression
# inputs in Testing/Fuzz/regressions/ no longer pass.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
BUILD="${GRIDFREE_FUZZ_BUILD_DIR:-$ROOT/build-fuzz}"
SECONDS_TO_RUN="${1:-60}"
RSS_MB="${FUZZ_RSS_MB:-2048}"
TIMEOUT="${FUZZ_TIMEOUT:-10}"
JOBS="${FUZZ_JOBS:-2}"

log() { printf '\033[1m[fuzz]\033[0m %s\n' "$*" >&2; }

if ! command -v clang++ >/dev/null 2>&1; then
  log "clang++ not found: apt-get install clang libclang-rt-14-dev"
  exit 2
fi

if [[ ! -f "$BUILD/CMakeCache.txt" ]]; then
  log "configuring in $BUILD"
  cmake -S "$ROOT/Testing/Fuzz" --preset fuzz -B "$BUILD" \
    >"$BUILD.configure.log" 2>&1 || { cat "$BUILD.configure.log" >&2; exit 2; }
  mv "$BUILD.configure.log" "$BUILD/configure.log"
fi
log "building (-j$JOBS)"
if ! cmake --build "$BUILD" -j"$JOBS" >"$BUILD/build.log" 2>&1; then
  grep -E -B2 -A8 "error" "$BUILD/build.log" | head -60 >&2
  exit 2
fi

mkdir -p "$BUILD/corpus" "$BUILD/artifacts"
if [[ ! -d "$BUILD/seeds" ]]; then
  log "writing the seed corpus from Data/"
  /usr/bin/python3 "$ROOT/Testing/Fuzz/make_seed_corpus.py" "$BUILD/seeds" >&2 ||
    { log "no seeds (needs python3 with vtkmodules): starting from an empty corpus"; mkdir -p "$BUILD/seeds"; }
fi

log "replaying the regression inputs"
"$BUILD/FuzzBoundaryWalksReplay" "$ROOT/Testing/Fuzz/regressions" >/dev/null

log "fuzzing for ${SECONDS_TO_RUN} s (rss limit ${RSS_MB} MB, ${TIMEOUT} s per input)"
before=$(find "$BUILD/artifacts" -type f | wc -l)
set +e
(cd "$BUILD" && ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}" \
  UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1}" \
  ./FuzzBoundaryWalks -max_total_time="$SECONDS_TO_RUN" -rss_limit_mb="$RSS_MB" \
  -malloc_limit_mb="$RSS_MB" -timeout="$TIMEOUT" -max_len=8192 -print_final_stats=1 \
  -artifact_prefix="$BUILD/artifacts/" corpus seeds) 2>&1 | tee "$BUILD/fuzz.log" |
  grep -E --line-buffered 'pulse|DONE|INITED|ERROR|SUMMARY|invariant|Test unit written|stat::'
status=${PIPESTATUS[0]}
set -e
after=$(find "$BUILD/artifacts" -type f | wc -l)
if [[ $status -ne 0 || $after -gt $before ]]; then
  log "finding(s): see $BUILD/fuzz.log and $BUILD/artifacts/ (exit $status)"
  exit 1
fi
log "no finding; corpus: $(find "$BUILD/corpus" -type f | wc -l) inputs"
