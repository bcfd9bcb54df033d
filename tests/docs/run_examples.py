#!/usr/bin/env python3
"""Runs the console examples of README.md and docs/*.md and compares their first output lines.

An example is run when the line before its ```sh block is `<!-- runnable -->` (quick) or
`<!-- runnable slow -->`. In the block, a line starting with `$ ` is a command (a trailing
backslash continues it on the next line) and the lines after it, up to the next command, are
what it printed; the first of them must equal the first line the command prints now (its
stdout, or its stderr when stdout is empty), with every number and every path (a word holding
a `/`) left out of the comparison. A shown `...` compares nothing; a command shown with no
output must print nothing.

The blocks of one page run in page order with bash in one folder of their own, so a block may
use what an earlier block of its page wrote (the README's tour reports the run it made). In
that folder `scenarios` is a link to the repository's scenarios/, so `scenarios/NAME.toml`
and `out/...` work as written and nothing is written into the repository; the folder is
deleted afterwards, also when the runner is interrupted.

Usage: run_examples.py --clothbench PATH --source DIR [--work DIR] [--slow | --all] [--list]
  --work DIR  where the blocks' folders go (created and deleted; default: a temporary folder)
  --slow      run the slow blocks only; --all runs both kinds; default: the quick blocks only
  --list      print the blocks found and run nothing
"""
import argparse
import os
import pathlib
import re
import shutil
import signal
import subprocess
import sys
import tempfile

MARK = re.compile(r"^<!-- runnable( slow)? -->\s*$")
NUMBER = re.compile(r"[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?")


class Block:
    """One runnable example: where it is, whether it is slow, its commands and shown lines."""

    def __init__(self, page, line, slow):
        self.page, self.line, self.slow = page, line, slow
        self.steps = []  # (command, first shown output line or None)


def parse_block(lines, page, start, slow):
    """The block whose ```sh line is lines[start]; returns it and the index after it."""
    block = Block(page, start + 1, slow)
    i = start + 1
    command, shown = None, []
    while i < len(lines) and not lines[i].startswith("```"):
        line = lines[i]
        if line.startswith("$ "):
            if command is not None:
                block.steps.append((command, shown[0] if shown else None))
            command, shown = line[2:], []
            while command.endswith("\\") and i + 1 < len(lines):
                i += 1
                command = command[:-1] + " " + lines[i].strip()
        elif command is not None:
            shown.append(line)
        i += 1
    if command is not None:
        block.steps.append((command, shown[0] if shown else None))
    return block, i + 1


def find_blocks(source):
    """Every marked block of README.md and docs/*.md, in page order."""
    blocks = []
    for page in [source / "README.md"] + sorted((source / "docs").glob("*.md")):
        lines = page.read_text().splitlines()
        i = 0
        while i < len(lines):
            m = MARK.match(lines[i])
            if m and i + 1 < len(lines):
                if not lines[i + 1].startswith("```sh"):
                    raise SystemExit("%s:%d: <!-- runnable --> must stand right before a ```sh "
                                     "block" % (page, i + 1))
                block, i = parse_block(lines, page.relative_to(source), i + 1, bool(m.group(1)))
                if not block.steps:
                    raise SystemExit("%s:%d: a runnable block without a `$ ` command"
                                     % (page, i + 1))
                blocks.append(block)
            else:
                i += 1
    return blocks


def normalise(line):
    """The line with paths and numbers replaced and runs of spaces made one."""
    words = ["<path>" if "/" in w else NUMBER.sub("<n>", w) for w in line.split()]
    return " ".join(words)


def run_block(block, folder, env):
    """Runs a block's commands in its page's folder; returns a list of mismatch messages."""
    problems = []
    for command, shown in block.steps:
        done = subprocess.run(["bash", "-c", command], cwd=folder, env=env,
                              capture_output=True, text=True,
                              timeout=3600 if block.slow else 900)
        out = done.stdout.splitlines() or done.stderr.splitlines()
        first = out[0] if out else None
        if shown is None or shown.strip() == "...":
            if shown is None and first is not None:
                problems.append("`%s` printed %r where the block shows no output"
                                % (command, first))
            continue
        if first is None or normalise(first) != normalise(shown):
            problems.append("`%s`\n    shown: %s\n    now:   %s%s" % (
                command, shown, first,
                "\n    stderr: " + done.stderr.strip()[-400:] if done.stderr.strip() else ""))
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--clothbench")
    parser.add_argument("--source", required=True)
    parser.add_argument("--work")
    parser.add_argument("--slow", action="store_true")
    parser.add_argument("--all", action="store_true")
    parser.add_argument("--list", action="store_true")
    args = parser.parse_args()
    source = pathlib.Path(args.source).resolve()
    blocks = find_blocks(source)
    if not blocks:
        print("no <!-- runnable --> block in README.md or docs/*.md")
        return 1
    chosen = [b for b in blocks if args.all or b.slow == args.slow]
    if args.list:
        for b in blocks:
            print("%s:%d %s %s" % (b.page, b.line, "slow " if b.slow else "quick",
                                   " && ".join(c for c, _ in b.steps)))
        return 0
    if not args.clothbench:
        parser.error("--clothbench is needed to run the blocks")
    env = dict(os.environ)
    env["PATH"] = str(pathlib.Path(args.clothbench).resolve().parent) + os.pathsep + env["PATH"]
    made_work = args.work is None
    work = pathlib.Path(args.work or tempfile.mkdtemp(prefix="clothbench-docs-"))
    if not made_work:
        shutil.rmtree(work, ignore_errors=True)
        work.mkdir(parents=True)
    # an interruption (ctest's timeout, Ctrl-C) still removes the folders
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    failed = 0
    folders = {}
    try:
        for b in chosen:
            if b.page not in folders:
                folders[b.page] = pathlib.Path(tempfile.mkdtemp(prefix="page-", dir=work))
                for shared in ("scenarios", "examples"):
                    (folders[b.page] / shared).symlink_to(source / shared)
            problems = run_block(b, folders[b.page], env)
            print("%s %s:%d (%d commands)" % ("FAIL" if problems else "ok  ", b.page, b.line,
                                              len(b.steps)))
            for p in problems:
                print("  " + p)
            failed += bool(problems)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print("%d of %d %s examples ran as shown" % (len(chosen) - failed, len(chosen),
                                                 "slow" if args.slow else
                                                 "" if args.all else "quick"))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
