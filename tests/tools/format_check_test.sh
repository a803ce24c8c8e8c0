#!/usr/bin/env bash
# tools/run.sh format-check on a throwaway git repository with the project's .clang-format: it
# passes when every C++ line changed since the commit in .clang-format-since is formatted, fails
# (exit 1) naming the file when one changed line is not, leaves older lines alone, and refuses a
# .clang-format-since that names no commit.
# Usage: format_check_test.sh SOURCE_DIR SCRATCH_DIR
set -u
src="$1"; scratch="$2"
rm -rf "$scratch"; mkdir -p "$scratch"
fail=0; pass=0
check() {  # name, expected exit (nz = any non-zero), actual exit, output file, expected text
    local name="$1" want="$2" got="$3" out="$4" text="$5"
    local ok=1
    if [ "$want" = nz ]; then [ "$got" -ne 0 ] || ok=0; else [ "$got" -eq "$want" ] || ok=0; fi
    grep -qF -- "$text" "$out" || ok=0
    if [ $ok -eq 1 ]; then pass=$((pass+1)); echo "ok   $name";
    else fail=$((fail+1)); echo "FAIL $name (exit $got, want $want; looked for: $text)"; sed 's/^/     | /' "$out" | tail -8; fi
}

repo="$scratch/repo"
mkdir -p "$repo"
git -C "$repo" init -q
git -C "$repo" config user.email t@example.invalid
git -C "$repo" config user.name test
cp "$src/.clang-format" "$repo/"
# An old misformatted line, committed before the base: never checked until it changes.
printf 'int  old( ){return 0;}\n' >"$repo/old.cpp"
git -C "$repo" add -A && git -C "$repo" commit -qm base
git -C "$repo" rev-parse HEAD >"$repo/.clang-format-since"
printf 'int ok() { return 1; }\n' >"$repo/new.cpp"
git -C "$repo" add -A && git -C "$repo" commit -qm formatted

"$src/tools/run.sh" format-check "$repo" >"$scratch/1.out" 2>&1; rc=$?
check "formatted changes pass, the older line is left alone" 0 $rc "$scratch/1.out" "is formatted"

printf 'int  bad( ){return 2;}\n' >>"$repo/new.cpp"
git -C "$repo" commit -qam misformatted
"$src/tools/run.sh" format-check "$repo" >"$scratch/2.out" 2>&1; rc=$?
check "a misformatted changed line fails, naming its file" 1 $rc "$scratch/2.out" "not formatted: new.cpp"
check "the fix is named" 1 $rc "$scratch/2.out" "run: git clang-format"

# Not committed: the working tree counts too.
git -C "$repo" reset -q --hard HEAD~1
printf 'int  w( ){return 3;}\n' >"$repo/work.hpp"
git -C "$repo" add work.hpp
"$src/tools/run.sh" format-check "$repo" >"$scratch/3.out" 2>&1; rc=$?
check "an uncommitted misformatted header fails" 1 $rc "$scratch/3.out" "not formatted: work.hpp"
git -C "$repo" rm -qf work.hpp

echo "not-a-commit" >"$repo/.clang-format-since"
"$src/tools/run.sh" format-check "$repo" >"$scratch/4.out" 2>&1; rc=$?
check "a base that is no commit is refused" nz $rc "$scratch/4.out" "not a commit"

rm -f "$repo/.clang-format-since"
"$src/tools/run.sh" format-check "$repo" >"$scratch/5.out" 2>&1; rc=$?
check "a missing base file is refused" nz $rc "$scratch/5.out" ".clang-format-since is missing"

echo "$pass passed, $fail failed"
[ $fail -eq 0 ]
