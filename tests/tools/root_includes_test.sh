#!/usr/bin/env bash
# tools/dev/root_includes.py on a throwaway git repository: --check names every include that is
# not from the root (bare in-folder, parent-relative) and every CMake export of a source folder;
# the rewrite roots them (same-folder headers too), leaves generated headers, comments and raw
# strings alone, and changes nothing when run again; an ambiguous or unknown name is an error
# naming file:line and the candidates, and then nothing is written; compile_commands.json
# chooses among same-named headers as the compiler does.
# Usage: root_includes_test.sh SOURCE_DIR SCRATCH_DIR [PYTHON3]
set -u
src="$1"; scratch="$2"; python="${3:-python3}"
rm -rf "$scratch"; mkdir -p "$scratch"
source "$(dirname "$0")/check.sh"
tool=("$python" "$src/tools/dev/root_includes.py")

repo="$scratch/repo"
mkdir -p "$repo/layer/a" "$repo/layer/b" "$repo/build"
git -C "$repo" init -q
printf 'build/\n' >"$repo/.gitignore"
printf '#pragma once\nint A();\n' >"$repo/layer/a/a.hpp"
printf '#include "a.hpp"\nint A() { return 1; }\n' >"$repo/layer/a/a.cpp"
cat >"$repo/layer/b/b.cpp" <<'EOF'
#include "a/a.hpp"
#include "gyrocal/status_t.hpp"
// #include "a.hpp" in a comment
/* #include "a.hpp"
   in a block comment */
const char* kC = R"(
#include "a.hpp"
)";
int B() { return A(); }
EOF
printf '#include "a.hpp"\n' >"$repo/build/generated.cpp"  # ignored: a build folder
printf 'add_library(a a.cpp)\ntarget_include_directories(a PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/..)\n' \
    >"$repo/layer/a/CMakeLists.txt"

"${tool[@]}" --check --root "$repo" >"$scratch/1.out" 2>&1; rc=$?
check "--check names a parent-relative include and its rooted path" 1 $rc "$scratch/1.out" \
    'not rooted: layer/b/b.cpp:1: #include "a/a.hpp" -> "layer/a/a.hpp"'
check "--check names a bare same-folder include" 1 $rc "$scratch/1.out" \
    'not rooted: layer/a/a.cpp:1: #include "a.hpp" -> "layer/a/a.hpp"'
check "--check names a CMake export of a source folder" 1 $rc "$scratch/1.out" \
    'layer/a/CMakeLists.txt:2: target_include_directories names ${CMAKE_CURRENT_SOURCE_DIR}/..'
check "--check counts: 2 of 3 includes not rooted (the generated one kept)" 1 $rc "$scratch/1.out" \
    '2 of 3 quoted includes in 3 files not rooted, 0 errors, 1 CMake'

"${tool[@]}" --root "$repo" >"$scratch/2.out" 2>&1; rc=$?
check "the rewrite roots both and names the files" 0 $rc "$scratch/2.out" \
    'rewrote 2 of 3 quoted includes in 2 of 3 files (1 generated headers kept by name)'
cat "$repo/layer/a/a.cpp" "$repo/layer/b/b.cpp" "$repo/build/generated.cpp" >"$scratch/2.files"
check "the same-folder include is rooted" 0 0 "$scratch/2.files" '#include "layer/a/a.hpp" int A()'
check "comments, raw strings and the generated header are left alone" 0 0 "$scratch/2.files" \
    '#include "layer/a/a.hpp" #include "gyrocal/status_t.hpp" // #include "a.hpp" in a comment /* #include "a.hpp" in a block comment */ const char* kC = R"( #include "a.hpp" )";'
check "the ignored build folder is left alone" 0 0 "$scratch/2.files" ')"; int B() { return A(); } #include "a.hpp"'

"${tool[@]}" --root "$repo" >"$scratch/3.out" 2>&1; rc=$?
check "a second run changes nothing" 0 $rc "$scratch/3.out" 'rewrote 0 of 3 quoted includes in 0 of 3 files'

rm "$repo/layer/a/CMakeLists.txt"
"${tool[@]}" --check --root "$repo" >"$scratch/4.out" 2>&1; rc=$?
check "--check passes on the rooted tree" 0 $rc "$scratch/4.out" 'all 3 quoted includes of 3 files rooted'

mkdir -p "$repo/layer/c" "$repo/layer/d" "$repo/layer/e"
printf '#pragma once\n' | tee "$repo/layer/c/cli.hpp" >"$repo/layer/d/cli.hpp"
printf '#include "cli.hpp"\n#include "nowhere.hpp"\n' >"$repo/layer/e/e.cpp"
printf '#include "a/a.hpp"\n' >"$repo/layer/e/f.cpp"
"${tool[@]}" --root "$repo" >"$scratch/5.out" 2>&1; rc=$?
check "an ambiguous name is an error naming the candidates" 1 $rc "$scratch/5.out" \
    'error: layer/e/e.cpp:1: #include "cli.hpp": ambiguous: layer/c/cli.hpp, layer/d/cli.hpp'
check "an unknown name is an error" 1 $rc "$scratch/5.out" \
    'error: layer/e/e.cpp:2: #include "nowhere.hpp": no file of the tree ends in /nowhere.hpp'
check "on an error nothing is written" 1 $rc "$scratch/5.out" '2 errors, nothing written'
check "... not even the files without error" 0 0 "$repo/layer/e/f.cpp" '#include "a/a.hpp"'

printf '#include "layer/d/cli.hpp"\n' >"$repo/layer/e/e.cpp"
"${tool[@]}" --root "$repo" >"$scratch/6.out" 2>&1; rc=$?
check "a rooted path written by hand settles the ambiguity" 0 $rc "$scratch/6.out" \
    'rewrote 1 of 5 quoted includes in 1 of 7 files'
check "... and the rest is rooted" 0 0 "$repo/layer/e/f.cpp" '#include "layer/a/a.hpp"'

printf '#include "cli.hpp"\n' >"$repo/layer/e/g.cpp"
printf '[{"directory": "%s", "file": "layer/e/g.cpp", "arguments": ["c++", "-I", "layer/x", "-Ilayer/c", "-Ilayer/d", "-c", "layer/e/g.cpp"]}]\n' \
    "$repo" >"$scratch/compile_commands.json"
"${tool[@]}" --root "$repo" --compile-commands "$scratch/compile_commands.json" >"$scratch/7.out" 2>&1; rc=$?
check "compile_commands.json settles it as the compiler would (first -I folder that has it)" 0 $rc \
    "$scratch/7.out" 'rewrote 1 of 6 quoted includes in 1 of 8 files'
check "... layer/c, the first" 0 0 "$repo/layer/e/g.cpp" '#include "layer/c/cli.hpp"'

finish
