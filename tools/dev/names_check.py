#!/usr/bin/env python3
"""One name per library: its folder, its CMake target and its C++ namespace say the same.

    tools/dev/names_check.py [--root DIR]            list every mismatch, exit 1 on a new one
    tools/dev/names_check.py --all [--root DIR]      the same, listing the allowed ones too

The rule (docs/developing.md#names): a library of the layers lcmtypes/ producers/ processors/
store/ tools/ lives alone in its folder (one add_library per CMakeLists.txt), and for the folder
LAYER/a/b:
  target     gyrocal_a_b       (the folder's path below the layer, "/" -> "_")
  namespace  gyrocal::a::b     (the same path, "/" -> "::")
Its code (every .cpp .hpp of the folder itself, not of its sub-folders, without the sources of
the folder's executables) is declared in that namespace or in one nested in it
(gyrocal::a::b::detail); anonymous namespaces are free. A pure library and its LCM node are two
folders, a and a/node. The one exception is the layer lcmtypes/ itself: its library is the
generated message types, target gyrocal_lcmtypes, LCM package (namespace) gyrocal.

Mismatches are listed one a line, each as a stable key:
  FOLDER: libraries A B ...          the folder holds several libraries
  FOLDER: target T, expected E       a library whose target is not the folder's name
  FOLDER: namespace N, expected E    code of the folder declared in another namespace
                                     (the first file:line that does so follows the key)
tools/dev/names_allowed.txt lists the mismatches not fixed yet, each with its reason. Exit 1 when
a mismatch is not in that list, or when an entry of the list matches no mismatch any more (then
the entry is to be deleted: the list only shrinks). Exit 0 prints the counts.

Python 3 standard library only.
"""

import argparse
import os
import re
import sys

LAYERS = ("lcmtypes", "producers", "processors", "store", "tools")
ALLOWED_FILE = os.path.join("tools", "dev", "names_allowed.txt")
CODE_EXTENSIONS = (".cpp", ".hpp")

ADD_LIBRARY = re.compile(r"^\s*add_library\(\s*([A-Za-z0-9_\-${}]+)", re.M)
ADD_EXECUTABLE = re.compile(r"^\s*add_executable\(([^)]*)\)", re.M)
CMAKE_COMMENT = re.compile(r"#[^\n]*")


def expected_names(folder):
    """(target, namespace) the rule gives the library in FOLDER (a path from the root)."""
    parts = folder.split("/")
    below = parts[1:]
    if not below:  # the layer's own folder: only lcmtypes/ has a library (the message types)
        return "gyrocal_" + parts[0], "gyrocal"
    return "gyrocal_" + "_".join(below), "gyrocal::" + "::".join(below)


def strip_code(text):
    """TEXT with comments, string and character literals (raw strings too) and preprocessor
    lines blanked out, newlines kept (so offsets still give line numbers)."""
    out = []
    i, n = 0, len(text)
    at_line_start = True
    while i < n:
        c = text[i]
        if at_line_start and c == "#":
            j = i
            while j < n and text[j] != "\n":  # a directive, with its continuation lines
                if text[j] == "\\" and j + 1 < n and text[j + 1] == "\n":
                    out.append("  \n")
                    j += 2
                    continue
                out.append(" ")
                j += 1
            i = j
            continue
        if c in " \t":
            out.append(c)
            i += 1
            continue
        at_line_start = c == "\n"
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == "R" and text.startswith('R"', i) and (i == 0 or not text[i - 1].isalnum()):
            m = re.compile(r'R"([^(\s]*)\(').match(text, i)
            if not m:
                out.append(c)
                i += 1
                continue
            end = text.find(")" + m.group(1) + '"', m.end())
            j = n if end < 0 else end + len(m.group(1)) + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c in "\"'":
            if c == "'" and i > 0 and text[i - 1].isalnum():  # a digit separator: 1'000
                out.append(" ")
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            j = min(j + 1, n)
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


NAMESPACE_OPEN = re.compile(r"\bnamespace\s+((?:[A-Za-z_]\w*)(?:\s*::\s*[A-Za-z_]\w*)*)?\s*\{")


def namespaces_with_code(text):
    """[(qualified namespace, line)] of every named namespace block of TEXT that holds code of
    its own (not only nested namespace blocks). Anonymous blocks count as their enclosing one
    only when that is named; code at global scope is not listed."""
    code = strip_code(text)
    stack = []  # entries: [qualified name or None for a non-namespace brace, has_code, line]
    found = []
    i, n = 0, len(code)
    while i < n:
        m = NAMESPACE_OPEN.match(code, i) if code[i] == "n" else None
        if m and (i == 0 or not (code[i - 1].isalnum() or code[i - 1] == "_")):
            name = m.group(1)
            enclosing = next((e for e in reversed(stack) if e[0] is not None), None)
            prefix = enclosing[0] if enclosing else ""
            if name:
                name = re.sub(r"\s+", "", name)
                qualified = prefix + "::" + name if prefix else name
            else:
                qualified = prefix if prefix else "(anonymous)"
            stack.append([qualified, False, code.count("\n", 0, i) + 1])
            i = m.end()
            continue
        c = code[i]
        if c == "{":
            if stack and stack[-1][0] is not None:
                stack[-1][1] = True
            stack.append([None, False, 0])
        elif c == "}":
            if stack:
                entry = stack.pop()
                if entry[0] is not None and entry[1] and entry[0] != "(anonymous)":
                    found.append((entry[0], entry[2]))
        elif not c.isspace() and stack and stack[-1][0] is not None:
            stack[-1][1] = True
        i += 1
    return found


def executable_sources(cmake_text):
    sources = set()
    for m in ADD_EXECUTABLE.finditer(cmake_text):
        for word in m.group(1).split()[1:]:
            sources.add(word)
    return sources


def mismatches(root):
    """[(key, where)] for every library of the layers that breaks the rule."""
    found = []
    for layer in LAYERS:
        for dirpath, dirnames, filenames in os.walk(os.path.join(root, layer)):
            dirnames[:] = sorted(d for d in dirnames if not d.startswith("."))
            if "CMakeLists.txt" not in filenames:
                continue
            folder = os.path.relpath(dirpath, root).replace(os.sep, "/")
            with open(os.path.join(dirpath, "CMakeLists.txt"), encoding="utf-8") as f:
                cmake = CMAKE_COMMENT.sub("", f.read())
            libraries = ADD_LIBRARY.findall(cmake)
            if not libraries:
                continue
            target, namespace = expected_names(folder)
            cmake_file = folder + "/CMakeLists.txt"
            if len(libraries) > 1:
                found.append((folder + ": libraries " + " ".join(libraries), cmake_file))
            for library in libraries:
                if library != target:
                    found.append(
                        (f"{folder}: target {library}, expected {target}", cmake_file))
            executables = executable_sources(cmake)
            seen = {}
            for name in sorted(filenames):
                if not name.endswith(CODE_EXTENSIONS) or name in executables:
                    continue
                path = os.path.join(dirpath, name)
                with open(path, encoding="utf-8", errors="replace") as f:
                    text = f.read()
                for qualified, line in namespaces_with_code(text):
                    if qualified == namespace or qualified.startswith(namespace + "::"):
                        continue
                    if qualified not in seen:
                        seen[qualified] = f"{folder}/{name}:{line}"
            for qualified in sorted(seen):
                found.append((f"{folder}: namespace {qualified}, expected {namespace}",
                              seen[qualified]))
    return found


def read_allowed(root):
    """{key: line number} of tools/dev/names_allowed.txt (# comments and blank lines skipped)."""
    allowed = {}
    path = os.path.join(root, ALLOWED_FILE)
    if not os.path.exists(path):
        return allowed
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            line = line.split("#", 1)[0].strip()
            if line:
                allowed[line] = number
    return allowed


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--root", default=os.path.join(os.path.dirname(__file__), "..", ".."))
    parser.add_argument("--all", action="store_true", help="list the allowed mismatches too")
    args = parser.parse_args()
    root = os.path.abspath(args.root)

    found = mismatches(root)
    allowed = read_allowed(root)
    keys = {key for key, _ in found}
    new = [(key, where) for key, where in found if key not in allowed]
    stale = [(key, number) for key, number in allowed.items() if key not in keys]

    if args.all:
        for key, where in found:
            if key in allowed:
                print(f"allowed: {key}  ({where})")
    for key, where in new:
        print(f"mismatch: {key}  ({where})")
    for key, number in stale:
        print(f"{ALLOWED_FILE}:{number}: no longer a mismatch, delete the entry: {key}")
    print(f"names_check: {len(found)} mismatches ({len(found) - len(new)} allowed, "
          f"{len(new)} new), {len(stale)} stale allow-list entries")
    return 1 if new or stale else 0


if __name__ == "__main__":
    sys.exit(main())
