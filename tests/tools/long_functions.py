#!/usr/bin/env python3
"""Lists functions (and process mains) longer than a limit, by brace counting.

Usage: tests/tools/long_functions.py [--limit 80] [--exclude DIR ...] [PATH ...]
Default paths: every folder but tests/. A function is a brace block whose header (the text since
the previous ';', '{' or '}') has a parameter list and is not a control statement, a class or a
namespace; lambdas inside a function count toward that function. Comments and string literals
(raw strings too) are blanked first. Prints "LINES path:line name", longest first; a heuristic,
good enough to find what to split (clang's AST would be exact).
"""
import argparse
import os
import re
import sys

CONTROL = re.compile(r'^\s*(if|for|while|switch|catch|else|do|try|return)\b')
TYPE_BLOCK = re.compile(r'\b(namespace|class|struct|union|enum)\b[^()]*$')


def blank(text):
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith('//', i):
            j = text.find('\n', i)
            j = n if j < 0 else j
            out.append(' ' * (j - i)); i = j
        elif text.startswith('/*', i):
            j = text.find('*/', i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r'[^\n]', ' ', text[i:j])); i = j
        elif text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == '_')):
            m = re.match(r'R"([^(\s]*)\(', text[i:])
            if not m:
                out.append(c); i += 1; continue
            end = text.find(')' + m.group(1) + '"', i)
            end = n if end < 0 else end + len(m.group(1)) + 2
            out.append('""' + re.sub(r'[^\n]', ' ', text[i + 2:end])); i = end
        elif c in '"\'':
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == '\\' else 1
            out.append(c + ' ' * (j - i - 1) + c); i = j + 1
        else:
            out.append(c); i += 1
    return ''.join(out)


def functions(path):
    text = blank(open(path, encoding='utf-8', errors='replace').read())
    stack, header_start, found = [], 0, []
    line_of = lambda pos: text.count('\n', 0, pos) + 1
    for pos, c in enumerate(text):
        if c in ';':
            header_start = pos + 1
        elif c == '{':
            header = ' '.join(text[header_start:pos].split())
            in_function = any(kind == 'function' for kind, _, _ in stack)
            is_function = (not in_function and '(' in header and not CONTROL.match(header)
                           and not TYPE_BLOCK.search(header) and '=' not in header.split('(')[0])
            name = header.split('(')[0].split()[-1] if is_function and header.split('(')[0].split() else ''
            stack.append(('function' if is_function else 'block', pos, name))
            header_start = pos + 1
        elif c == '}':
            if stack:
                kind, start, name = stack.pop()
                if kind == 'function':
                    found.append((line_of(pos) - line_of(start) + 1, line_of(start), name))
            header_start = pos + 1
    return found


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('paths', nargs='*')
    ap.add_argument('--limit', type=int, default=80)
    ap.add_argument('--exclude', nargs='*', default=[])
    a = ap.parse_args()
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    paths = a.paths or [os.path.join(root, d) for d in ('lcmtypes', 'producers', 'processors', 'store', 'tools')]
    rows = []
    for top in paths:
        for dirpath, _, files in os.walk(top):
            rel_dir = os.path.relpath(dirpath, root)
            if any(rel_dir == e or rel_dir.startswith(e.rstrip('/') + '/') for e in a.exclude):
                continue
            for f in files:
                if f.endswith(('.cpp', '.hpp')):
                    p = os.path.join(dirpath, f)
                    for lines, line, name in functions(p):
                        if lines > a.limit:
                            rows.append((lines, f'{os.path.relpath(p, root)}:{line}', name))
    for lines, where, name in sorted(rows, reverse=True):
        print(f'{lines:5d} {where} {name}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
