#!/usr/bin/env bash
# Runs one fuzz target under libFuzzer with address and undefined-behaviour sanitizers.
#   fuzz/run.sh TARGET [SECONDS=600] [JOBS=2]
# Builds into build-fuzz/ with clang, fuzzes a scratch copy of corpus/TARGET, merges new coverage
# back into corpus/TARGET/merged/, and prints exec/s and coverage from the log.
set -euo pipefail
target=${1:?usage: fuzz/run.sh TARGET [SECONDS] [JOBS]}
seconds=${2:-600}
jobs=${3:-2}
root=$(cd "$(dirname "$0")/.." && pwd)
build="$root/build-fuzz"
if [ ! -f "$build/build.ninja" ]; then
  CC=clang CXX=clang++ cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DQEX_LIBFUZZER=ON -DQEX_BUILD_TESTS=OFF -DQEX_BUILD_CLI=OFF -DQEX_BUILD_FUZZERS=ON >/dev/null
fi
cmake --build "$build" --target "$target"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/corpus" "$root/corpus/$target/merged" "$work/artifacts"
find "$root/corpus/$target" -type f ! -name '*.md' -exec cp {} "$work/corpus/" \;
cd "$work"
"$build/fuzz/$target" -max_total_time="$seconds" -fork="$jobs" -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 \
  -timeout=30 -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 -artifact_prefix="$work/artifacts/" \
  "$work/corpus" >"$work/log" 2>&1 || true
grep -E "exec/s|cov:" "$work/log" | tail -n 2
grep -E "stat::" "$work/log" | tail -n 8 || true
if ls "$work/artifacts"/* >/dev/null 2>&1; then
  mkdir -p "$root/corpus/$target/regressions"
  for a in "$work/artifacts"/*; do cp "$a" "$root/corpus/$target/regressions/$(sha1sum "$a" | cut -c1-16)"; done
  echo "FINDINGS copied to corpus/$target/regressions/ (add a note of what each found)"
fi
"$build/fuzz/$target" -merge=1 "$root/corpus/$target/merged" "$work/corpus" >/dev/null 2>&1 || true
echo "corpus: $(find "$root/corpus/$target" -type f | wc -l) files"
