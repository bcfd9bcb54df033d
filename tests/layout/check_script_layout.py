#!/usr/bin/env python3
"""The scripts' rules, checked on the sources (the C++ rules are check_layout.py's).

1. Python function length: no function (or method) in analysis/, tests/, scripts/ or examples/
   is longer than 60 lines, counted from its `def` line (decorators left out) to the last line
   of its body; a nested function counts toward the one that holds it, and on its own.
2. JavaScript function length: no function in analysis/ is longer than 60 lines, counted from
   the line that starts it (`function`, the name a method or an arrow function is given, or
   an anonymous arrow's parameters) to the line of its closing brace.
3. No import cycle among the modules of analysis/: every import counts, also one inside a
   function; a module's own enclosing packages are left out (Python imports them first, and
   a package's __init__ importing its modules is the usual pattern).

Usage: check_script_layout.py SOURCE_DIR     (exit 1 and one line per violation when a rule fails)
       check_script_layout.py --self-test    (proves each rule fails on a tree that breaks it)
"""

import ast
import os
import re
import sys
import tempfile

MAX_LINES = 60
PYTHON_ROOTS = ("analysis", "tests", "scripts", "examples")
JS_ROOTS = ("analysis",)
PACKAGE = "analysis"
SKIP_DIRS = {"__pycache__", "node_modules", "build"}


def files(root, folders, accept):
    for folder in folders:
        for dirpath, dirs, names in os.walk(os.path.join(root, folder)):
            dirs[:] = sorted(d for d in dirs if d not in SKIP_DIRS and not d.startswith("."))
            for name in sorted(names):
                path = os.path.join(dirpath, name)
                if accept(path):
                    yield path


def is_python(path):
    if path.endswith(".py"):
        return True
    if os.path.splitext(path)[1]:
        return False
    try:
        with open(path, encoding="utf-8") as fh:
            return re.match(r"#!.*\bpython", fh.readline() or "") is not None
    except (UnicodeDecodeError, OSError):
        return False


# --- Python ---------------------------------------------------------------------------------

def python_lengths(path):
    """(lines, first line, name) of every function in a Python file."""
    with open(path, encoding="utf-8") as fh:
        tree = ast.parse(fh.read(), path)
    return [(node.end_lineno - node.lineno + 1, node.lineno, node.name)
            for node in ast.walk(tree)
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef))]


def python_violations(root):
    out = []
    for path in files(root, PYTHON_ROOTS, is_python):
        for n, first, name in sorted(python_lengths(path), key=lambda f: f[1]):
            if n > MAX_LINES:
                out.append(f"{os.path.relpath(path, root)}:{first}: {n} lines, over "
                           f"{MAX_LINES}: def {name}")
    return out


# --- JavaScript -----------------------------------------------------------------------------

# a '/' after one of these (or at the start) opens a regular expression, else it divides
REGEX_AFTER = set("(,=:[!&|?{};+-*%<>~^") | {""}
NOT_FUNCTIONS = {"if", "for", "while", "switch", "catch", "with", "return", "function"}
IDENT = r"[A-Za-z_$][\w$]*"


def js_code(text):
    """text with comments, strings, template literals and regular expressions blanked to
    spaces (newlines and the quotes kept), so that the braces and parentheses left are the
    code's own."""
    out, i, n = list(text), 0, len(text)
    last = ""  # the last character of code before i that is not white space
    while i < n:
        c, nxt = text[i], text[i + 1:i + 2]
        if c == "/" and nxt in "/*" and nxt:
            end = text.find("\n" if nxt == "/" else "*/", i + 2)
            end = n if end < 0 else end + (0 if nxt == "/" else 2)
            first, stop = i, end  # a comment goes whole
        elif c in "'\"`" or (c == "/" and last in REGEX_AFTER):
            end, in_class = i + 1, False  # inside [...] of a regular expression '/' goes on
            while end < n and (text[end] != c or in_class):
                if text[end] == "\\":
                    end += 1
                elif c == "/" and text[end] in "[]":
                    in_class = text[end] == "["
                elif c != "`" and text[end] == "\n":
                    break
                end += 1
            end = min(n, end + 1)
            first, stop, last = i + 1, end - 1, c  # a literal keeps its quotes: an operand
        else:
            last = c if not c.isspace() else last
            i += 1
            continue
        for k in range(first, stop):
            if out[k] != "\n":
                out[k] = " "
        i = end
    return "".join(out)


def _matching_open(code, close):
    """Index of the '(' that the ')' at close ends, or -1."""
    depth = 0
    for k in range(close, -1, -1):
        if code[k] == ")":
            depth += 1
        elif code[k] == "(":
            depth -= 1
            if depth == 0:
                return k
    return -1


def _function_head(code, brace):
    """(start index, name) when the '{' at brace opens a function body, else None."""
    before = code[:brace].rstrip()
    if before.endswith("=>"):
        params = before[:-2].rstrip()
        if params.endswith(")"):
            start = _matching_open(params, len(params) - 1)
        else:
            m = re.search(IDENT + r"$", params)
            start = m.start() if m else len(params)
        named = re.search(r"(" + IDENT + r")\s*[=:]\s*(async\s+)?$", code[:start])
        return (named.start(1), named.group(1)) if named else (start, "(arrow)")
    if not before.endswith(")"):
        return None
    open_paren = _matching_open(code, len(before) - 1)
    if open_paren < 0:
        return None
    head = code[:open_paren]
    m = re.search(r"\bfunction\b\s*\*?\s*(" + IDENT + r")?\s*$", head)
    if m:
        if m.group(1):
            return m.start(), m.group(1)
        named = re.search(r"(" + IDENT + r")\s*[=:]\s*(async\s+)?$", head[:m.start()])
        return (named.start(1), named.group(1)) if named else (m.start(), "(anonymous)")
    m = re.search(r"(?:^|[\s{},;])(?:(?:static|async|get|set)\s+)*(" + IDENT + r")\s*$", head)
    if m and m.group(1) not in NOT_FUNCTIONS:
        return m.start(1), m.group(1)  # a method: name(params) { ... }
    return None


def js_lengths(text):
    """(lines, first line, name) of every function in JavaScript text."""
    code = js_code(text)
    found, opened = [], []  # opened: (index of '{', head or None)
    for k, c in enumerate(code):
        if c == "{":
            opened.append((k, _function_head(code, k)))
        elif c == "}" and opened:
            _, head = opened.pop()
            if head:
                first = code.count("\n", 0, head[0]) + 1
                last = code.count("\n", 0, k) + 1
                found.append((last - first + 1, first, head[1]))
    return found


def js_violations(root):
    out = []
    for path in files(root, JS_ROOTS, lambda p: p.endswith((".js", ".mjs"))):
        with open(path, encoding="utf-8") as fh:
            text = fh.read()
        for n, first, name in sorted(js_lengths(text), key=lambda f: f[1]):
            if n > MAX_LINES:
                out.append(f"{os.path.relpath(path, root)}:{first}: {n} lines, over "
                           f"{MAX_LINES}: function {name}")
    return out


# --- import cycles --------------------------------------------------------------------------

def module_names(root):
    """{module name: path} of every module of the analysis package."""
    names = {}
    base = os.path.join(root, PACKAGE)
    for path in files(root, (PACKAGE,), lambda p: p.endswith(".py")):
        parts = os.path.relpath(path, root)[:-3].split(os.sep)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        if os.path.isfile(os.path.join(base, "__init__.py")):
            names[".".join(parts)] = path
    return names


def imports_of(name, path, modules):
    """The package's modules that module `name` imports anywhere in its text."""
    with open(path, encoding="utf-8") as fh:
        tree = ast.parse(fh.read(), path)
    is_package = os.path.basename(path) == "__init__.py"
    here = name.split(".") if is_package else name.split(".")[:-1]
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                up = here[:len(here) - node.level + 1]
                base = ".".join(up + ([node.module] if node.module else []))
            else:
                base = node.module or ""
            targets = [base] + [f"{base}.{a.name}" for a in node.names]
        else:
            continue
        for t in targets:
            if t in modules:
                found.add(t)
    ancestors = {".".join(name.split(".")[:k]) for k in range(1, len(name.split(".")))}
    return sorted(found - ancestors - {name})


def import_cycles(root):
    """Each import cycle among the package's modules, as a list of module names."""
    modules = module_names(root)
    graph = {m: imports_of(m, p, modules) for m, p in modules.items()}
    cycles, done = [], set()

    def visit(m, path):
        if m in path:
            cycle = path[path.index(m):]
            k = cycle.index(min(cycle))  # one spelling per cycle: start at its smallest name
            cycle = cycle[k:] + cycle[:k]
            if cycle not in cycles:
                cycles.append(cycle)
            return
        if m in done:
            return
        for t in graph[m]:
            visit(t, path + [m])
        done.add(m)

    for m in sorted(graph):
        visit(m, [])
    return cycles


def cycle_violations(root):
    modules = module_names(root)
    return [f"{os.path.relpath(modules[c[0]], root)}: import cycle "
            f"{' -> '.join(c + [c[0]])}" for c in import_cycles(root)]


def check(root):
    return python_violations(root) + js_violations(root) + cycle_violations(root)


# --- self-test ------------------------------------------------------------------------------

def self_test():
    with tempfile.TemporaryDirectory() as root:
        def write(rel, text):
            os.makedirs(os.path.dirname(os.path.join(root, rel)), exist_ok=True)
            with open(os.path.join(root, rel), "w", encoding="utf-8") as fh:
                fh.write(text)

        def body(n, indent):
            return "".join(f"{indent}x += {k}\n" for k in range(n))

        # a tree that keeps every rule, with functions of exactly 60 lines
        write("analysis/__init__.py", "")
        write("analysis/a.py", "from .b import g\n\n\ndef f(x):\n" + body(58, "    ")
              + "    return g(x)\n")
        write("analysis/b.py", "import math\n\n\n@staticmethod\ndef g(x):\n" + body(59, "    "))
        write("analysis/plots/__init__.py", "from . import p\n")
        write("analysis/plots/p.py", "from . import q\nfrom .. import a\n")
        write("analysis/plots/q.py", "")
        js_ok = ("// a { in a comment, '}' in a string, /}/ in a regular expression\n"
                 "var s = '{', r = /[}/]/g, t = `${1}`;\n"
                 "function ok(a) {\n" + "".join(f"  a += {k};\n" for k in range(58)) + "}\n")
        write("analysis/player/ok.js", js_ok)
        assert check(root) == [], check(root)

        # now break each rule once
        write("analysis/long.py", "class C:\n    def method(self, x):\n" + body(60, "        "))
        write("tests/tool", "#!/usr/bin/env python3\ndef main():\n" + body(60, "    "))
        write("analysis/b.py", "def g(x):\n    from .plots import p\n    return x\n")
        write("analysis/plots/q.py", "from analysis.plots import p\n")
        lines = "".join(f"    a += {k};\n" for k in range(59))
        write("analysis/player/long.js",
              "(function () {\n  var f = function (a) {\n" + lines + "  };\n"
              + "  var g = (a, b) => {\n" + lines + "  };\n"
              + "  var o = { method(a) {\n" + lines + "  } };\n"
              + "  if (f) {\n" + lines + "  }\n"
              + "})();\n")
        found = check(root)
        # (the 61-line if block is no function, so it is not among them)
        expect = ["analysis/long.py:2: 61 lines, over 60: def method",
                  "tests/tool:2: 61 lines, over 60: def main",
                  "analysis/player/long.js:1: 246 lines, over 60: function (anonymous)",
                  "analysis/player/long.js:2: 61 lines, over 60: function f",
                  "analysis/player/long.js:63: 61 lines, over 60: function g",
                  "analysis/player/long.js:124: 61 lines, over 60: function method",
                  "analysis/a.py: import cycle analysis.a -> analysis.b -> analysis.plots -> "
                  "analysis.plots.p -> analysis.a",
                  "analysis/plots/p.py: import cycle analysis.plots.p -> analysis.plots.q -> "
                  "analysis.plots.p"]
        for e in expect:
            assert e in found, (e, found)
        assert len(found) == len(expect), found
    print("check_script_layout self-test: every rule fails on a tree that breaks it")


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
        print(f"check_script_layout: {len(found)} violation(s)")
        return 1
    print(f"check_script_layout: no Python or JavaScript function over {MAX_LINES} lines, "
          f"no import cycle in {PACKAGE}/")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
