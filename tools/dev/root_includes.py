#!/usr/bin/env python3
"""Every quoted #include names its file from the repository root, layer first.

    tools/dev/root_includes.py [--root DIR] [--compile-commands FILE] [-v]     rewrite in place
    tools/dev/root_includes.py --check [--root DIR] [--compile-commands FILE]  change nothing

The rule (docs/developing.md): `#include "processors/model/model.hpp"`, never `"model.hpp"` or
`"model/model.hpp"`, also for a header in the including file's own folder; the one include
directory of the sources is the repository root (CMakeLists.txt). Only generated headers, which
are not in the source tree, keep their names (GENERATED below: the LCM types `gyrocal/*_t.hpp`,
`gyrocal/version.hpp`, the fuzz harness list, the firmware test's `gyrocal_coeffs.h`).

Rewrite: each quoted include of the C/C++ sources (.cpp .hpp .h .c .cc and their .in templates;
the files git tracks or would add, so no build folder) is resolved as the compiler resolves it
today, then written as the path of that file from the root. Resolution of "X" in file F:
  1. F's own folder: F's folder/X exists -> that file (the compiler looks there first);
  2. X is a generated header (GENERATED) -> left as it is;
  3. the files of the tree whose path is X or ends in /X: one -> that file; several -> the one
     at the root (X is already rooted), else the ones the build's include directories reach
     (compile_commands.json: for a compiled F exactly the compiler's order of -I/-iquote folders,
     for a header any translation unit's); still not one -> an error naming every candidate;
     none -> an error.
Then the rooted path must give back the same file with the root as the only include directory
(F's folder must not hold a different file under that path), else it is an error.
On any error nothing is written; the errors are listed (file:line) and the exit status is 1.
Fix an ambiguous one by writing its rooted path by hand (a rooted include is kept) and run again.

--check: writes nothing; exit 1 listing every include that is not rooted (with the path it
should have), every error above, and every CMake include directory that names a source folder
(target_include_directories / include_directories / gyrocal_test INCLUDE with a source folder:
the sources have one include root). Exit 0 prints the counts. Running the rewrite twice changes
nothing the second time; after it, --check passes (once CMake exports no source folder).

Python 3 standard library only.
"""

import argparse
import json
import os
import re
import subprocess
import sys

SOURCE_EXTENSIONS = (".cpp", ".hpp", ".h", ".c", ".cc")
# configure_file templates of C/C++ sources (processors/model/c_source.cpp.in): the copy in the
# build folder includes the same way.
TEMPLATE_EXTENSIONS = tuple(e + ".in" for e in SOURCE_EXTENSIONS)

# Headers written by the build (not in the source tree): their quoted names stay as they are.
GENERATED = [
    # lcm-gen's C++ of lcmtypes/*.lcm (build/generated/lcmtypes)
    re.compile(r"gyrocal/[a-z0-9_]+_t\.hpp"),
    # git describe (tools/version.cmake, build/generated)
    re.compile(r"gyrocal/version\.hpp"),
    # the harness list of tests/fuzz/CMakeLists.txt (in its build folder)
    re.compile(r"fuzz_harnesses\.inc"),
    # `gyrocal export --format c-header`, written by the firmware test into a scratch folder
    re.compile(r"gyrocal_coeffs\.h"),
]

INCLUDE_DIRECTIVE = re.compile(r'#[ \t]*include[ \t]*"([^"\n]*)"')


class Include:
    """One `#include "name"` directive: where it is and what it names."""

    def __init__(self, path, line, start, end, name):
        self.path = path  # the including file, from the root
        self.line = line  # 1-based
        self.start = start  # offsets of the name (between the quotes) in the file's text
        self.end = end
        self.name = name


def quoted_includes(path, text):
    """The quoted #include directives of a C/C++ text: at the start of a line (after blanks),
    outside comments, string and character literals and raw strings (a test may hold C code in a
    raw string)."""
    found = []
    i, n, line = 0, len(text), 1
    line_start = True  # only blanks since the last new line (outside comments)
    while i < n:
        c = text[i]
        if c == "\n":
            line += 1
            line_start = True
            i += 1
            continue
        if c in " \t\r\f\v":
            i += 1
            continue
        if line_start and c == "#":
            m = INCLUDE_DIRECTIVE.match(text, i)
            if m:
                found.append(Include(path, line, m.start(1), m.end(1), m.group(1)))
                i = m.end()
                line_start = False
                continue
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
            continue
        if text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            line += text.count("\n", i, j)
            i = j
            continue
        line_start = False
        raw = re.compile(r'(?:u8|u|U|L)?R"([^()\\ \t\n]{0,16})\(').match(text, i)
        if raw and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            close = ")" + raw.group(1) + '"'
            j = text.find(close, raw.end())
            j = n if j < 0 else j + len(close)
            line += text.count("\n", i, j)
            i = j
            continue
        if c.isalnum() or c == "_":
            # An identifier or number, in one piece (so that 1'000 is no character literal).
            j = i + 1
            while j < n and (text[j].isalnum() or text[j] in "_'." or
                             (text[j] in "+-" and text[j - 1] in "eEpP" and text[i].isdigit())):
                if text[j] == "'" and not text[i].isdigit():
                    break
                j += 1
            i = j
            continue
        if c in "\"'":
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            i = min(j + 1, n) if j < n and text[j] == c else j
            continue
        i += 1
    return found


def tree_files(root):
    """Every file git tracks or would add (so build folders and ignored files are out), from the
    root; without git, a walk that skips hidden folders and CMake build folders."""
    try:
        out = subprocess.run(["git", "-C", root, "ls-files", "-z", "-co", "--exclude-standard"],
                             check=True, capture_output=True).stdout
        files = [f for f in out.decode("utf-8").split("\0") if f]
        return sorted(f for f in files if os.path.isfile(os.path.join(root, f)))
    except (OSError, subprocess.CalledProcessError):
        pass
    files = []
    for folder, dirs, names in os.walk(root):
        dirs[:] = [d for d in dirs if not d.startswith(".")
                   and not os.path.exists(os.path.join(folder, d, "CMakeCache.txt"))]
        for name in names:
            files.append(os.path.relpath(os.path.join(folder, name), root).replace(os.sep, "/"))
    return sorted(files)


def norm(path):
    """A path from the root, normalized with forward slashes; None if it leaves the root."""
    p = os.path.normpath(path).replace(os.sep, "/")
    return None if p == ".." or p.startswith("../") or os.path.isabs(p) else p


class IncludeDirs:
    """The include folders of today's build (compile_commands.json), from the root: per compiled
    file in the compiler's search order, and their union (for headers)."""

    def __init__(self, root, compile_commands):
        self.per_file = {}
        self.all = []
        if not compile_commands or not os.path.isfile(compile_commands):
            return
        with open(compile_commands, encoding="utf-8") as f:
            entries = json.load(f)
        seen = set()
        for e in entries:
            args = e.get("arguments") or _split_command(e.get("command", ""))
            where = e.get("directory", root)
            dirs = []
            k = 0
            while k < len(args):
                a = args[k]
                for flag in ("-iquote", "-I"):
                    if a.startswith(flag):
                        d = a[len(flag):] or (args[k + 1] if k + 1 < len(args) else "")
                        if not a[len(flag):]:
                            k += 1
                        rel = _from_root(root, os.path.join(where, d))
                        if rel is not None:
                            dirs.append(rel)
                        break
                k += 1
            f_rel = _from_root(root, os.path.join(where, e.get("file", "")))
            if f_rel is not None:  # a file compiled by several targets has several lists
                self.per_file.setdefault(f_rel, []).append(dirs)
            for d in dirs:
                if d not in seen:
                    seen.add(d)
                    self.all.append(d)

    def known(self):
        return bool(self.per_file)


def _split_command(command):
    import shlex
    return shlex.split(command)


def _from_root(root, path):
    rel = os.path.relpath(os.path.realpath(path), os.path.realpath(root)).replace(os.sep, "/")
    return None if rel == ".." or rel.startswith("../") else ("" if rel == "." else rel)


def generated(name):
    return any(pattern.fullmatch(name) for pattern in GENERATED)


def resolve(inc, files, by_suffix, dirs):
    """(the included file from the root, None) or (None, error text) or (None, None) for a
    generated header."""
    name = inc.name
    here = os.path.dirname(inc.path)
    if name.startswith("/"):
        return None, "an absolute path: name the file from the repository root"
    local = norm(os.path.join(here, name))
    if local is not None and local in files:
        return local, None
    if name.startswith("./") or name.startswith("../"):
        return None, "a relative path to no file of the tree"
    if generated(name):
        return None, None  # found in a build folder, whatever the tree holds
    key = norm(name)
    candidates = sorted(by_suffix.get(key, ())) if key else []
    if not candidates:
        return None, ("no file of the tree ends in /%s and it is no generated header "
                      "(GENERATED in tools/dev/root_includes.py)" % name)
    if len(candidates) == 1:
        return candidates[0], None
    if key in files:
        return key, None  # already rooted
    if dirs.known():
        searches = dirs.per_file.get(inc.path)
        if searches is not None:
            found = set()
            for search in searches:
                for d in search:  # the compiler's order
                    p = norm(os.path.join(d, key)) if d else key
                    if p in candidates:
                        found.add(p)
                        break
            if len(found) == 1:
                return found.pop(), None
            if found:
                candidates = sorted(found)
        else:
            reached = [c for c in candidates
                       if any((norm(os.path.join(d, key)) if d else key) == c for d in dirs.all)]
            if len(reached) == 1:
                return reached[0], None
            if reached:
                candidates = reached
    return None, ("ambiguous: %s; write the rooted path of the right one by hand and run again"
                  % ", ".join(candidates))


CMAKE_CALL = re.compile(r"\b(target_include_directories|include_directories|gyrocal_test)\s*\(",
                        re.IGNORECASE)
ALLOWED_DIR_ARGS = {"${PROJECT_SOURCE_DIR}", "${CMAKE_SOURCE_DIR}"}  # the one root, top level only


def cmake_source_exports(root, files):
    """CMake include directories that name a source folder other than the root (file:line text).
    Binary-folder ones (generated headers) are fine."""
    problems = []
    for f in files:
        if os.path.basename(f) != "CMakeLists.txt" and not f.endswith(".cmake"):
            continue
        with open(os.path.join(root, f), encoding="utf-8") as fh:
            text = fh.read()
        # Drop comments (a # outside quotes, to the end of the line), keep the lines.
        text = re.sub(r'#[^\n"]*', "", text)
        for m in CMAKE_CALL.finditer(text):
            depth, j = 1, m.end()
            while j < len(text) and depth:
                depth += {"(": 1, ")": -1}.get(text[j], 0)
                j += 1
            args = text[m.end():j - 1].split()
            kind = m.group(1).lower()
            if kind == "gyrocal_test":
                if "INCLUDE" not in args:
                    continue
                keywords = {"LINK", "DEFINE", "INCLUDE", "NEEDS", "PREFIX", "TIMEOUT",
                            "DISCOVERY_TIMEOUT"}
                k = args.index("INCLUDE") + 1
                dir_args = []
                while k < len(args) and args[k] not in keywords:
                    dir_args.append(args[k])
                    k += 1
            else:
                skip = {"SYSTEM", "BEFORE", "AFTER", "PUBLIC", "PRIVATE", "INTERFACE"}
                dir_args = [a for a in args[1 if kind == "target_include_directories" else 0:]
                            if a.upper() not in skip]
            for a in dir_args:
                if "BINARY_DIR" in a or a.startswith("${gen_"):
                    continue
                if a in ALLOWED_DIR_ARGS and f == "CMakeLists.txt":
                    continue
                line = text.count("\n", 0, m.start()) + 1
                problems.append("%s:%d: %s names %s: the sources' one include root is the "
                                "repository root (top-level CMakeLists.txt)"
                                % (f, line, m.group(1), a))
    return problems


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="See the module text (head of this file) for the rules.")
    ap.add_argument("--check", action="store_true",
                    help="change nothing; exit 1 listing every include not rooted")
    ap.add_argument("--root", default=os.path.normpath(os.path.join(here, "..", "..")),
                    help="the repository root (default: the one holding this script)")
    ap.add_argument("--compile-commands", default=None,
                    help="compile_commands.json of a configured build, used only to choose "
                         "among several files of the same name (default: "
                         "ROOT/build/compile_commands.json if it exists)")
    ap.add_argument("-v", "--verbose", action="store_true", help="print every rewrite")
    opt = ap.parse_args()

    root = os.path.realpath(opt.root)
    cc = opt.compile_commands
    if cc is None:
        default = os.path.join(root, "build", "compile_commands.json")
        cc = default if os.path.isfile(default) else None
    elif not os.path.isfile(cc):
        sys.exit("root_includes.py: --compile-commands %s: no such file" % cc)
    dirs = IncludeDirs(root, cc)

    files_list = tree_files(root)
    files = set(files_list)
    by_suffix = {}
    for f in files_list:
        parts = f.split("/")
        for k in range(len(parts)):
            by_suffix.setdefault("/".join(parts[k:]), []).append(f)

    sources = [f for f in files_list if f.endswith(SOURCE_EXTENSIONS + TEMPLATE_EXTENSIONS)]
    errors, unrooted, edits = [], [], {}
    n_includes = n_generated = 0
    for f in sources:
        with open(os.path.join(root, f), encoding="utf-8", newline="") as fh:
            text = fh.read()
        for inc in quoted_includes(f, text):
            n_includes += 1
            target, err = resolve(inc, files, by_suffix, dirs)
            where = "%s:%d: #include \"%s\"" % (f, inc.line, inc.name)
            if err:
                errors.append("%s: %s" % (where, err))
                continue
            if target is None:
                n_generated += 1
                continue
            # With the root as the only include folder, the rooted name must give the same file.
            shadow = norm(os.path.join(os.path.dirname(f), target))
            if shadow != target and shadow in files:
                errors.append("%s: its rooted path %s would find %s (the including file's folder "
                              "comes first)" % (where, target, shadow))
                continue
            if inc.name != target:
                unrooted.append("%s -> \"%s\"" % (where, target))
                edits.setdefault(f, (text, []))[1].append((inc, target))

    cmake_problems = cmake_source_exports(root, files_list) if opt.check else []
    for e in errors:
        print("root_includes.py: error: " + e, file=sys.stderr)
    if opt.check:
        for u in unrooted:
            print("root_includes.py: not rooted: " + u, file=sys.stderr)
        for p in cmake_problems:
            print("root_includes.py: " + p, file=sys.stderr)
        if errors or unrooted or cmake_problems:
            print("root_includes.py: --check: %d of %d quoted includes in %d files not rooted, "
                  "%d errors, %d CMake source include directories; fix: tools/dev/root_includes.py "
                  "(then clang-format -i on the files it names)" % (
                      len(unrooted), n_includes, len(sources), len(errors), len(cmake_problems)),
                  file=sys.stderr)
            return 1
        print("root_includes.py: --check: all %d quoted includes of %d files rooted "
              "(%d generated headers kept by name)" % (n_includes, len(sources), n_generated))
        return 0
    if errors:
        print("root_includes.py: %d errors, nothing written" % len(errors), file=sys.stderr)
        return 1
    for f, (text, changes) in sorted(edits.items()):
        out, last = [], 0
        for inc, target in sorted(changes, key=lambda c: c[0].start):
            out.append(text[last:inc.start])
            out.append(target)
            last = inc.end
            if opt.verbose:
                print("%s:%d: \"%s\" -> \"%s\"" % (f, inc.line, inc.name, target))
        out.append(text[last:])
        with open(os.path.join(root, f), "w", encoding="utf-8", newline="") as fh:
            fh.write("".join(out))
    for f in sorted(edits):
        print(f)
    print("root_includes.py: rewrote %d of %d quoted includes in %d of %d files "
          "(%d generated headers kept by name); run clang-format -i on the files above" % (
              len(unrooted), n_includes, len(edits), len(sources), n_generated), file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
