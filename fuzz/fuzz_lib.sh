# shellcheck shell=bash
# Shared by fuzz/run.sh and fuzz/campaign.sh (source it, do not run it): the clang libFuzzer
# build in build-fuzz/ and the run of one target.
#   qex_fuzz_build TARGET...                  configure build-fuzz/ if needed, build the targets
#   qex_fuzz_run TARGET SECONDS JOBS OUTDIR   fuzz one target; see the function for what it writes
# The build runs CMAKE_BUILD_PARALLEL_LEVEL jobs, by default one per core (ninja's own default is
# the cores + 2), so that a shared machine can be spared: CMAKE_BUILD_PARALLEL_LEVEL=1 fuzz/run.sh ...
# CMake takes CMAKE_CXX_COMPILER_LAUNCHER=ccache from the environment when it first configures.

qex_root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
qex_build="$qex_root/build-fuzz"
# shellcheck disable=SC2034 # used by campaign.sh
QEX_FUZZ_TARGETS=(fuzz_obj fuzz_ply fuzz_sanitize fuzz_predicates_differential fuzz_layout fuzz_extract fuzz_extract_large) # slowest last
# Units of the merged corpus are kept only up to this size, to keep the repository small.
QEX_FUZZ_MAX_KEEP=16384
qex_build_jobs=${CMAKE_BUILD_PARALLEL_LEVEL:-$(getconf _NPROCESSORS_ONLN)}

# clang 19's libFuzzer where installed: clang 14's spends most of a fuzz_extract run updating its
# feature frequencies (39% of the samples; fixed upstream in LLVM 18), and 90 s on 2 jobs ran
# 1,410 executions with it against 4,465 with clang 19.
if command -v clang++-19 >/dev/null 2>&1; then
  qex_cc=clang-19 qex_cxx=clang++-19
else
  qex_cc=clang qex_cxx=clang++
fi

qex_fuzz_build() {
  # A build made with another compiler is made again.
  if [ -f "$qex_build/CMakeCache.txt" ] &&
    ! grep -q "^CMAKE_CXX_COMPILER:[A-Z]*=.*/$qex_cxx\$" "$qex_build/CMakeCache.txt"; then
    rm -rf "${qex_build:?}"
  fi
  if [ ! -f "$qex_build/build.ninja" ]; then
    CC=$qex_cc CXX=$qex_cxx cmake -S "$qex_root" -B "$qex_build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DQEX_LIBFUZZER=ON -DQEX_BUILD_TESTS=OFF -DQEX_BUILD_CLI=OFF -DQEX_BUILD_FUZZERS=ON >/dev/null
  fi
  cmake --build "$qex_build" --parallel "$qex_build_jobs" --target "$@"
}

# The corpus folder of a target, under corpus/: fuzz_extract_large shares fuzz_extract's (the same
# bytes mean the same cases, on larger maps).
qex_fuzz_corpus() {
  case "$1" in
    fuzz_extract_large) echo fuzz_extract ;;
    *) echo "$1" ;;
  esac
}

# The -dict file of a target, if it has one.
qex_fuzz_dict() {
  case "$1" in
    fuzz_obj) echo "$qex_root/fuzz/obj.dict" ;;
    fuzz_ply) echo "$qex_root/fuzz/ply.dict" ;;
  esac
}

# Copies corpus/TARGET (seeds, merged/, regressions/; same names kept apart) into the scratch
# directory DIR and lists its files in DIR.before, for qex_fuzz_added.
qex_fuzz_scratch() {
  local target=$1 dir=$2
  find "$qex_root/corpus/$(qex_fuzz_corpus "$target")" -type f ! -name '*.md' -exec cp --backup=numbered -t "$dir" {} +
  (cd "$dir" && ls) | sort >"$dir.before"
}

# The files of scratch directory DIR that qex_fuzz_scratch did not put there, one per line.
qex_fuzz_added() {
  (cd "$1" && ls) | sort | comm -13 "$1.before" -
}

# Fuzzes a scratch copy of corpus/TARGET (seeds, merged/, regressions/) for SECONDS in libFuzzer's
# fork mode with JOBS workers, ignoring crashes, timeouts and out-of-memory so that one run
# collects every finding. Writes, under OUTDIR:
#   TARGET.log    libFuzzer's output
#   TARGET.row    one tab-separated line: target, wall seconds, executions, exec/s, cov, ft,
#                 new units kept, findings (count and kinds), slow units
#   TARGET/       the artifacts libFuzzer wrote (crash-*, timeout-*, oom-*, leak-*, slow-unit-*)
#   TARGET.merge.log  libFuzzer's output of the merge of the new units (qex_fuzz_keep)
# and in the repository: every artifact but slow units in corpus/TARGET/regressions/<sha1:16>,
# and of the units the run added, up to QEX_FUZZ_MAX_KEEP bytes, those that reach edges the whole
# corpus does not (qex_fuzz_keep) in corpus/TARGET/merged/.
qex_fuzz_run() {
  local target=$1 seconds=$2 jobs=$3 out=$4
  local bin="$qex_build/fuzz/$target" work="$qex_build/fuzz-work/$target"
  local dict
  dict=$(qex_fuzz_dict "$target")
  rm -rf "${work:?}" "${out:?}/$target"
  mkdir -p "$work/corpus" "$out/$target" "$qex_root/corpus/$(qex_fuzz_corpus "$target")/merged"
  qex_fuzz_scratch "$target" "$work/corpus"
  local start end
  start=$(date +%s)
  (cd "$work" && "$bin" -max_total_time="$seconds" -fork="$jobs" -ignore_crashes=1 -ignore_timeouts=1 \
    -ignore_ooms=1 -timeout=30 -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 \
    -artifact_prefix="$out/$target/" ${dict:+-dict="$dict"} "$work/corpus") >"$out/$target.log" 2>&1 || true
  end=$(date +%s)

  # The last stats line: "#RUNS: cov: C ft: F corp: ... exec/s E ..." (fork mode) or
  # "#RUNS <event> cov: C ft: F ... exec/s: E ..." (one process).
  local stats runs cov ft eps
  stats=$(grep -E '^#[0-9]+.*cov: [0-9]+' "$out/$target.log" | tail -n 1 || true)
  runs=$(sed -nE 's/^#([0-9]+).*/\1/p' <<<"$stats")
  cov=$(sed -nE 's/.* cov: ([0-9]+).*/\1/p' <<<"$stats")
  ft=$(sed -nE 's/.* ft: ([0-9]+).*/\1/p' <<<"$stats")
  eps=$(sed -nE 's/.* exec\/s:? ([0-9]+).*/\1/p' <<<"$stats")

  # New coverage: the units the run added to the scratch corpus, up to QEX_FUZZ_MAX_KEEP bytes,
  # merged by edges against the corpus (before the findings: the merge can time out on a unit too).
  local f
  mkdir -p "$work/new"
  qex_fuzz_added "$work/corpus" >"$work/new.list"
  while read -r f; do
    if [ -n "$f" ] && [ "$(stat -c %s "$work/corpus/$f")" -le "$QEX_FUZZ_MAX_KEEP" ]; then
      cp "$work/corpus/$f" "$work/new/"
    fi
  done <"$work/new.list"
  local added
  added=$(qex_fuzz_keep "$target" "$work/new" "$out/$target/" "$out/$target.merge.log")
  rm -rf "$work"

  # Findings: every artifact but slow units goes to regressions/, named by content.
  local a kind n=0 slow=0 kinds=""
  for a in "$out/$target"/*; do
    [ -f "$a" ] || continue
    kind=$(basename "$a" | sed -E 's/-[0-9a-f]{40}$//')
    if [ "$kind" = slow-unit ]; then slow=$((slow + 1)); continue; fi
    mkdir -p "$qex_root/corpus/$(qex_fuzz_corpus "$target")/regressions"
    cp "$a" "$qex_root/corpus/$(qex_fuzz_corpus "$target")/regressions/$(sha1sum "$a" | cut -c1-16)"
    n=$((n + 1))
    kinds="$kinds $kind"
  done
  local findings=none
  if [ "$n" -gt 0 ]; then
    findings="$n ($(tr ' ' '\n' <<<"$kinds" | sed '/^$/d' | sort | uniq -c | awk '{printf "%s%s %s", s, $1, $2; s=", "}'))"
  fi

  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$target" "$((end - start))" "${runs:-?}" "${eps:-?}" \
    "${cov:-?}" "${ft:-?}" "$added" "$findings" "$slow" >"$out/$target.row"
}

# Keeps the units in DIR that reach edges the whole corpus/TARGET (seeds, merged/, regressions/)
# does not: libFuzzer's merge by edges only (-use_counters=0; units that add only hit-count
# features made the replays 3-9 times slower) into a scratch copy of the corpus. Copies them to
# corpus/TARGET/merged/ under libFuzzer's hash names and prints how many. The merge replays the
# whole corpus once (fuzz_extract: about 10 minutes under the sanitizers), and not at all when DIR
# is empty; artifacts of units that crash or time out in it go to ARTIFACTS, and its output to LOG
# (defaults: the scratch directory, then dropped).
qex_fuzz_keep() {
  local target=$1 dir=$2 artifacts=${3:-} log=${4:-} ctrl f n=0
  # Nothing new: no merge (it would replay the whole corpus for nothing).
  if [ -z "$(ls -A "$dir" 2>/dev/null)" ]; then
    echo 0
    return
  fi
  ctrl=$(mktemp -d)
  qex_fuzz_scratch "$target" "$ctrl"
  "$qex_build/fuzz/$target" -merge=1 -use_counters=0 -timeout=30 -rss_limit_mb=2048 \
    -artifact_prefix="${artifacts:-$ctrl.}" "$ctrl" "$dir" >"${log:-$ctrl.log}" 2>&1 || true
  while read -r f; do
    if [ ! -e "$qex_root/corpus/$(qex_fuzz_corpus "$target")/merged/$f" ]; then
      cp "$ctrl/$f" "$qex_root/corpus/$(qex_fuzz_corpus "$target")/merged/"
      n=$((n + 1))
    fi
  done < <(qex_fuzz_added "$ctrl")
  rm -rf "$ctrl" "$ctrl".*
  echo "$n"
}
