#!/usr/bin/env bash
# One entry point for a fresh Debian bookworm machine:
#   tools/run.sh calibrate [gyrocal calibrate options]   set up, build, run a simulated calibration,
#                                                        judge it by tools/acceptance/limits.json and
#                                                        write its report (reports/, path printed)
#   tools/run.sh test                                    set up, build, run every test (CTest)
#   tools/run.sh setup                                   set up and build only
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
          libssl-dev chromium)

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

build_all() {
    cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
    cmake --build "$build" -j "$jobs"
}

cmd="${1:-}"
[ $# -gt 0 ] && shift
case "$cmd" in
    setup)     install_missing; check_multicast; build_all ;;
    calibrate) install_missing; check_multicast; build_all
               # Example limits and the report of the run, unless the caller chose their own.
               extra=()
               case " $* " in *" --limits"*) ;; *) extra+=(--limits "$here/tools/acceptance/limits.json") ;; esac
               case " $* " in *" --report"*) ;; *) extra+=(--report "${GYROCAL_REPORT_DIR:-$here/reports}") ;; esac
               exec "$build/bin/gyrocal" calibrate --db "${GYROCAL_DB:-$here/gyrocal.db}" "${extra[@]}" "$@" ;;
    test)      install_missing; check_multicast; build_all
               cd "$build" && exec ctest --output-on-failure -j "$jobs" "$@" ;;
    *) echo "usage: tools/run.sh calibrate [options] | test [ctest options] | setup" >&2; exit 2 ;;
esac
