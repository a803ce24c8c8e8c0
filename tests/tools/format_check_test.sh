#!/usr/bin/env bash
# tools/run.sh format-check on a throwaway git repository with the project's .clang-format: it
# passes when every C++ file is formatted, fails (exit 1) naming file:line of a misformatted line
# (committed, staged or new and untracked), leaves ignored files (a build tree) alone, and
# refuses a repository without .clang-format.
# Usage: format_check_test.sh SOURCE_DIR SCRATCH_DIR
set -u
src="$1"; scratch="$2"
rm -rf "$scratch"; mkdir -p "$scratch"
source "$(dirname "$0")/check.sh"

repo="$scratch/repo"
mkdir -p "$repo/build"
git -C "$repo" init -q
git -C "$repo" config user.email t@example.invalid
git -C "$repo" config user.name test
cp "$src/.clang-format" "$repo/"
printf 'build/\n' >"$repo/.gitignore"
printf 'int ok() { return 1; }\n' >"$repo/ok.cpp"
printf 'int  gen( ){return 0;}\n' >"$repo/build/generated.hpp"  # ignored: never checked
git -C "$repo" add -A && git -C "$repo" commit -qm formatted

"$src/tools/run.sh" format-check "$repo" >"$scratch/1.out" 2>&1; rc=$?
check "a formatted tree passes, the ignored build tree is left alone" 0 $rc "$scratch/1.out" "are formatted"

printf 'int a() { return 2; }\nint  bad( ){return 2;}\n' >>"$repo/ok.cpp"
git -C "$repo" commit -qam misformatted
"$src/tools/run.sh" format-check "$repo" >"$scratch/2.out" 2>&1; rc=$?
check "a misformatted committed line fails, naming file and line" 1 $rc "$scratch/2.out" "not formatted: ok.cpp:3"
check "the fix is named" 1 $rc "$scratch/2.out" "run: clang-format -i ok.cpp"

git -C "$repo" reset -q --hard HEAD~1
printf 'int  w( ){return 3;}\n' >"$repo/work.hpp"
"$src/tools/run.sh" format-check "$repo" >"$scratch/3.out" 2>&1; rc=$?
check "a new untracked misformatted header fails" 1 $rc "$scratch/3.out" "not formatted: work.hpp:1"
rm -f "$repo/work.hpp"

rm -f "$repo/.clang-format"
"$src/tools/run.sh" format-check "$repo" >"$scratch/4.out" 2>&1; rc=$?
check "a repository without .clang-format is refused" nz $rc "$scratch/4.out" ".clang-format is missing"

finish
