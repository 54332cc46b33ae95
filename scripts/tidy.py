#!/usr/bin/env python3
"""Tidy checks for the documents (issue 51, part 6): every reference resolves.

Run from anywhere: ``python3 scripts/tidy.py`` checks the repository this file is in;
``python3 scripts/tidy.py --root DIR`` checks another checkout; ``--self-test`` runs the checks
on a small synthetic tree in a temporary folder and asserts that each kind of problem is found
(the negative control) and that a clean tree passes, printing what it found; an ordinary run
does the same quietly before checking the repository. Exit status 0: no problem; 1: problems,
each printed as ``file:line: message``. Standard library only.

Only files that git tracks are read (``git ls-files``), as they are in the working tree.

(a) Section references. Every ``§N`` or ``§N.M`` (also ``§ N``; ``N`` and ``M`` digits; a range
``§N.M–P.Q`` or ``§N–P`` checks both ends) in a ``*.rs``, ``*.py``, ``*.pyi``, ``*.md`` or
``*.toml`` file must be listed in the table of contents of ``docs/maths.md``: a line of the form
``- [§N.M title](path#anchor)``, whose link is itself checked by (b). The rule that tells a
reference to another document apart looks at the text just before the ``§`` on the same line,
after skipping spaces, opening brackets, quotes and backticks:

* the last token names a Markdown or TeX file (``one-navigator.md §3.2``, ``(`README.md` §2)``,
  ``paper.tex §4``): if its basename is ``maths.md`` the reference is to the maths (checked as
  above); if a tracked file has that basename and is Markdown, ``N.M`` must be the number of one
  of its headings (``## 3.2 Title`` or ``## 3.2. Title``); otherwise (a file outside the
  repository) the reference is not checked;
* the last word is one of ``paper``, ``paper's``, ``notes``, ``note``, ``notes'``,
  ``RFC``, ``REP``, ``ISO``, ``IEEE`` (case-insensitive): another document's section, not
  checked.

Everything else, including ``maths §12.7``, ``docs/maths.md §9`` and a bare ``§13.7``, is a
reference to ``docs/maths.md``. Nothing else is exempt: a new foreign document needs its word
added here, on purpose. This script itself is not scanned for (a): its examples and the
problems its self-test plants are not references.

(b) Relative Markdown links. In every tracked ``*.md`` file, each inline link or image
``[text](target)`` and each reference definition ``[label]: target`` whose target has no URL
scheme (``http:``, ``https:``, ``mailto:`` …) must name an existing file or folder, relative to
the linking file (``/path`` from the repository root). A target ``file.md#anchor`` or
``#anchor`` must also name an anchor of that Markdown file: a heading's GitHub slug (the text as
rendered, lower-cased, every character but letters, digits, ``_``, ``-`` and spaces removed,
spaces turned into ``-``; repeated slugs get ``-1``, ``-2`` …) or an explicit
``<a id="…">`` / ``<a name="…">``. Code blocks and inline code are skipped.

(c) The codemap's word budget. In ``docs/ARCHITECTURE.md``, each ``###`` section under the
``## Codemap`` heading holds at most 120 words (whitespace-separated tokens, heading excluded).
"""

import argparse
import os
import re
import subprocess
import sys
import tempfile
import unicodedata
import urllib.parse

SECTION_SUFFIXES = (".rs", ".py", ".pyi", ".md", ".toml")
TOC_FILE = "docs/maths.md"
ARCHITECTURE = "docs/ARCHITECTURE.md"
CODEMAP_WORDS = 120
SELF = "scripts/tidy.py"
FOREIGN_WORDS = {"paper", "paper's", "notes", "note", "notes'", "rfc", "rep", "iso", "ieee"}

SECTION_REF = re.compile(r"§\s?(\d+(?:\.\d+)?)(?:\s?[–-]\s?(\d+(?:\.\d+)?))?")
TOC_ENTRY = re.compile(r"^\s*[-*] \[§(\d+(?:\.\d+)?)[ \]]")
FILE_TOKEN = re.compile(r"([\w./-]+\.(?:md|tex))$")
INLINE_LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]*)>?(?:\s+\"[^\"]*\")?\s*\)")
REF_DEF = re.compile(r"^\s{0,3}\[[^\]]+\]:\s*<?(\S+?)>?(?:\s+\"[^\"]*\")?\s*$")
SCHEME = re.compile(r"^[a-zA-Z][a-zA-Z0-9+.-]*:")
EXPLICIT_ANCHOR = re.compile(r"<a\s+(?:id|name)=\"([^\"]+)\"", re.I)
HEADING = re.compile(r"^ {0,3}(#{1,6})\s+(.*?)\s*#*\s*$")
FENCE = re.compile(r"^ {0,3}(```|~~~)")


def tracked(root):
    out = subprocess.run(["git", "ls-files", "-z"], cwd=root, capture_output=True, check=True)
    return [p for p in out.stdout.decode().split("\0") if p and os.path.isfile(os.path.join(root, p))]


def read(root, path):
    with open(os.path.join(root, path), encoding="utf-8", errors="replace") as f:
        return f.read().split("\n")


def prose_lines(lines):
    """(number, line) of the lines outside fenced code blocks, inline code blanked out."""
    fenced = False
    for i, line in enumerate(lines, 1):
        if FENCE.match(line):
            fenced = not fenced
            continue
        if not fenced:
            yield i, re.sub(r"(`+)(.+?)\1", lambda m: " " * len(m.group(0)), line)


def github_slug(text):
    text = re.sub(r"<[^>]*>", "", text)                      # HTML tags
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", text)    # links: their text
    text = text.replace("`", "").replace("*", "")
    text = text.strip().lower()
    kept = []
    for ch in text:
        cat = unicodedata.category(ch)
        if ch in "-_ " or cat[0] in "LN" or cat == "Mn" or cat == "Mc":
            kept.append(ch)
    return "".join(kept).replace(" ", "-")


def anchors(lines):
    found, seen = set(), {}
    fenced = False
    for line in lines:
        if FENCE.match(line):
            fenced = not fenced
            continue
        if fenced:
            continue
        for a in EXPLICIT_ANCHOR.findall(line):
            found.add(a)
        m = HEADING.match(line)
        if m:
            slug = github_slug(m.group(2))
            n = seen.get(slug, 0)
            found.add(slug if n == 0 else f"{slug}-{n}")
            seen[slug] = n + 1
    return found


def toc_sections(root):
    path = os.path.join(root, TOC_FILE)
    if not os.path.isfile(path):
        return set()
    return {m.group(1) for line in read(root, TOC_FILE) for m in [TOC_ENTRY.match(line)] if m}


def heading_numbers(lines):
    nums = set()
    for _, line in prose_lines(lines):
        m = HEADING.match(line)
        if m:
            n = re.match(r"(?:§\s?)?(\d+(?:\.\d+)*)\.?(?:\s|$)", m.group(2))
            if n:
                nums.add(n.group(1))
    return nums


def foreign_target(before):
    """What the text before a `§` names: None (the maths), a file name, or 'foreign'."""
    before = before.rstrip(" \t([{\"'`“‘*_")
    m = FILE_TOKEN.search(before)
    if m:
        return m.group(1)
    words = before.split()
    if words and words[-1].lower().strip(",;:") in FOREIGN_WORDS:
        return "foreign"
    return None


def check_sections(root, files, problems):
    sections = toc_sections(root)
    if not sections:
        problems.append(f"{TOC_FILE}:1: no table of contents (lines `- [§N title](file#anchor)`)")
    by_name = {}
    for p in files:
        by_name.setdefault(os.path.basename(p), []).append(p)
    numbered = {}
    for path in files:
        if not path.endswith(SECTION_SUFFIXES) or path == SELF:
            continue
        lines = read(root, path)
        # Markdown: skip code blocks; code files: every line (comments and strings alike).
        source = prose_lines(lines) if path.endswith(".md") else enumerate(lines, 1)
        for i, line in source:
            for m in SECTION_REF.finditer(line):
                target = foreign_target(line[: m.start()])
                ends = [e for e in m.groups() if e]
                if target is None or os.path.basename(target) == "maths.md":
                    for e in ends:
                        if e not in sections:
                            problems.append(
                                f"{path}:{i}: §{e} is not in {TOC_FILE}'s table of contents")
                elif target == "foreign":
                    continue
                else:
                    owners = [p for p in by_name.get(os.path.basename(target), []) if p.endswith(".md")]
                    if not owners:
                        continue  # a document outside the repository
                    for owner in owners:
                        if owner not in numbered:
                            numbered[owner] = heading_numbers(read(root, owner))
                    for e in ends:
                        if not any(e in numbered[o] for o in owners):
                            problems.append(f"{path}:{i}: §{e} is not a numbered heading of {owners[0]}")


def check_links(root, files, problems):
    cache = {}
    for path in files:
        if not path.endswith(".md"):
            continue
        lines = read(root, path)
        for i, line in prose_lines(lines):
            targets = [m.group(1) for m in INLINE_LINK.finditer(line)]
            d = REF_DEF.match(line)
            if d:
                targets.append(d.group(1))
            for t in targets:
                if not t or SCHEME.match(t):
                    continue
                file_part, _, anchor = t.partition("#")
                file_part = urllib.parse.unquote(file_part)
                if file_part:
                    base = root if file_part.startswith("/") else os.path.join(root, os.path.dirname(path))
                    dest = os.path.normpath(os.path.join(base, file_part.lstrip("/")))
                    rel = os.path.relpath(dest, root)
                    if rel.startswith(".."):
                        problems.append(f"{path}:{i}: link `{t}` leaves the repository")
                        continue
                    if not os.path.exists(dest):
                        problems.append(f"{path}:{i}: link `{t}`: no file {rel}")
                        continue
                else:
                    dest, rel = os.path.join(root, path), path
                if anchor and rel.endswith(".md") and os.path.isfile(dest):
                    if rel not in cache:
                        cache[rel] = anchors(read(root, rel))
                    if urllib.parse.unquote(anchor) not in cache[rel]:
                        problems.append(f"{path}:{i}: link `{t}`: no heading or anchor #{anchor} in {rel}")


def check_codemap(root, problems):
    path = os.path.join(root, ARCHITECTURE)
    if not os.path.isfile(path):
        return
    lines = read(root, ARCHITECTURE)
    in_map, section, start, words = False, None, 0, 0

    def close():
        if section is not None and words > CODEMAP_WORDS:
            problems.append(f"{ARCHITECTURE}:{start}: codemap section `{section}` has {words} words "
                            f"(at most {CODEMAP_WORDS})")

    fenced = False
    found_map = False
    for i, line in enumerate(lines, 1):
        if FENCE.match(line):
            fenced = not fenced
        m = None if fenced else HEADING.match(line)
        if m and len(m.group(1)) <= 2:
            close()
            section = None
            in_map = m.group(2).strip().lower() == "codemap"
            found_map = found_map or in_map
            continue
        if not in_map:
            continue
        if m and len(m.group(1)) == 3:
            close()
            section, start, words = m.group(2).strip(), i, 0
            continue
        if section is not None:
            words += len(line.split())
    close()
    if not found_map:
        problems.append(f"{ARCHITECTURE}:1: no `## Codemap` section")


def run(root):
    files = tracked(root)
    problems = []
    check_sections(root, files, problems)
    check_links(root, files, problems)
    check_codemap(root, problems)
    return problems


def self_test(quiet=False):
    """Negative controls on a synthetic tree: each planted problem is found, and nothing else."""
    tree = {
        "docs/maths.md": "# Maths\n\n- [§1 One](maths/01.md#s1)\n  - [§1.2 Two](maths/01.md#s1-2)\n",
        "docs/maths/01.md": '<a id="s1"></a>\n\n# 1. One\n\n<a id="s1-2"></a>\n\n## 1.2 Two\n\n## Two\n\n## Two\n',
        "docs/design.md": "# Design\n\n## 3.2 Glossary\n",
        "docs/ARCHITECTURE.md": "# A\n\n## Codemap\n\n### short\n\n" + "word " * 120
        + "\n\n### long\n\n" + "word " * 121 + "\n\n## Glossary\n\n" + "word " * 500 + "\n",
        "docs/links.md": "\n".join([
            "[ok](maths/01.md#s1-2) [ok](maths/01.md#two-1) [ok](../README.md) [ok](#links)",
            "[ok](https://example.org/x.md#nowhere) `[skipped](nowhere.md)`",
            "```", "[skipped](nowhere.md) §99", "```",
            "[bad](maths/02.md)",                    # line 6: no such file
            "[bad](maths/01.md#three)",              # line 7: no such anchor
            "[ref]: maths/01.md#s9",                 # line 8: no such anchor
            "# Links", ""]),
        "README.md": "See docs/maths.md §1 and §1.2, `§1.2`.\n",
        "src/lib.rs": "\n".join([
            "// docs/maths.md §1.2, maths §1; the paper's §7; notes §4 (others' sections)",
            "// one-navigator.md §3.2 lies outside the repository; design.md §3.2 resolves",
            "// §1.3 does not exist",               # line 3
            "// design.md §3.3 does not exist",     # line 4
            "// §1–1.2 is a range; §1.2–1.5 is not", # line 5: 1.5
            ""]),
    }
    expected = {
        ("docs/links.md", 6), ("docs/links.md", 7), ("docs/links.md", 8),
        ("src/lib.rs", 3), ("src/lib.rs", 4), ("src/lib.rs", 5),
        ("docs/ARCHITECTURE.md", 9),
    }
    with tempfile.TemporaryDirectory() as tmp:
        for path, text in tree.items():
            os.makedirs(os.path.join(tmp, os.path.dirname(path)), exist_ok=True)
            with open(os.path.join(tmp, path), "w", encoding="utf-8") as f:
                f.write(text)
        subprocess.run(["git", "init", "-q"], cwd=tmp, check=True)
        subprocess.run(["git", "add", "."], cwd=tmp, check=True)
        problems = run(tmp)
        got = {(p.split(":")[0], int(p.split(":")[1])) for p in problems}
        ok = got == expected
        if not quiet:
            for p in problems:
                print(f"  self-test found: {p}")
        if not ok:
            print(f"tidy self-test FAILED: missing {sorted(expected - got)}, unexpected {sorted(got - expected)}")
            return 1
        # and the clean tree: remove the planted problems, expect none
        with open(os.path.join(tmp, "docs/links.md"), "w", encoding="utf-8") as f:
            f.write("[ok](maths/01.md#s1-2)\n")
        with open(os.path.join(tmp, "src/lib.rs"), "w", encoding="utf-8") as f:
            f.write("// §1.2 and the paper's §9\n")
        with open(os.path.join(tmp, "docs/ARCHITECTURE.md"), "w", encoding="utf-8") as f:
            f.write("# A\n\n## Codemap\n\n### short\n\nfew words\n")
        left = run(tmp)
        if left:
            print("tidy self-test FAILED on the clean tree:", *left, sep="\n  ")
            return 1
    if not quiet:
        print(f"tidy self-test: {len(expected)} planted problems found, clean tree passes")
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--root", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    ap.add_argument("--self-test", action="store_true", help="run the negative controls and exit")
    args = ap.parse_args()
    if args.self_test:
        return self_test()
    if self_test(quiet=True):  # the negative control runs every time: a check that cannot fail is no check
        return 1
    problems = run(args.root)
    for p in problems:
        print(p)
    if problems:
        print(f"tidy: {len(problems)} problem(s)", file=sys.stderr)
        return 1
    print("tidy: § references, Markdown links and the codemap's word budget all resolve")
    return 0


if __name__ == "__main__":
    sys.exit(main())
