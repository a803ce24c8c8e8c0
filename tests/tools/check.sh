# What the shell tests of tools/ share (sourced): check NAME WANT GOT OUT TEXT counts a case as
# passed when the exit code GOT is WANT (nz = any non-zero) and the file OUT holds TEXT, compared
# with runs of white space folded to one space (CMake wraps long messages); otherwise it says
# what it wanted and shows the end of OUT. finish prints the counts and fails when any case failed.
fail=0; pass=0
check() {  # name, expected exit (nz = any non-zero), actual exit, output file, expected text
    local name="$1" want="$2" got="$3" out="$4" text="$5"
    local ok=1
    if [ "$want" = nz ]; then [ "$got" -ne 0 ] || ok=0; else [ "$got" -eq "$want" ] || ok=0; fi
    tr -s " \n" "  " <"$out" | grep -qF -- "$text" || ok=0
    if [ $ok -eq 1 ]; then pass=$((pass+1)); echo "ok   $name";
    else fail=$((fail+1)); echo "FAIL $name (exit $got, want $want; looked for: $text)"; sed 's/^/     | /' "$out" | tail -8; fi
}
finish() {
    echo "$pass passed, $fail failed"
    [ $fail -eq 0 ]
}
