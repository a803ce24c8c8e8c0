#!/usr/bin/env bash
# Bad input to the set-up path: a missing dependency stops the configure with the Debian package
# to install; tools/run.sh refuses an unknown command and reports a failed apt-get, non-zero.
# Usage: run_test.sh SOURCE_DIR SCRATCH_DIR
set -u
src="$1"; scratch="$2"
rm -rf "$scratch"; mkdir -p "$scratch"
source "$(dirname "$0")/check.sh"

# 1. A dependency CMake cannot find: the message names the package.
cmake -S "$src" -B "$scratch/b1" -DCMAKE_DISABLE_FIND_PACKAGE_Eigen3=TRUE >"$scratch/1.out" 2>&1; rc=$?
check "missing Eigen names libeigen3-dev" nz $rc "$scratch/1.out" "apt-get install libeigen3-dev"
cmake -S "$src" -B "$scratch/b2" -DCMAKE_DISABLE_FIND_PACKAGE_SQLite3=TRUE >"$scratch/2.out" 2>&1; rc=$?
check "missing SQLite names libsqlite3-dev" nz $rc "$scratch/2.out" "apt-get install libsqlite3-dev"
cmake -S "$src" -B "$scratch/b5" -DCMAKE_DISABLE_FIND_PACKAGE_OpenSSL=TRUE >"$scratch/5.out" 2>&1; rc=$?
check "missing OpenSSL names libssl-dev" nz $rc "$scratch/5.out" "apt-get install libssl-dev"

# 2. Unknown command: usage and exit 2.
"$src/tools/run.sh" frobnicate >"$scratch/3.out" 2>&1; rc=$?
check "unknown run.sh command" 2 $rc "$scratch/3.out" "usage: tools/run.sh calibrate"

# 3. Packages missing and apt-get failing (fakes first on PATH): one line naming them, exit 1.
mkdir -p "$scratch/fake"
printf '#!/bin/sh\necho "dpkg-query: no packages found"; exit 1\n' >"$scratch/fake/dpkg-query"
printf '#!/bin/sh\necho "E: simulated failure" >&2; exit 100\n' >"$scratch/fake/apt-get"
printf '#!/bin/sh\nexit 1\n' >"$scratch/fake/sudo"
chmod +x "$scratch/fake/"*
PATH="$scratch/fake:$PATH" "$src/tools/run.sh" setup >"$scratch/4.out" 2>&1; rc=$?
check "failing apt-get is reported" 1 $rc "$scratch/4.out" "run.sh: apt-get"
check "missing packages are named" 1 $rc "$scratch/4.out" "liblcm-dev"

finish
