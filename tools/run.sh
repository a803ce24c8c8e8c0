#!/usr/bin/env bash
# One entry point for a fresh Debian bookworm machine:
#   tools/run.sh calibrate [gyrocal calibrate options]   set up, build, run a simulated calibration,
#                                                        judge it by tools/acceptance/limits.json and
#                                                        write its report (reports/, path printed)
#   tools/run.sh test                                    set up, build, run every test (CTest)
#   tools/run.sh setup                                   set up and build everything (tests too)
# calibrate builds only what it runs (the processes and the gyrocal command: target
# gyrocal_apps); test and setup build everything.
#   tools/run.sh sanitize [asan|tsan|fast]               the tests under sanitizers (below)
#   tools/run.sh fuzz [--seconds N] [HARNESS...]         run the fuzz harnesses (tests/fuzz/run.sh)
#   tools/run.sh format-check [REPO]                     every C++ file is as clang-format
#                                                        makes it (.ci/run; exit 1 names the lines)
# Set-up installs what is missing with apt-get (needs root or sudo) and is quick when all is there.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${GYROCAL_BUILD_DIR:-$here/build}"
jobs="$(nproc 2>/dev/null || echo 2)"

die() { echo "run.sh: $*" >&2; exit 1; }

# Debian package names. libglib2.0-dev: lcm.pc requires glib but liblcm-dev does not depend on it.
packages=(build-essential cmake pkg-config git
          liblcm-dev liblcm-bin liblcm-java libglib2.0-dev
          libeigen3-dev libsqlite3-dev sqlite3 libcli11-dev nlohmann-json3-dev
          libgtest-dev libgmock-dev libbenchmark-dev
          default-jdk-headless libjchart2d-java xvfb xauth gnuplot-nox iproute2
          libssl-dev chromium clang libclang-rt-14-dev e2fsprogs ccache
          postgresql libpqxx-dev clang-format python3)
# libssl-dev: SHA-256 of CSV/log inputs. chromium: the report's browser test. clang,
# libclang-rt-14-dev: libFuzzer for tools/run.sh fuzz. e2fsprogs: mkfs.ext4 and chattr for the
# read-only database test (tests/store/recorder/storage_fault_test.cpp). ccache: a second build
# of the same sources (CI's clean clone of a commit already built on this machine) compiles
# nothing again; the cache is keyed relative to the clone (base dir, no cwd), so clones share it.
# clang-format: tools/run.sh format-check (the whole tree against the committed .clang-format).
# python3: tools/dev/root_includes.py (includes from the repository root; its --check is a test).
# postgresql, libpqxx-dev: the lab's central database (gyrocal push; store/README.md); the tests
# start a throwaway server of their own (initdb + pg_ctl in a temporary folder, as the
# unprivileged user 'postgres' the package creates).

install_missing() {
    local missing=()
    for p in "${packages[@]}"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
    done
    [ ${#missing[@]} -eq 0 ] && return 0
    echo "run.sh: installing ${missing[*]}"
    local sudo=""
    if [ "$(id -u)" -ne 0 ]; then
        command -v sudo >/dev/null || die "missing packages (${missing[*]}) and not root: run as root or install them"
        sudo="sudo"
    fi
    $sudo env DEBIAN_FRONTEND=noninteractive apt-get update -qq ||
        die "apt-get update failed: check the apt sources of this machine"
    $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null ||
        die "apt-get install ${missing[*]} failed"
}

# LCM's UDP multicast needs a route for 224.0.0.0/4. LCM's documented fix for a host without one
# is to route multicast over loopback; messages stay on this host (TTL 0) either way.
check_multicast() {
    if ! ip route get 239.255.76.67 >/dev/null 2>&1; then
        if [ "$(id -u)" -eq 0 ]; then
            echo "run.sh: no multicast route; adding one on lo (LCM's loopback fix)"
            ip link set lo multicast on
            ip route add 224.0.0.0/4 dev lo
        else
            die "no route for multicast (LCM udpm): run as root: ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo"
        fi
    fi
    # A 4 MB socket receive buffer keeps bursts from being dropped by the kernel.
    local rmem
    rmem="$(cat /proc/sys/net/core/rmem_max 2>/dev/null || echo 0)"
    if [ "$rmem" -lt 4194304 ] && [ "$(id -u)" -eq 0 ]; then
        sysctl -q -w net.core.rmem_max=4194304 || echo "run.sh: warning: cannot raise net.core.rmem_max" >&2
    fi
}

# The compiler launcher for every build: ccache when installed, keyed relative to this clone.
launcher=()
if command -v ccache >/dev/null; then
    export CCACHE_BASEDIR="$here" CCACHE_NOHASHDIR=true
    launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi

configure() {
    cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo "${launcher[@]}" >/dev/null
}
build_all() {
    configure
    cmake --build "$build" -j "$jobs"
}
# What a calibration runs, without the tests and benchmarks (CMake target gyrocal_apps).
build_apps() {
    configure
    cmake --build "$build" -j "$jobs" --target gyrocal_apps
}

# Sanitizer builds, each in its own folder, with clang (GCC 12's UBSan reports a false
# "misaligned address"/"invalid vptr" inside LCM's own header, at its pointer-to-member call in
# lcm-cpp-impl.hpp; clang's does not), -O1 with asserts on; a finding aborts the test:
#   asan  ASan+UBSan, every test (build-asan)
#   fast  ASan+UBSan, the unit tests of the pure libraries, the store and the fuzz inputs
#         (build-asan, only their targets): what CI runs, a few minutes
#   tsan  TSan, the threaded parts: the bus, the batching writer and the real recorder
#         (build-tsan, only their targets)
# Suppressions (tools/sanitizers/*.supp) cover third-party code only, each with its reason.
# fast: the code that reads what comes from outside (bus decode, channel names and sensor ids, CSV
# and line parsers, the store and its writer, the recorder's mapper, every fuzz input) within CI's
# time budget.
fast_tests=(lcmtypes_bus_test lcmtypes_roundtrip_test lcmtypes_channels_test model_unit_tests
            compensator_unit_tests gyrocal_csv_parser_test gyrocal_csv_messages_test
            store_db_test store_storage_fault_test store_record_mapper_test store_writer_watch_test
            fuzz_replay_test)
tsan_tests=(lcmtypes_bus_test lcmtypes_bus_multiprocess_test store_db_test store_storage_fault_test
            store_recorder_process_test store_recorder_fault_test store_recorder_crash_test)

# Runs test executables one by one (bounded time each); prints "N passed, M failed".
run_test_binaries() {
    local dir="$1"; shift
    local passed=0 failed=0 t
    for t in "$@"; do
        if timeout 600 "$dir/bin/$t" >"$dir/$t.log" 2>&1; then
            passed=$((passed + 1)); echo "run.sh: $t passed"
        else
            failed=$((failed + 1)); echo "run.sh: $t FAILED (log $dir/$t.log):"; tail -n 40 "$dir/$t.log"
        fi
    done
    echo "sanitize: $passed passed, $failed failed"
    [ "$failed" -eq 0 ]
}

sanitize() {
    local mode="${1:-asan}" dir flags
    case "$mode" in
        asan|fast) dir="$here/build-asan"; flags="address,undefined" ;;
        tsan)      dir="$here/build-tsan"; flags="thread" ;;
        *) echo "usage: tools/run.sh sanitize [asan|tsan|fast]" >&2; exit 2 ;;
    esac
    command -v clang++ >/dev/null || die "clang++ not found: apt-get install clang libclang-rt-14-dev"
    cmake -S "$here" -B "$dir" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Debug \
          -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g1" -DGYROCAL_SANITIZE="$flags" \
          -DGYROCAL_BENCHMARKS=OFF "${launcher[@]}" >/dev/null
    local supp="$here/tools/sanitizers"
    export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1"
    export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0"
    export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
    export TSAN_OPTIONS="suppressions=$supp/tsan.supp:halt_on_error=1:second_deadlock_stack=1"
    case "$mode" in
        asan) cmake --build "$dir" -j "$jobs"
              (cd "$dir" && ctest --output-on-failure -j "$jobs") ;;
        fast) cmake --build "$dir" -j "$jobs" --target "${fast_tests[@]}"
              run_test_binaries "$dir" "${fast_tests[@]}" ;;
        tsan) cmake --build "$dir" -j "$jobs" --target "${tsan_tests[@]}"
              run_test_binaries "$dir" "${tsan_tests[@]}" ;;
    esac
}

# The house format on the whole tree: every C++ file git knows of (tracked, or new and not
# ignored) must be as clang-format (the committed .clang-format) makes it. Each line that is not
# is named as file:line; the fix is `clang-format -i` on the files named.
format_check() {
    local repo="${1:-$here}"
    [ -f "$repo/.clang-format" ] || die "format-check: $repo/.clang-format is missing; the house format lives there"
    command -v clang-format >/dev/null || die "format-check: clang-format not found: apt-get install clang-format"
    local files=() f
    while IFS= read -r -d '' f; do
        [ -f "$repo/$f" ] && files+=("$f")
    done < <(git -C "$repo" ls-files -z -co --exclude-standard -- '*.cpp' '*.hpp' '*.h' '*.cc')
    [ ${#files[@]} -gt 0 ] || die "format-check: no C++ file under $repo (is it a git checkout?)"
    local out rc=0
    out="$(cd "$repo" && clang-format --style=file --dry-run -Werror "${files[@]}" 2>&1)" || rc=$?
    if [ $rc -ne 0 ]; then
        printf '%s\n' "$out" | grep -E '^[^ ]+:[0-9]+:[0-9]+: (error|warning)' |
            sed -E 's|^([^:]+):([0-9]+):.*|run.sh: format-check: not formatted: \1:\2|' | uniq >&2
        local bad
        bad="$(printf '%s\n' "$out" | grep -oE '^[^ :]+:[0-9]+:[0-9]+: (error|warning)' | cut -d: -f1 | sort -u | tr '\n' ' ')"
        [ -n "$bad" ] || { printf '%s\n' "$out" >&2; die "format-check: clang-format failed"; }
        echo "run.sh: format-check: ${#files[@]} C++ files checked; not as .clang-format says: $bad; run: clang-format -i $bad" >&2
        return 1
    fi
    echo "run.sh: format-check: all ${#files[@]} C++ files are formatted as .clang-format says"
}

cmd="${1:-}"
[ $# -gt 0 ] && shift

# GYROCAL_CHECK_ONLY=1 (the docs test, tests/docs): check the command line, install, build and
# run nothing; `calibrate` hands its options to the built gyrocal, which checks them the same way.
if [ "${GYROCAL_CHECK_ONLY:-}" = "1" ]; then
    case "$cmd" in
        calibrate) exec "$build/bin/gyrocal" calibrate "$@" ;;
        test|setup) exit 0 ;;
        sanitize) case "${1:-asan}" in asan|tsan|fast) exit 0 ;; esac ;;
        fuzz|format-check) exit 0 ;;
    esac
    echo "run.sh: '$cmd ${*}' is not a command of tools/run.sh" >&2
    exit 2
fi
case "$cmd" in
    setup)     install_missing; check_multicast; build_all ;;
    calibrate) install_missing; check_multicast; build_apps
               # Example limits and the report of the run, unless the caller chose their own.
               extra=()
               case " $* " in *" --limits"*) ;; *) extra+=(--limits "$here/tools/acceptance/limits.json") ;; esac
               case " $* " in *" --report"*) ;; *) extra+=(--report "${GYROCAL_REPORT_DIR:-$here/reports}") ;; esac
               exec "$build/bin/gyrocal" calibrate --db "${GYROCAL_DB:-$here/gyrocal.db}" "${extra[@]}" "$@" ;;
    test)      install_missing; check_multicast; build_all
               cd "$build" && exec ctest --output-on-failure -j "$jobs" "$@" ;;
    sanitize)  install_missing; check_multicast; sanitize "$@" ;;
    fuzz)      install_missing; exec "$here/tests/fuzz/run.sh" "$@" ;;
    format-check) install_missing; format_check "$@" ;;
    *) echo "usage: tools/run.sh calibrate [options] | test [ctest options] | setup |" \
            "sanitize [asan|tsan|fast] | fuzz [--seconds N] [HARNESS...] | format-check [REPO]" >&2; exit 2 ;;
esac
