#!/usr/bin/env python3
"""The tree's rules that the compiler does not enforce, checked on the sources.

1. Layers: data flows one way, format -> cloth -> reference -> harness -> cli. src/format
   includes nothing of the project's; src/cloth includes only cloth/ headers (never Bullet,
   TOML, CSV or a layer above); reference/ includes format/, cloth/ and reference/ only;
   src/harness never includes src/cli; a project header is included by its path from src/
   (or the root for reference/), never by its bare name.
2. Rooms: inside a layer the folders point one way too. The engine's parts:
   model <- forces <- contact <- solvers <- integrators <- analysis; the harness's stages:
   io <- scenario <- engines <- fabric <- run <- sweeps <- gate. A folder may include its own headers
   and those of a folder before it, never one after it.
3. Folder size: no source folder under src/ or reference/ holds more than 16 concepts (a
   .hpp/.cpp pair, or a lone .hpp or .cpp, counts one) or more than a third of the C++ lines
   under src/ and reference/.
4. Function length: no function in src/ or reference/ is longer than 80 lines, counted from
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
MAX_CONCEPTS = 16
MAX_LINE_SHARE = 1 / 3
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^>"]+)[>"]')
QUOTED = re.compile(r'^\s*#\s*include\s*"([^"]+)"')
# what each layer may include of the project's own folders
ALLOWED = {
    "src/format": {"format"},
    "src/cloth": {"cloth"},
    "reference": {"format", "cloth", "reference"},
    "src/harness": {"format", "cloth", "reference", "harness"},
}
PROJECT_DIRS = {"format", "cloth", "reference", "harness", "cli"}
FORBIDDEN_IN_CLOTH = ("toml++/", "btBulletDynamicsCommon.h", "BulletSoftBody/", "BulletDynamics/",
                      "LinearMath/")
# the rooms of a layer, in the order their dependencies point: a room may include its own
# headers and those of an earlier room, never a later one's
ROOMS = {
    "cloth": ["model", "forces", "contact", "solvers", "integrators", "analysis"],
    "harness": ["io", "scenario", "engines", "fabric", "run", "sweeps", "stability", "gate"],
}
CPP_SUFFIXES = (".cpp", ".hpp", ".h")


def sources(root, folder):
    base = os.path.join(root, folder)
    for dirpath, dirs, files in os.walk(base):
        dirs.sort()
        for f in sorted(files):
            if f.endswith(CPP_SUFFIXES):
                yield os.path.join(dirpath, f)


def room_violation(layer, rel, target):
    """Why rel (a file of src/<layer>/) must not include target, or None."""
    parts = rel.split("/")
    wanted = target.split("/")
    if wanted[0] != layer:
        return None
    rooms = ROOMS[layer]
    if len(wanted) < 3 or wanted[1] not in rooms:
        return f"{target} is in no room of src/{layer} ({', '.join(rooms)})"
    if len(parts) < 4 or parts[2] not in rooms:
        return None
    if rooms.index(wanted[1]) > rooms.index(parts[2]):
        return (f"src/{layer}/{parts[2]} must not include {target} "
                f"({' <- '.join(rooms)}: a room uses only earlier ones)")
    return None


def layer_violations(root):
    out = []
    for folder, allowed in ALLOWED.items():
        for path in sources(root, folder):
            rel = os.path.relpath(path, root).replace(os.sep, "/")
            with open(path, encoding="utf-8") as fh:
                for number, line in enumerate(fh, 1):
                    m = INCLUDE.match(line)
                    if not m:
                        continue
                    target = m.group(1)
                    top = target.split("/")[0]
                    if top in PROJECT_DIRS and top not in allowed:
                        out.append(f"{rel}:{number}: {folder} must not include {target} "
                                   f"(allowed: {', '.join(sorted(allowed))})")
                    if folder == "src/cloth" and target.startswith(FORBIDDEN_IN_CLOTH):
                        out.append(f"{rel}:{number}: src/cloth must not include {target}")
                    if QUOTED.match(line) and "/" not in target:
                        out.append(f"{rel}:{number}: {folder} includes {target} by its bare "
                                   "name: write its path from src/")
                    layer = folder.split("/")[-1]
                    why = room_violation(layer, rel, target) if layer in ROOMS else None
                    if why:
                        out.append(f"{rel}:{number}: {why}")
    return out


def line_count(path):
    with open(path, encoding="utf-8") as fh:
        return sum(1 for _ in fh)


def folder_violations(root):
    """Folders with more than MAX_CONCEPTS concepts or MAX_LINE_SHARE of the C++ lines."""
    concepts, lines = {}, {}
    for folder in ("src", "reference"):
        for path in sources(root, folder):
            rel = os.path.relpath(path, root).replace(os.sep, "/")
            where, name = rel.rsplit("/", 1)
            concepts.setdefault(where, set()).add(os.path.splitext(name)[0])
            lines[where] = lines.get(where, 0) + line_count(path)
    total = sum(lines.values())
    out = []
    for where in sorted(concepts):
        if len(concepts[where]) > MAX_CONCEPTS:
            out.append(f"{where}/: {len(concepts[where])} concepts, over {MAX_CONCEPTS}: "
                       "split it into rooms by what its files do")
        if lines[where] > MAX_LINE_SHARE * total:
            out.append(f"{where}/: {lines[where]} of the {total} C++ lines in src/ and "
                       f"reference/, over a third: split it into rooms")
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
    return layer_violations(root) + folder_violations(root) + length_violations(root)


def self_test():
    with tempfile.TemporaryDirectory() as root:
        def write(rel, text):
            os.makedirs(os.path.dirname(os.path.join(root, rel)), exist_ok=True)
            with open(os.path.join(root, rel), "w", encoding="utf-8") as fh:
                fh.write(text)

        def filler(n):
            return "".join(f"// line {k}\n" for k in range(n))
        # a tree that keeps every rule: one-way includes, rooms in order, lines spread out
        write("src/format/f.cpp", '#include "format/f.hpp"\n' + filler(99))
        write("src/cloth/model/a.cpp", '#include "cloth/model/b.hpp"\nint f() {\n  return 1;\n}\n'
              + filler(96))
        write("src/cloth/solvers/s.cpp", '#include "cloth/model/a.hpp"\n' + filler(99))
        write("reference/r.cpp", '#include "cloth/model/a.hpp"\n#include "reference/r.hpp"\n'
              '#include "format/f.hpp"\n' + filler(97))
        write("src/harness/io/i.cpp", '#include "harness/io/i.hpp"\n' + filler(99))
        write("src/harness/run/r.cpp", '#include "harness/io/i.hpp"\n#include "reference/r.hpp"\n'
              + filler(98))
        write("src/cli/main.cpp", '#include "harness/gate/g.hpp"\n#include "commands.hpp"\n'
              + filler(98))
        for k in range(MAX_CONCEPTS - 1):  # with main.cpp: as many concepts as allowed
            write(f"src/cli/c{k}.hpp", "#pragma once\n")
        assert check(root) == [], check(root)
        # ... then breaks each rule once
        write("reference/bad.hpp", '#include "harness/scenario/scenario.hpp"\n')
        write("src/cloth/model/bad.cpp", '#include <toml++/toml.h>\n#include "harness/x/y.hpp"\n')
        write("src/format/bad.hpp", '#include "cloth/model/a.hpp"\n')
        write("src/cloth/contact/up.hpp", '#include "cloth/integrators/i.hpp"\n')
        write("src/harness/io/up.hpp", '#include "harness/scenario/scenario.hpp"\n')
        write("src/harness/run/up.cpp", '#include "harness/gate/g.hpp"\n#include "harness/g.hpp"\n'
              '#include "cli/summaries.hpp"\n#include "summaries.hpp"\n')
        for k in range(MAX_CONCEPTS + 1):
            write(f"src/harness/gate/g{k}.hpp", "#pragma once\n")
        write("src/harness/sweeps/big.cpp", filler(2000))
        body = "\n".join(f"  x += {k};" for k in range(MAX_LINES - 2))
        write("src/harness/engines/ok.cpp", "namespace n {\nint ok(int x) {\n" + body + "\n}\n}\n")
        write("src/harness/engines/long.cpp",
              "namespace n {\nstruct S {\n  int y = 0;\n};\nint long_one(int x,\n             int z) {\n"
              + body + "\n  auto l = [](int a) {\n    return a;\n  };\n  return l(x);\n}\n}\n")
        found = check(root)
        expect = [
            "reference/bad.hpp:1: reference must not include harness/scenario/scenario.hpp",
            "src/cloth/model/bad.cpp:1: src/cloth must not include toml++/toml.h",
            "src/cloth/model/bad.cpp:2: src/cloth must not include harness/x/y.hpp",
            "src/format/bad.hpp:1: src/format must not include cloth/model/a.hpp",
            "src/cloth/contact/up.hpp:1: src/cloth/contact must not include "
            "cloth/integrators/i.hpp",
            "src/harness/io/up.hpp:1: src/harness/io must not include harness/scenario/scenario.hpp",
            "src/harness/run/up.cpp:1: src/harness/run must not include harness/gate/g.hpp",
            "src/harness/run/up.cpp:2: harness/g.hpp is in no room of src/harness",
            "src/harness/run/up.cpp:3: src/harness must not include cli/summaries.hpp",
            "src/harness/run/up.cpp:4: src/harness includes summaries.hpp by its bare name",
            f"src/harness/gate/: {MAX_CONCEPTS + 1} concepts, over {MAX_CONCEPTS}",
            "src/harness/sweeps/: 2000 of the ",
            "src/harness/engines/long.cpp:5: 85 lines, over 80"]
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
    print(f"check_layout: layers and rooms one-way, no folder over {MAX_CONCEPTS} concepts or a "
          f"third of the lines, no function over {MAX_LINES} lines in src/ and reference/")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
