#!/usr/bin/env bash
# Runs one fuzz target under libFuzzer with address and undefined-behaviour sanitizers.
#   fuzz/run.sh TARGET [SECONDS=600] [JOBS=number of cores]
# Builds into build-fuzz/ with clang, fuzzes a scratch copy of corpus/TARGET (with fuzz/obj.dict
# or fuzz/ply.dict for fuzz_obj and fuzz_ply), copies findings to corpus/TARGET/regressions/,
# keeps the units of new coverage in corpus/TARGET/merged/, and prints the run's numbers.
# The log and the artifacts stay in build-fuzz/run/. fuzz/campaign.sh runs every target.
set -euo pipefail
# shellcheck source=fuzz/fuzz_lib.sh
. "$(dirname "$0")/fuzz_lib.sh"
target=${1:?usage: fuzz/run.sh TARGET [SECONDS] [JOBS]}
seconds=${2:-600}
jobs=${3:-$(getconf _NPROCESSORS_ONLN)}
qex_fuzz_build "$target"
out="$qex_build/run"
qex_fuzz_run "$target" "$seconds" "$jobs" "$out"
IFS=$'\t' read -r _ wall runs eps cov ft added findings slow <"$out/$target.row"
grep -E "stat::" "$out/$target.log" | tail -n 8 || true
echo "$target: $wall s, $runs executions, $eps exec/s, cov $cov ft $ft, $added new units in merged/"
echo "findings: $findings; slow units: $slow (log and artifacts in $out/)"
if [ "$findings" != none ]; then
  echo "FINDINGS copied to corpus/$(qex_fuzz_corpus "$target")/regressions/ (add a note of what each found to its NOTES.md)"
fi
echo "corpus: $(find "$qex_root/corpus/$(qex_fuzz_corpus "$target")" -type f ! -name '*.md' | wc -l) files"
