#!/usr/bin/env python3
"""Holds cli/flag_terms.cc to the library messages it rewrites: each library
phrase must still occur in a library's sources (else a message changed and
the CLI stopped naming its flag, silently), and no flag-side text may
contain another entry's library phrase (else the rewriting would depend on
the table's order).

Usage: flag_terms_test.py SOURCE_DIR. Exits 1 naming each problem.
"""
import os
import re
import sys

LIBRARIES = ["base", "families", "layout", "generator", "detector", "rig", "verify", "calib"]
PAIR = re.compile(r'\{\s*"((?:[^"\\]|\\.)*)"\s*,\s*"((?:[^"\\]|\\.)*)"\s*\}', re.S)
LITERAL = re.compile(r'"((?:[^"\\]|\\.)*)"')


def library_text(source):
    """Every string literal of the libraries' non-test sources, adjacent
    literals joined as the compiler joins them."""
    texts = []
    for lib in LIBRARIES:
        for root, _, files in os.walk(os.path.join(source, lib)):
            for name in files:
                if name.endswith((".cc", ".h")) and not name.endswith("_test.cc"):
                    with open(os.path.join(root, name), encoding="utf-8") as f:
                        code = f.read()
                    # "a" "b" across a line break is one literal.
                    code = re.sub(r'"\s*\n\s*"', "", code)
                    texts += LITERAL.findall(code)
    return "\n".join(texts)


def main():
    source = sys.argv[1]
    with open(os.path.join(source, "cli", "flag_terms.cc"), encoding="utf-8") as f:
        table = f.read()
    table = table[table.index("kTerms[]"):]
    pairs = PAIR.findall(re.sub(r'"\s*\n\s*"', "", table))
    text = library_text(source)
    problems = []
    for library, flags in pairs:
        if library not in text:
            problems.append(f'"{library}" is in no library message any more')
        for other, _ in pairs:
            if other != library and other in flags:
                problems.append(f'"{flags}" contains the library phrase "{other}"')
    for problem in problems:
        print(f"flag_terms_test: {problem}")
    if not pairs:
        problems.append("no pairs read from cli/flag_terms.cc")
        print("flag_terms_test: no pairs read from cli/flag_terms.cc")
    if not problems:
        print(f"flag_terms_test: {len(pairs)} library phrases, each still in a library message")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
