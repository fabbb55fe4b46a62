#!/usr/bin/env python3
"""Lists the project's longest functions, from the compiler's own view of them.

Usage: scripts/function_lengths.py [BUILD_DIR] [--over N] [--tests]

Reads BUILD_DIR/compile_commands.json (default: build), parses each C++
source of the tree the build was configured from with libclang (Debian: python3-clang-14) and prints every
function, method, constructor and lambda-free body of more than N lines
(default 60), longest first, as "lines  path:line  name". Test sources
(*_test.cc, tests/) are left out unless --tests is given. A lambda counts as
part of the function that holds it. Exits 0; this is a report, not a gate.
"""
import argparse
import json
import os
import shlex
import sys

import clang.cindex as ci

LIBCLANG = "/usr/lib/llvm-14/lib/libclang-14.so.1"
KINDS = {
    ci.CursorKind.FUNCTION_DECL,
    ci.CursorKind.CXX_METHOD,
    ci.CursorKind.CONSTRUCTOR,
    ci.CursorKind.DESTRUCTOR,
    ci.CursorKind.FUNCTION_TEMPLATE,
    ci.CursorKind.CONVERSION_FUNCTION,
}


def parse_flags(command):
    """The include paths and definitions of a compile command, each with its
    argument (an "-isystem DIR" pair kept whole)."""
    argv = command.get("arguments") or shlex.split(command["command"])
    flags = []
    i = 1
    while i < len(argv):
        arg = argv[i]
        if arg in ("-isystem", "-I", "-D", "-include") and i + 1 < len(argv):
            flags += [arg, argv[i + 1]]
            i += 2
            continue
        if arg.startswith(("-I", "-D", "-std", "-isystem")):
            flags.append(arg)
        i += 1
    return flags


def is_test(path):
    return path.endswith("_test.cc") or "/tests/" in path or "/fuzz/" in path


def source_dir(build_dir):
    """The source tree the build dir was configured from (its CMakeCache)."""
    with open(os.path.join(build_dir, "CMakeCache.txt")) as f:
        for line in f:
            if line.startswith("CMAKE_HOME_DIRECTORY:"):
                return os.path.realpath(line.split("=", 1)[1].strip())
    sys.exit(f"{build_dir} is not a CMake build folder (no CMAKE_HOME_DIRECTORY)")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build_dir", nargs="?", default="build")
    parser.add_argument("--over", type=int, default=60)
    parser.add_argument("--tests", action="store_true")
    args = parser.parse_args()
    root = source_dir(args.build_dir)
    with open(os.path.join(args.build_dir, "compile_commands.json")) as f:
        commands = json.load(f)
    if os.path.exists(LIBCLANG):
        ci.Config.set_library_file(LIBCLANG)
    build = os.path.realpath(args.build_dir)
    index = ci.Index.create()
    seen = {}
    failed = 0
    for command in commands:
        source = os.path.realpath(command["file"])
        # The tree's own sources: not generated ones in the build folder.
        if not source.startswith(root + os.sep) or source.startswith(build + os.sep):
            continue
        if is_test(source) and not args.tests:
            continue
        flags = parse_flags(command)
        flags += ["-isystem", "/usr/lib/llvm-14/lib/clang/14.0.6/include"]
        unit = index.parse(source, args=flags)
        if any(d.severity >= ci.Diagnostic.Error for d in unit.diagnostics):
            failed += 1
        for cursor in unit.cursor.walk_preorder():
            if cursor.kind not in KINDS or not cursor.is_definition():
                continue
            where = cursor.location.file
            if where is None:
                continue
            path = os.path.realpath(where.name)
            if not path.startswith(root + os.sep) or (is_test(path) and not args.tests):
                continue
            lines = cursor.extent.end.line - cursor.extent.start.line + 1
            key = (path, cursor.extent.start.line)
            seen[key] = (lines, cursor.spelling)
    rows = sorted(((n, p, l, name) for (p, l), (n, name) in seen.items() if n > args.over),
                  reverse=True)
    for n, path, line, name in rows:
        print(f"{n:5d}  {os.path.relpath(path, root)}:{line}  {name}")
    print(f"{len(rows)} functions over {args.over} lines", file=sys.stderr)
    if failed:
        print(f"{failed} sources parsed with errors: their functions may be missing",
              file=sys.stderr)


if __name__ == "__main__":
    main()
