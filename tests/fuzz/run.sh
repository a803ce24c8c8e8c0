#!/usr/bin/env bash
# Builds the libFuzzer harnesses (clang, ASan+UBSan, in build-fuzz/) and runs each for a stated
# time on a working copy of its committed seed corpus, one after the other (nice'd: the machine
# is shared). Prints one line per harness: seconds, executions, executions/s, corpus size,
# coverage, and what it found.
#
#   tests/fuzz/run.sh [--seconds N] [HARNESS...]     default: 60 s each, every harness
#   (tools/run.sh fuzz [...] does the same after installing clang and the other packages)
#
# Limits that make a finding of what would hurt a process: -malloc_limit_mb=512 (a decode that
# allocates more than that from one input is reported), -rss_limit_mb=2048, -timeout=10 s per
# input. A finding stops that harness: its input is saved in build-fuzz/fuzz-out/<harness>/;
# once fixed, copy it into tests/fuzz/regressions/<harness>/ so that fuzz_replay_test runs it
# in every build. Exit status: 0 when nothing was found, 1 otherwise, 2 on bad usage.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${GYROCAL_FUZZ_BUILD_DIR:-$here/build-fuzz}"
seconds=60
harnesses=()
while [ $# -gt 0 ]; do
    case "$1" in
        --seconds) seconds="${2:-}"; shift 2 ;;
        -h|--help) sed -n '2,18p' "$0"; exit 0 ;;
        -*) echo "run.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
        *) harnesses+=("$1"); shift ;;
    esac
done
[[ "$seconds" =~ ^[0-9]+$ ]] && [ "$seconds" -ge 1 ] ||
    { echo "run.sh: --seconds '$seconds' is not a whole number of seconds >= 1" >&2; exit 2; }
command -v clang++ >/dev/null ||
    { echo "run.sh: clang++ not found: apt-get install clang libclang-rt-14-dev (or tools/run.sh fuzz)" >&2; exit 2; }

launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
      -DGYROCAL_FUZZ=ON -DGYROCAL_BENCHMARKS=OFF "${launcher[@]}" >/dev/null
cmake --build "$build" -j 2 --target fuzz_all

if [ ${#harnesses[@]} -eq 0 ]; then
    for d in "$here"/tests/fuzz/corpus/*/; do harnesses+=("$(basename "$d")"); done
fi
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'), load $(cut -d' ' -f1 /proc/loadavg)"
printf '%-28s %7s %12s %9s %7s %7s  %s\n' harness seconds executions exec/s corpus cov found
found_any=0
for h in "${harnesses[@]}"; do
    bin="$build/bin/fuzz_$h"
    [ -x "$bin" ] || { echo "run.sh: no harness '$h' ($bin)" >&2; exit 2; }
    work="$build/fuzz-work/$h" out="$build/fuzz-out/$h"
    mkdir -p "$work" "$out"
    log="$out/last-run.log"
    set +e
    nice -n 10 "$bin" "$work" "$here/tests/fuzz/corpus/$h" -max_total_time="$seconds" \
        -max_len=65536 -malloc_limit_mb=512 -rss_limit_mb=2048 -timeout=10 \
        -print_final_stats=1 -artifact_prefix="$out/" >"$log" 2>&1
    rc=$?
    set -e
    execs="$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)"
    took="$(sed -n 's/^Done [0-9]* runs in \([0-9]*\) second.*/\1/p' "$log" | tail -1)"
    last="$(grep -E '^#[0-9]+' "$log" | tail -1)"
    cov="$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")"
    corp="$(sed -n 's/.* corp: \([0-9]*\).*/\1/p' <<<"$last")"
    rate=""
    [ -n "$execs" ] && [ -n "$took" ] && [ "$took" -gt 0 ] && rate=$((execs / took))
    what="nothing"
    if [ $rc -ne 0 ]; then
        found_any=1
        what="FOUND: $(grep -m1 -E 'ERROR: |fuzz contract broken|terminate called|out-of-memory|timeout' "$log" || echo "exit $rc") -> $(ls -t "$out" | grep -v last-run.log | head -1) (log $log)"
    fi
    printf '%-28s %7s %12s %9s %7s %7s  %s\n' "$h" "${took:-?}" "${execs:-?}" "${rate:-?}" \
        "${corp:-?}" "${cov:-?}" "$what"
done
exit $found_any
