#!/usr/bin/env bash
# Builds the libFuzzer harnesses (clang, ASan + UBSan, in build-fuzz/) and runs each for a bounded
# time. Exit 0 when no harness found anything; 1 on any finding (crash, sanitizer report, leak,
# timeout, out-of-memory, or a FUZZ FINDING of a harness's oracle); 2 when the build fails.
#
#   tests/fuzz/run.sh [SECONDS]     SECONDS: total fuzzing time, split evenly (default 60)
#
# Each harness runs SECONDS / (number of harnesses), stopped at that plus 15 s wall clock even if
# replaying its saved corpus takes longer. Prints one line per harness:
#   fuzz: <harness>: <N> inputs in <s> s, 0 findings
#   fuzz: <harness>: <N> inputs in <s> s, 1 finding: <first report line> (input <file>, log <file>)
#
# Environment:
#   GLINTLAB_FUZZ_BUILD_DIR   build folder (default <repo>/build-fuzz); corpora, logs and
#                             crash inputs go to <build>/fuzz/{corpus,logs,artifacts}/<harness>/
#   GLINTLAB_FUZZ_HARNESSES   which harnesses (default "experiment compare check journal options merge
#                             glint_model")
#   GLINTLAB_FUZZ_TIMEOUT     seconds one input may take before it is a finding (default 10)
#   GLINTLAB_FUZZ_JOBS        build parallelism (default: all cores)
#   GLINTLAB_FUZZ_IGNORE, GLINTLAB_FUZZ_STRICT, GLINTLAB_FUZZ_ORACLES, GLINTLAB_FUZZ_MAX_SIDE,
#   GLINTLAB_FUZZ_TRY_ALL_READERS   passed to the harnesses (see fuzz_common.h and the harnesses)
# The corpora persist between runs (seeded each run from the project's experiment files and
# tests/fuzz/corpus/); delete <build>/fuzz/corpus to start over.
set -uo pipefail

TOTAL="${1:-60}"
if ! [[ "$TOTAL" =~ ^[0-9]+$ ]] || [ "$TOTAL" -lt 1 ]; then
  echo "usage: $0 [SECONDS]   (total fuzzing time, a positive integer; default 60)" >&2
  exit 2
fi
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
BUILD="${GLINTLAB_FUZZ_BUILD_DIR:-$ROOT/build-fuzz}"
read -r -a HARNESSES <<<"${GLINTLAB_FUZZ_HARNESSES:-experiment compare check journal options merge glint_model}"
TIMEOUT="${GLINTLAB_FUZZ_TIMEOUT:-10}"
W="$BUILD/fuzz"

# ---- build
mkdir -p "$W/logs"
targets=()
for h in "${HARNESSES[@]}"; do targets+=("fuzz_$h"); done
generator=()
if [ ! -f "$BUILD/CMakeCache.txt" ] && command -v ninja >/dev/null; then generator=(-G Ninja); fi
if ! cmake -S "$ROOT" -B "$BUILD" "${generator[@]}" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
       "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g" -DGLINTLAB_FUZZ=ON >"$W/logs/configure.log" 2>&1; then
  cat "$W/logs/configure.log" >&2
  echo "fuzz: configure failed (is clang installed? see bootstrap.sh)" >&2
  exit 2
fi
if ! cmake --build "$BUILD" --target "${targets[@]}" -j "${GLINTLAB_FUZZ_JOBS:-$(nproc)}" >"$W/logs/build.log" 2>&1; then
  tail -n 40 "$W/logs/build.log" >&2
  echo "fuzz: build failed ($W/logs/build.log)" >&2
  exit 2
fi

# ---- dictionary and corpora
"$ROOT/tests/fuzz/make_dict.sh" >"$W/experiment.dict"
seed_corpus() {  # seed_corpus HARNESS FILE...: copies seeds in (existing corpus entries stay)
  local dir="$W/corpus/$1"
  shift
  mkdir -p "$dir"
  for f in "$@"; do
    [ -f "$f" ] || continue
    local rel="${f#"$ROOT"/}"
    cp "$f" "$dir/seed-${rel//\//-}"
  done
}
seed_corpus experiment "$ROOT"/experiments/*.json "$ROOT"/experiments/thesis/*.json "$ROOT"/tests/fuzz/corpus/experiment/*
seed_corpus compare "$ROOT"/tests/fuzz/corpus/compare/*
seed_corpus check "$ROOT"/results/baselines/*.json
seed_corpus journal "$ROOT"/tests/fuzz/corpus/journal/*
seed_corpus options "$ROOT"/tests/fuzz/corpus/options/*
seed_corpus merge "$ROOT"/tests/fuzz/corpus/merge/*
seed_corpus glint_model "$ROOT"/shaders/glint/models/*.glsl "$ROOT"/tests/data/glint_models/*.glsl

# ---- sanitizer settings: stop at the first report; leaks count
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=1:abort_on_error=1:symbolize=1:detect_stack_use_after_return=1:check_initialization_order=1:strict_init_order=1"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:+$UBSAN_OPTIONS:}print_stacktrace=1:halt_on_error=1:abort_on_error=1"
if [ -f "$ROOT/tests/fuzz/lsan.supp" ]; then
  export LSAN_OPTIONS="${LSAN_OPTIONS:+$LSAN_OPTIONS:}suppressions=$ROOT/tests/fuzz/lsan.supp:print_suppressions=0"
fi
if command -v llvm-symbolizer >/dev/null; then export ASAN_SYMBOLIZER_PATH="$(command -v llvm-symbolizer)"; fi
mkdir -p "$W/tmp"
export TMPDIR="$W/tmp"  # the harnesses' private temp folders live here

# ---- run
per=$((TOTAL / ${#HARNESSES[@]}))
[ "$per" -lt 1 ] && per=1
failed=0
for h in "${HARNESSES[@]}"; do
  args=(-max_total_time="$per" -timeout="$TIMEOUT" -rss_limit_mb=2048 -print_final_stats=1
        -artifact_prefix="$W/artifacts/$h/")
  case "$h" in
    experiment) args+=(-max_len=16384 -dict="$W/experiment.dict") ;;
    compare) args+=(-max_len=8192) ;;
    check) args+=(-max_len=65536 -dict="$W/experiment.dict") ;;
    journal) args+=(-max_len=65536 -dict="$W/experiment.dict") ;;
    merge) args+=(-max_len=16384 -dict="$W/experiment.dict") ;;
    options) args+=(-max_len=2048 -dict="$ROOT/tests/fuzz/options.dict" -close_fd_mask=1) ;;
  esac
  mkdir -p "$W/artifacts/$h"
  log="$W/logs/$h.log"
  before="$(ls "$W/artifacts/$h" | sort)"
  start=$(date +%s.%N)
  # libFuzzer replays the whole corpus before it checks -max_total_time; the wall-clock bound
  # (SIGINT: libFuzzer prints its stats and exits 72) keeps a grown corpus from stretching the run.
  timeout --preserve-status --signal=INT --kill-after=30 $((per + 15)) \
    "$BUILD/fuzz_$h" "${args[@]}" "$W/corpus/$h" >"$log" 2>&1
  rc=$?
  [ "$rc" -eq 72 ] && rc=0
  end=$(date +%s.%N)
  secs=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.0f", b - a }')
  n=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | tail -n 1 | awk '{print $2}')
  [ -z "$n" ] && n=$(grep -oE '^#[0-9]+' "$log" | tail -n 1 | tr -d '#')
  [ -z "$n" ] && n=0
  if [ "$rc" -eq 0 ] && ! grep -qE 'ERROR: (AddressSanitizer|LeakSanitizer|UndefinedBehaviorSanitizer|libFuzzer)|runtime error:|FUZZ FINDING' "$log"; then
    echo "fuzz: $h: $n inputs in $secs s, 0 findings"
  else
    failed=1
    report=$(grep -m 1 -E 'FUZZ FINDING|ERROR: (AddressSanitizer|LeakSanitizer|UndefinedBehaviorSanitizer|libFuzzer)|runtime error:|==[0-9]+==ERROR' "$log" |
      sed -E 's/^==[0-9]+==//' | cut -c 1-300)
    [ -z "$report" ] && report="exit status $rc"
    new="$(comm -13 <(echo "$before") <(ls "$W/artifacts/$h" | sort) | head -n 1)"
    input="${new:+$W/artifacts/$h/$new}"
    echo "fuzz: $h: $n inputs in $secs s, 1 finding: $report (input ${input:-none saved}, log $log)"
    grep -A 30 -m 1 -E 'FUZZ FINDING|ERROR: (AddressSanitizer|LeakSanitizer|UndefinedBehaviorSanitizer|libFuzzer)|runtime error:' "$log" | head -n 40 | sed 's/^/    /' >&2
  fi
  rm -rf "${TMPDIR:?}"/glintlab-fuzz-"$h"-* 2>/dev/null
done
exit "$failed"
