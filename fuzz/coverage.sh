#!/usr/bin/env bash
# Line coverage of src/ from replaying the fuzz corpus (llvm-cov).
#   fuzz/coverage.sh            -> summary table; HTML in build-cov/coverage/index.html
# Replays every target's corpus. The build runs CMAKE_BUILD_PARALLEL_LEVEL jobs (default: the cores).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build="$root/build-cov"
if [ ! -f "$build/build.ninja" ]; then
  CC=clang CXX=clang++ cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Debug -DQEX_COVERAGE=ON \
    -DQEX_BUILD_TESTS=OFF -DQEX_BUILD_CLI=OFF -DQEX_BUILD_FUZZERS=ON >/dev/null
fi
cmake --build "$build" --parallel "${CMAKE_BUILD_PARALLEL_LEVEL:-$(getconf _NPROCESSORS_ONLN)}" --target fuzzers
rm -f "$build"/*.profraw
objects=()
for t in fuzz_obj fuzz_ply fuzz_extract fuzz_sanitize fuzz_predicates_differential fuzz_layout; do
  LLVM_PROFILE_FILE="$build/$t.profraw" "$build/fuzz/$t" "$root/corpus/$t" >/dev/null
  objects+=(-object "$build/fuzz/$t")
done
llvm-profdata merge -sparse "$build"/*.profraw -o "$build/corpus.profdata"
llvm-cov report "${objects[@]:1}" -instr-profile="$build/corpus.profdata" "$root/src" \
  -ignore-filename-regex='src/cli/.*'
llvm-cov show "${objects[@]:1}" -instr-profile="$build/corpus.profdata" "$root/src" \
  -ignore-filename-regex='src/cli/.*' -format=html -output-dir="$build/coverage" >/dev/null
echo "HTML: $build/coverage/index.html"
