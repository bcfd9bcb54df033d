#!/usr/bin/env python3
"""The tree's rules that the compiler does not enforce, checked on the sources.

1. Layers: data flows one way, cloth -> reference -> harness -> cli. src/cloth includes only
   cloth/ headers (never Bullet, TOML, CSV or a layer above); reference/ includes cloth/ and
   reference/ only; src/harness never includes src/cli.
2. Function length: no function in src/ or reference/ is longer than 80 lines, counted from
   the line that opens its body's brace back to its signature's first line, to the closing
   brace (lambdas count toward the function that holds them).

Usage: check_layout.py SOURCE_DIR     (exit 1 and one line per violation when a rule fails)
       check_layout.py --self-test    (proves each rule fails on a tree that breaks it)
"""

import os
import re
import sys
import tempfile

MAX_LINES = 80
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^>"]+)[>"]')
# what each layer may include of the project's own folders
ALLOWED = {
    "src/cloth": {"cloth"},
    "reference": {"cloth", "reference"},
    "src/harness": {"cloth", "reference", "harness"},
}
PROJECT_DIRS = {"cloth", "reference", "harness", "cli"}
FORBIDDEN_IN_CLOTH = ("toml++/", "btBulletDynamicsCommon.h", "BulletSoftBody/", "BulletDynamics/",
                      "LinearMath/")


def sources(root, folder):
    base = os.path.join(root, folder)
    for dirpath, _, files in os.walk(base):
        for f in sorted(files):
            if f.endswith((".cpp", ".hpp", ".h")):
                yield os.path.join(dirpath, f)


def layer_violations(root):
    out = []
    for folder, allowed in ALLOWED.items():
        for path in sources(root, folder):
            with open(path, encoding="utf-8") as fh:
                for number, line in enumerate(fh, 1):
                    m = INCLUDE.match(line)
                    if not m:
                        continue
                    target = m.group(1)
                    top = target.split("/")[0]
                    rel = os.path.relpath(path, root)
                    if top in PROJECT_DIRS and top not in allowed:
                        out.append(f"{rel}:{number}: {folder} must not include {target} "
                                   f"(allowed: {', '.join(sorted(allowed))})")
                    if folder == "src/cloth" and target.startswith(FORBIDDEN_IN_CLOTH):
                        out.append(f"{rel}:{number}: src/cloth must not include {target}")
    return out


def strip_code(line):
    line = re.sub(r'"(\\.|[^"\\])*"', '""', line)
    line = re.sub(r"'(\\.|[^'\\])'", "''", line)
    return re.sub(r"//.*", "", line)


def function_lengths(path):
    """(lines, first line, signature) of every function body at namespace or class scope."""
    with open(path, encoding="utf-8") as fh:
        lines = fh.read().split("\n")
    depth, scopes, start, found = 0, [], None, []
    in_comment = False
    for i, raw in enumerate(lines):
        line = raw
        if in_comment:
            if "*/" not in line:
                continue
            line, in_comment = line.split("*/", 1)[1], False
        line = re.sub(r"/\*.*?\*/", "", strip_code(line))
        if "/*" in line:
            line, in_comment = line.split("/*", 1)[0], True
        for ch in line:
            if ch == "{":
                if start is None:
                    before = line.split("{")[0]
                    head = " ".join(lines[max(0, i - 2):i]) + " " + before
                    holds_functions = re.search(r"\b(namespace|class|struct|union|enum)\b[^;()]*$",
                                                head.split(")")[-1])
                    initialiser = re.search(r"=\s*$", before) or ")" not in head
                    if holds_functions or initialiser:
                        scopes.append(depth)
                    else:
                        # walk back to the signature's first line
                        sig = i
                        while sig > 0 and lines[sig - 1].strip() \
                                and not re.search(r"[;{}]\s*$", strip_code(lines[sig - 1])) \
                                and not lines[sig - 1].strip().startswith(("//", "#")):
                            sig -= 1
                        start = (sig, depth)
                depth += 1
            elif ch == "}":
                depth -= 1
                if start is not None and depth == start[1]:
                    found.append((i - start[0] + 1, start[0] + 1, lines[start[0]].strip()[:70]))
                    start = None
                elif scopes and scopes[-1] == depth:
                    scopes.pop()
    return found


def length_violations(root):
    out = []
    for folder in ("src", "reference"):
        for path in sources(root, folder):
            for n, first, sig in function_lengths(path):
                if n > MAX_LINES:
                    out.append(f"{os.path.relpath(path, root)}:{first}: {n} lines, over "
                               f"{MAX_LINES}: {sig}")
    return out


def check(root):
    return layer_violations(root) + length_violations(root)


def self_test():
    with tempfile.TemporaryDirectory() as root:
        def write(rel, text):
            os.makedirs(os.path.dirname(os.path.join(root, rel)), exist_ok=True)
            with open(os.path.join(root, rel), "w", encoding="utf-8") as fh:
                fh.write(text)
        write("src/cloth/a.cpp", '#include "cloth/b.hpp"\nint f() {\n  return 1;\n}\n')
        write("reference/r.cpp", '#include "cloth/a.hpp"\n#include "reference/r.hpp"\n')
        assert check(root) == [], check(root)
        write("reference/bad.hpp", '#include "harness/scenario.hpp"\n')
        write("src/cloth/bad.cpp", '#include <toml++/toml.h>\n#include "harness/x.hpp"\n')
        body = "\n".join(f"  x += {k};" for k in range(MAX_LINES - 2))
        write("src/harness/ok.cpp", "namespace n {\nint ok(int x) {\n" + body + "\n}\n}\n")
        write("src/harness/long.cpp",
              "namespace n {\nstruct S {\n  int y = 0;\n};\nint long_one(int x,\n             int z) {\n"
              + body + "\n  auto l = [](int a) {\n    return a;\n  };\n  return l(x);\n}\n}\n")
        found = check(root)
        expect = ["reference/bad.hpp:1: reference must not include harness/scenario.hpp",
                  "src/cloth/bad.cpp:1: src/cloth must not include toml++/toml.h",
                  "src/cloth/bad.cpp:2: src/cloth must not include harness/x.hpp",
                  "src/harness/long.cpp:5: 85 lines, over 80"]
        for e in expect:
            assert any(f.startswith(e) for f in found), (e, found)
        assert len(found) == len(expect), found
    print("check_layout self-test: every rule fails on a tree that breaks it")


def main(argv):
    if argv[1:] == ["--self-test"]:
        self_test()
        return 0
    if len(argv) != 2:
        print(__doc__.strip().split("\n\n")[-1], file=sys.stderr)
        return 2
    found = check(argv[1])
    for f in found:
        print(f)
    if found:
        print(f"check_layout: {len(found)} violation(s)")
        return 1
    print("check_layout: layers one-way, no function over "
          f"{MAX_LINES} lines in src/ and reference/")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
