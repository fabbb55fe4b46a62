#!/usr/bin/env python3
"""Holds the libraries' layers (docs/architecture.md): no library's code
includes a header of a library it does not build on. (That the detector's
kernels include none of its stages is detector/check_kernel_includes.cmake's.)

Usage: layering_test.py SOURCE_DIR. Prints each offending include as
"path:line: includes chromatag/<lib>/... (<lib> is not below <this lib>)" and
exits 1 if there is any. Unit tests beside the code (*_test.cc) may use more
than their library does and are not checked.
"""
import os
import re
import sys

# Each library and the ones it may include, as CMake links them.
BELOW = {
    "base": set(),
    "families": {"base"},
    "layout": {"base", "families"},
    "detector": {"base", "families"},
    "generator": {"base", "families", "layout"},
    "rig": {"base", "families", "layout", "detector"},
    "verify": {"base", "families", "layout", "generator", "detector"},
    "calib": {"base", "families", "layout", "generator", "detector", "rig"},
}
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]chromatag/(\w+)/')


def sources(folder):
    for root, _, files in os.walk(folder):
        for name in sorted(files):
            if name.endswith((".h", ".cc", ".in")) and not name.endswith("_test.cc"):
                yield os.path.join(root, name)


def main():
    source = sys.argv[1]
    problems = []
    for lib, allowed in BELOW.items():
        if not any(sources(os.path.join(source, lib))):
            problems.append(f"{lib}/: no sources (a library renamed or moved? update BELOW)")
        for path in sources(os.path.join(source, lib)):
            with open(path, encoding="utf-8") as f:
                for number, line in enumerate(f, 1):
                    match = INCLUDE.match(line)
                    if match and match.group(1) != lib and match.group(1) not in allowed:
                        problems.append(f"{os.path.relpath(path, source)}:{number}: includes "
                                        f"chromatag/{match.group(1)}/... ({match.group(1)} is "
                                        f"not below {lib})")
    for problem in problems:
        print(problem)
    if not problems:
        print(f"layering_test: {len(BELOW)} libraries keep their layers")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
