#!/usr/bin/env python3
"""Every relative link of README.md and docs/*.md points to a file that exists, and every
#anchor to a heading of that file (GitHub's heading ids).

Usage: check_links.py SOURCE_DIR      check the repository's manual; exit 1 naming each bad link
       check_links.py --self-test     a bad file, a bad anchor and a good link on a made-up tree
"""
import pathlib
import re
import sys
import tempfile

LINK = re.compile(r"!?\[(?:[^\]\\]|\\.)*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")


def pages(root):
    """The manual's Markdown files: README.md and docs/*.md."""
    return [root / "README.md"] + sorted((root / "docs").glob("*.md"))


def prose_lines(text):
    """The lines outside fenced code blocks, with inline code removed, as (number, line)."""
    fence = False
    for n, line in enumerate(text.splitlines(), 1):
        if line.lstrip().startswith("```"):
            fence = not fence
            continue
        if not fence:
            yield n, re.sub(r"`[^`]*`", "", line)


def slug(heading):
    """GitHub's id for a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r"<[^>]+>", "", heading).strip().lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(path):
    """Every heading id of a Markdown file, with GitHub's -1, -2 suffixes for repeats."""
    seen, ids = {}, set()
    fence = False
    for line in path.read_text().splitlines():
        if line.lstrip().startswith("```"):
            fence = not fence
            continue
        m = re.match(r"#{1,6}\s+(.*?)\s*#*\s*$", line)
        if fence or not m:
            continue
        base = slug(m.group(1))
        k = seen.get(base, 0)
        seen[base] = k + 1
        ids.add(base if k == 0 else "%s-%d" % (base, k))
    return ids


def bad_links(root):
    """(file, line, target, reason) for every relative link that does not resolve."""
    problems = []
    for page in pages(root):
        for n, line in prose_lines(page.read_text()):
            for target in LINK.findall(line):
                if re.match(r"[a-z]+:", target):  # http:, https:, mailto:
                    continue
                path_part, _, anchor = target.partition("#")
                dest = (page.parent / path_part).resolve() if path_part else page
                if not dest.exists():
                    problems.append((page, n, target, "no such file"))
                elif anchor and dest.suffix == ".md" and anchor not in anchors(dest):
                    problems.append((page, n, target, "no heading with this id"))
    return problems


def self_test():
    with tempfile.TemporaryDirectory() as tmp:
        root = pathlib.Path(tmp)
        (root / "docs").mkdir()
        (root / "README.md").write_text(
            "# Top\n\n[good](docs/a.md#a-b-c) [bad file](docs/none.md) [bad anchor](#nowhere)\n"
            "```sh\n[in code](not/checked.md)\n```\n")
        (root / "docs" / "a.md").write_text("# A: b `c`\n\n[back](../README.md#top)\n")
        found = {(p.name, t) for p, _, t, _ in bad_links(root)}
    want = {("README.md", "docs/none.md"), ("README.md", "#nowhere")}
    if found != want:
        print("self-test failed: found %s, expected %s" % (sorted(found), sorted(want)))
        return 1
    print("self-test passed: a missing file and a missing anchor are caught, good links pass")
    return 0


def main(argv):
    if argv[1:] == ["--self-test"]:
        return self_test()
    if len(argv) != 2:
        print(__doc__)
        return 2
    root = pathlib.Path(argv[1]).resolve()
    problems = bad_links(root)
    for page, n, target, reason in problems:
        print("%s:%d: %s: %s" % (page.relative_to(root), n, target, reason))
    count = len(pages(root))
    print("%d bad links in %d pages" % (len(problems), count) if problems
          else "every relative link of %d pages resolves" % count)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
