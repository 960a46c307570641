#!/usr/bin/env bash
# Runs every fuzz target in turn under libFuzzer with address and undefined-behaviour sanitizers.
#   fuzz/campaign.sh SECONDS [JOBS=number of cores]
# SECONDS is per target. Each target runs as fuzz/run.sh runs it (fuzz_lib.sh): a scratch copy of
# corpus/<target>, fork mode with JOBS workers, -dict for fuzz_obj and fuzz_ply; findings are
# copied to corpus/<target>/regressions/, units of new coverage to corpus/<target>/merged/.
# Ends with a table, also written as Markdown to build-fuzz/campaign.md; logs and artifacts are in
# build-fuzz/campaign/. Set QEX_FUZZ_ONLY="fuzz_obj fuzz_ply" to run some targets only, and
# CMAKE_BUILD_PARALLEL_LEVEL to build with fewer jobs than the cores (fuzz_lib.sh), and
# QEX_FUZZ_SECONDS_<target>=S to give one target S seconds instead (fuzz_extract replays its corpus
# for about 10 minutes under the sanitizers before it fuzzes).
set -euo pipefail
# shellcheck source=fuzz/fuzz_lib.sh
. "$(dirname "$0")/fuzz_lib.sh"
seconds=${1:?usage: fuzz/campaign.sh SECONDS [JOBS]}
[[ $seconds =~ ^[0-9]+$ ]] || { echo "SECONDS=$seconds: not a number of seconds" >&2; exit 2; }
jobs=${2:-$(getconf _NPROCESSORS_ONLN)}
read -r -a targets <<<"${QEX_FUZZ_ONLY:-${QEX_FUZZ_TARGETS[*]}}"
declare -A budget # per target: QEX_FUZZ_SECONDS_<target>, else SECONDS
own_seconds=""
for t in "${targets[@]}"; do
  own="QEX_FUZZ_SECONDS_$t"
  budget[$t]=${!own:-$seconds}
  [[ ${budget[$t]} =~ ^[0-9]+$ ]] || { echo "$own=${budget[$t]}: not a number of seconds" >&2; exit 2; }
  [ "${budget[$t]}" = "$seconds" ] || own_seconds="$own_seconds ($t: ${budget[$t]} s)"
done
qex_fuzz_build "${targets[@]}"
out="$qex_build/campaign"
rm -rf "$out"
mkdir -p "$out"
commit=$(git -C "$qex_root" rev-parse --short HEAD 2>/dev/null || echo unknown)
if [ "$commit" != unknown ] && ! git -C "$qex_root" diff --quiet HEAD -- src include fuzz 2>/dev/null; then
  commit="$commit (with uncommitted changes)"
fi
for t in "${targets[@]}"; do
  echo "== $t: ${budget[$t]} s, $jobs job(s)"
  qex_fuzz_run "$t" "${budget[$t]}" "$jobs" "$out"
  cut -f2- "$out/$t.row" | awk -F'\t' '{printf "   %s s, %s executions, %s exec/s, cov %s ft %s, %s new units, findings: %s, slow units: %s\n", $1,$2,$3,$4,$5,$6,$7,$8}'
done
{
  echo "Fuzz campaign $(date +%F), commit $commit: $seconds s per target$own_seconds, $jobs job(s), $(getconf _NPROCESSORS_ONLN) cores," \
    "clang $($qex_cxx --version | sed -nE 's/.*version ([0-9.]+).*/\1/p' | head -n 1), ASan+UBSan," \
    "OMP_NUM_THREADS=${OMP_NUM_THREADS:-unset}"
  echo
  echo "| target | seconds | executions | exec/s | cov / ft | new units | findings | slow units |"
  echo "|---|---|---|---|---|---|---|---|"
  for t in "${targets[@]}"; do
    awk -F'\t' '{printf "| `%s` | %s | %s | %s | %s / %s | %s | %s | %s |\n", $1,$2,$3,$4,$5,$6,$7,$8,$9}' "$out/$t.row"
  done
} >"$qex_build/campaign.md"
echo
cat "$qex_build/campaign.md"
echo
echo "Table: $qex_build/campaign.md; logs and artifacts: $out/"
