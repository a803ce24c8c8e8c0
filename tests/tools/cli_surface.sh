#!/usr/bin/env bash
# Dumps the command-line surface of every built executable: the --help text of each process and
# of each `gyrocal` subcommand, and the exit code (and first stderr line) of a few bad inputs.
# Run it before and after a change that moves code around, then diff the two files:
#   tests/tools/cli_surface.sh build/bin > /tmp/before.txt
#   ... change, rebuild ...
#   tests/tools/cli_surface.sh build/bin > /tmp/after.txt && diff /tmp/before.txt /tmp/after.txt
# Only inputs that end at once are tried (no process is left running, nothing is published).
set -u
bin="$(realpath "${1:?usage: cli_surface.sh BIN_DIR}")"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# Prints the exit code and the first line of stderr of one command line.
try() {
    local rc
    (cd "$tmp" && timeout 20 "$@" >"$tmp/out" 2>"$tmp/err" </dev/null)
    rc=$?
    echo "## $(basename "$1") ${*:2} -> exit $rc: $(head -n 1 "$tmp/err")" | sed "s|$tmp|TMP|g"
}

help() {
    echo "### $(basename "$1") ${*:2} --help"
    (cd "$tmp" && timeout 20 "$@" --help 2>&1 </dev/null) | sed "s|$bin/||g"
    echo "### exit ${PIPESTATUS[0]}"
}

# The product's executables (test helpers such as gyrocal-bus-probe and gyrocal-othersim are not).
for exe in "$bin"/gyrocal "$bin"/gyrocal-*; do
    case "$(basename "$exe")" in gyrocal-bus-probe|gyrocal-othersim) continue ;; esac
    [ -x "$exe" ] || continue
    help "$exe"
    try "$exe" --no-such-option
done

# Every subcommand that `gyrocal --help` lists.
subs=$("$bin/gyrocal" --help | awk '/^Subcommands:/{on=1; next} /^[^ ]/{on=0} on && /^  [a-z]/ {print $1}')
for s in $subs; do
    help "$bin/gyrocal" "$s"
    try "$bin/gyrocal" "$s" --no-such-option
done

# Bad inputs that fail before any process starts.
printf 'not,a,gyrocal,csv\n1,2,3,4\n' >"$tmp/bad.csv"
try "$bin/gyrocal"
try "$bin/gyrocal" no-such-command
try "$bin/gyrocal" runs --db "$tmp/missing/none.db"
try "$bin/gyrocal" show no-such-run --db "$tmp/empty.db"
try "$bin/gyrocal" analyze no-such-run --db "$tmp/empty.db"
try "$bin/gyrocal" compensate "$tmp/bad.csv" --coeffs "$tmp/missing.json"
try "$bin/gyrocal" calibrate --source csv --db "$tmp/cal.db"
try "$bin/gyrocal" calibrate --effect no_such_effect=1
try "$bin/gyrocal" calibrate --source nowhere
try "$bin/gyrocal-recorder" --channels '('
try "$bin/gyrocal-recorder" --db "$tmp/missing/dir/x.db"
try "$bin/gyrocal-recorder" --batch-ms 0
try "$bin/gyrocal-replay"
try "$bin/gyrocal-replay" no-such-run --db "$tmp/missing/none.db"
try "$bin/gyrocal-replay" run --speed 0
try "$bin/gyrocal-csv-source" "$tmp/missing.csv"
try "$bin/gyrocal-csv-source" "$tmp/bad.csv" --lcm-url memq://
try "$bin/gyrocal-csv-source" "$tmp/bad.csv" --on-error never
try "$bin/gyrocal-fitter" --mode nowhere
try "$bin/gyrocal-compensator" --out-of-range never
exit 0
