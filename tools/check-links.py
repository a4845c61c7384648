#!/usr/bin/python3
"""Checks the relative links and anchors of the repository's Markdown files.

    tools/check-links.py [--root DIR]     every tracked *.md file (git ls-files) of DIR
    tools/check-links.py --self-test      the checker on a folder of known good and bad links

For every link `[text](target)`, image `![alt](target)` and reference definition
`[label]: target` outside code, the target must be a file or folder tracked in the
repository (a path leaving the repository, an absolute path or an untracked file is an
error), and an anchor (`file.md#anchor`, `#anchor`) must name a heading of that Markdown
file or an explicit `<a id="...">` / `<a name="...">` in it. Anchors of headings follow
GitHub's rule: the heading's text, lowercased, without every character that is not a
letter, mark, digit, connector (`_`), hyphen or space, each space turned into a hyphen;
a repeated slug gets -1, -2, ... in order. Links to http(s) and mailto are not checked;
links into other files (`source.cpp#L10`) may only carry GitHub's line anchors.

Prints one line per broken link, `file:line: target: why`, and exits with status 1 if
there is any (0 otherwise). Standard library only.
"""
import argparse
import html
import os
import re
import subprocess
import sys
import tempfile
import unicodedata
from pathlib import Path, PurePosixPath
from urllib.parse import unquote

# ---------------------------------------------------------------------------- masking


def mask(text):
    """`text` with everything that is not Markdown prose (fenced code blocks, inline code
    spans, HTML comments) replaced by spaces, line breaks kept, so that offsets and line
    numbers stay those of the file. Returns (masked text, fenced-line flags)."""
    lines = text.split("\n")
    fenced = [False] * len(lines)
    fence = None
    for i, line in enumerate(lines):
        opening = re.match(r"^ {0,3}(`{3,}|~{3,})", line)
        if fence is None:
            if opening and not (opening.group(1)[0] == "`" and "`" in line[opening.end():]):
                fence = opening.group(1)
                fenced[i] = True
        else:
            fenced[i] = True
            closing = re.match(r"^ {0,3}(`{3,}|~{3,})\s*$", line)
            if closing and closing.group(1)[0] == fence[0] and len(closing.group(1)) >= len(fence):
                fence = None
    masked = "\n".join(" " * len(line) if fenced[i] else line for i, line in enumerate(lines))
    blank = lambda m: re.sub(r"[^\n]", " ", m.group(0))  # noqa: E731
    masked = re.sub(r"<!--.*?-->", blank, masked, flags=re.S)
    masked = mask_code_spans(masked, blank)
    return masked, fenced


def mask_code_spans(text, blank):
    """Inline code: a run of backticks up to the next run of the same length (CommonMark);
    a backslash before a backtick outside code escapes it."""
    out, i = [], 0
    while i < len(text):
        if text[i] == "\\" and i + 1 < len(text):
            out.append(text[i:i + 2])
            i += 2
            continue
        if text[i] != "`":
            out.append(text[i])
            i += 1
            continue
        run = re.match(r"`+", text[i:]).group(0)
        end = re.compile(r"(?<!`)" + run + r"(?!`)").search(text, i + len(run))
        # a code span does not cross a blank line (the paragraph ends there)
        if end is None or "\n\n" in text[i:end.start()]:
            out.append(run)
            i += len(run)
            continue
        out.append(blank(re.match(r"(?s).*", text[i:end.end()])))
        i = end.end()
    return "".join(out)


# ---------------------------------------------------------------------------- anchors


def heading_text(raw):
    """The text a heading renders, as far as the slug is concerned: code spans keep
    their content, links and images their text (images: nothing), HTML tags and
    emphasis markers go, backslash escapes and entities become their characters."""
    parts = re.split(r"(`+)(.*?)\1", raw)
    # re.split with two groups: [text, run, code, text, run, code, ..., text]
    result = []
    for k in range(0, len(parts), 3):
        prose = parts[k]
        prose = re.sub(r"!\[[^\]]*\]\([^)]*\)", "", prose)          # images
        prose = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", prose)      # links
        prose = re.sub(r"\[([^\]]*)\]\[[^\]]*\]", r"\1", prose)     # reference links
        prose = re.sub(r"<[^>]*>", "", prose)                       # HTML tags
        # emphasis with underscores: a run at the start or the end of a word (snake_case
        # inside a word is literal); an escaped underscore is literal
        prose = re.sub(r"\\_", "\x00", prose)
        prose = re.sub(r"(?<![\w\\])_+(?=\S)|(?<=\S)_+(?!\w)", "", prose)
        prose = re.sub(r"\\([!-/:-@\[-`{-~])", r"\1", prose).replace("\x00", "_")
        result.append(html.unescape(prose))
        if k + 2 < len(parts):
            result.append(parts[k + 2])
    return "".join(result)


def slug(text):
    """GitHub's anchor of a heading whose rendered text is `text` (before de-duplication)."""
    kept = []
    for c in text.strip().lower():
        category = unicodedata.category(c)
        if c in " -" or category[0] in "LMN" or category == "Pc":
            kept.append(c)
    return "".join(kept).replace(" ", "-")


def anchors_of(text):
    """Every anchor a Markdown file defines: the headings' slugs (duplicates numbered)
    and the explicit <a id=...> / <a name=...>."""
    masked, fenced = mask(text)
    lines = text.split("\n")
    masked_lines = masked.split("\n")
    headings = []
    for i, line in enumerate(lines):
        if fenced[i]:
            continue
        atx = re.match(r"^ {0,3}#{1,6}(?:[ \t]+(.*?))?(?:[ \t]+#+)?[ \t]*$", line)
        if atx:
            headings.append(atx.group(1) or "")
            continue
        setext = re.match(r"^ {0,3}(=+|-+)[ \t]*$", line)
        if setext and i > 0 and not fenced[i - 1] and is_paragraph_line(lines[i - 1]):
            # a setext heading of one line (the usual case in hand-written Markdown)
            if i < 2 or not lines[i - 2].strip() or re.match(r"^ {0,3}#", lines[i - 2]):
                headings.append(lines[i - 1].strip())
    anchors, seen = set(), {}
    for raw in headings:
        base = slug(heading_text(raw))
        name, n = base, seen.get(base, 0)
        while name in anchors:
            n += 1
            name = f"{base}-{n}"
        seen[base] = n
        anchors.add(name)
    for m in re.finditer(r"<a\s[^>]*?\b(?:id|name)\s*=\s*(\"[^\"]*\"|'[^']*'|[^\s>]+)",
                         "\n".join(masked_lines), flags=re.I):
        anchors.add(m.group(1).strip("\"'"))
    return anchors


def is_paragraph_line(line):
    return bool(line.strip()) and not re.match(
        r"^ {0,3}([-*+] |\d+[.)] |>|#|\||```|~~~)|^ {4}", line)


# ---------------------------------------------------------------------------- links

# [text](target) and ![alt](target): link text with one level of nested brackets, a
# target in <...> or one without spaces (one level of nested parentheses), an optional
# title.
INLINE = re.compile(
    r"(!?)\[((?:[^\[\]\\]|\\.|\[(?:[^\[\]\\]|\\.)*\])*)\]"
    r"\(\s*(<[^<>\n]*>|(?:[^\s()\\]|\\.|\((?:[^\s()\\]|\\.)*\))*)"
    r"(?:\s+(?:\"[^\"]*\"|'[^']*'|\([^)]*\)))?\s*\)")
DEFINITION = re.compile(r"^ {0,3}\[((?:[^\]\\]|\\.)+)\]:[ \t]*(<[^<>\n]*>|\S+)", re.M)
LINE_ANCHOR = re.compile(r"^L\d+(?:C\d+)?(?:-L\d+(?:C\d+)?)?$")


def links_of(text):
    """(line, target) of every link, image and reference definition outside code."""
    masked, _ = mask(text)
    found = []
    for m in INLINE.finditer(masked):
        found.append((masked.count("\n", 0, m.start(3)) + 1, m.group(3)))
    for m in DEFINITION.finditer(masked):
        found.append((masked.count("\n", 0, m.start(2)) + 1, m.group(2)))
    return sorted(found)


class Repository:
    """The tracked files of a repository, and the anchors of its Markdown files."""

    def __init__(self, root, files):
        self.root = Path(root).resolve()
        self.files = set(files)
        self.folders = {str(PurePosixPath(f).parent) for f in files}
        for f in list(self.folders):
            while f not in (".", ""):
                f = str(PurePosixPath(f).parent)
                self.folders.add(f)
        self.folders.add(".")
        self._anchors = {}

    def anchors(self, name):
        if name not in self._anchors:
            self._anchors[name] = anchors_of((self.root / name).read_text(encoding="utf-8"))
        return self._anchors[name]


def problem(repo, source, target):
    """Why `target`, a link in the tracked Markdown file `source`, is broken; None if it
    is not (or is not ours to check)."""
    if target.startswith("<") and target.endswith(">"):
        target = target[1:-1]
    target = re.sub(r"\\(.)", r"\1", target)
    scheme = re.match(r"^([A-Za-z][A-Za-z0-9+.-]*):", target)
    if scheme:
        if scheme.group(1).lower() in ("http", "https", "mailto"):
            return None
        return f"a {scheme.group(1)}: link (only relative links, http(s) and mailto are allowed)"
    if target.startswith("//"):
        return "a protocol-relative URL (give http(s) or a relative path)"
    path, _, anchor = target.partition("#")
    path = unquote(path.split("?", 1)[0])
    anchor = unquote(anchor)
    if not path and not anchor:
        return "an empty link"
    if path.startswith("/"):
        return "an absolute path (links must be relative to the file)"
    if path:
        joined = os.path.normpath(os.path.join(os.path.dirname(source), path))
        resolved = Path(os.path.realpath(repo.root / joined))
        if resolved != repo.root and repo.root not in resolved.parents:
            return "points outside the repository"
        name = resolved.relative_to(repo.root).as_posix() if resolved != repo.root else "."
        if name not in repo.files and name not in repo.folders:
            if (repo.root / name).exists():
                return f"{name} is not tracked by git"
            return f"no file {name}"
    else:
        name = source
    if not anchor:
        return None
    if name in repo.folders:
        return f"an anchor on the folder {name}"
    if not name.endswith(".md"):
        if LINE_ANCHOR.match(anchor):
            return None
        return f"anchor #{anchor} in {name}, which is not Markdown (only #L<line> anchors)"
    if anchor not in repo.anchors(name):
        return f"no heading or anchor #{anchor} in {name}"
    return None


def check(root, files):
    """The broken links of the Markdown files among `files` (tracked paths, relative to
    `root`), as 'file:line: target: why' lines."""
    repo = Repository(root, files)
    report = []
    for source in sorted(f for f in files if f.endswith(".md")):
        text = (repo.root / source).read_text(encoding="utf-8")
        for line, target in links_of(text):
            why = problem(repo, source, target)
            if why:
                report.append(f"{source}:{line}: {target}: {why}")
    return report


def tracked_files(root):
    done = subprocess.run(["git", "-C", str(root), "ls-files", "-z"], capture_output=True)
    if done.returncode != 0:
        sys.exit(f"check-links: {root}: cannot list the tracked files (git ls-files: "
                 f"{done.stderr.decode(errors='replace').strip()})")
    return [f for f in done.stdout.decode("utf-8").split("\0") if f]


# ---------------------------------------------------------------------------- self-test

SELF_TEST_FILES = {
    "README.md": """\
# Top: the `fem-solve` page

[good file](docs/guide.md) and [good anchor](docs/guide.md#3-the-fe-phase) and
[a folder](docs/) and ![an image](docs/figure.png) and [local](#top-the-fem-solve-page)
[wrapped
link text](docs/guide.md#performance-toolsbenchmarkstransfer) [web](https://example.org/x.md)
[mail](mailto:someone@example.org) [title](docs/guide.md "a title") [angle](<docs/guide.md>)
[line of a source file](src/code.cpp#L10-L12) [encoded](docs/guide.md#%CF%83yy-and-%CF%81)
[duplicate one](docs/guide.md#notes-1) [explicit id](docs/guide.md#kept) [name](docs/guide.md#old-name)
[nested [brackets]](docs/guide.md#emphasis-and-snake_case) [up one](src/../docs/guide.md)
[ref]: docs/guide.md#notes

`[in code](missing.md)` and

```sh
[in a fence](missing.md)
# not a heading
```

[missing file](docs/nothing.md)
[missing anchor](docs/guide.md#performance-benchmarkstransfer)
[outside](../outside/notes.md)
[absolute](/docs/guide.md)
[untracked](docs/untracked.md)
[no third duplicate](docs/guide.md#notes-2)
[fenced heading](#not-a-heading)
[source anchor](src/code.cpp#main)
[ftp](ftp://example.org/f)
[bad ref]: docs/guide.md#nowhere
""",
    "docs/guide.md": """\
# Guide

## 3. The FE phase

## Performance (tools/benchmarks/transfer)

## σyy and ρ

## Notes

## Notes

### _Emphasis_ and snake_case

<a id="kept"></a><a name="old-name"></a>

[up](../README.md#top-the-fem-solve-page) [self](#guide)
[bad self](#guides)
""",
    "docs/figure.png": "",
    "src/code.cpp": "int main() {}\n",
}
# (file, target) of every broken link above, each on a line of its own, and nothing else
SELF_TEST_BROKEN = {
    ("README.md", "docs/nothing.md"),
    ("README.md", "docs/guide.md#performance-benchmarkstransfer"),
    ("README.md", "../outside/notes.md"),
    ("README.md", "/docs/guide.md"),
    ("README.md", "docs/untracked.md"),
    ("README.md", "docs/guide.md#notes-2"),
    ("README.md", "#not-a-heading"),
    ("README.md", "src/code.cpp#main"),
    ("README.md", "ftp://example.org/f"),
    ("README.md", "docs/guide.md#nowhere"),
    ("docs/guide.md", "#guides"),
}


def planted_line(name, target):
    """The line of the file that holds the broken link to `target` (1-based)."""
    lines = SELF_TEST_FILES[name].split("\n")
    return next(i + 1 for i, line in enumerate(lines)
                if f"]({target})" in line or f"]: {target}" in line)


# GitHub's slugs of some headings, as its rendered pages give them
SELF_TEST_SLUGS = {
    "Performance (tools/benchmarks/transfer)": "performance-toolsbenchmarkstransfer",
    "6. Measuring a run": "6-measuring-a-run",
    "The finite element phase: `fem-solve`": "the-finite-element-phase-fem-solve",
    "`[metrics]` (the measures)": "metrics-the-measures",
    "Mohr–Coulomb with tension cut-off": "mohrcoulomb-with-tension-cut-off",
    "Column-short with the case defaults (small strain, quad4-1gp, 0 → 8 s)":
        "column-short-with-the-case-defaults-small-strain-quad4-1gp-0--8-s",
    "Kinds \"particles\" and \"mpm\"": "kinds-particles-and-mpm",
    "σyy and ρ₀": "σyy-and-ρ₀",
    "_Emphasis_ and __init__ and `__init__`": "emphasis-and-init-and-__init__",
    "Verification (tests/mpm: `build/tests/mpm/tests_mpm`, `tests_mpm_cli`)":
        "verification-testsmpm-buildtestsmpmtests_mpm-tests_mpm_cli",
}


def self_test():
    failures = []
    for heading, expected in SELF_TEST_SLUGS.items():
        got = slug(heading_text(heading))
        if got != expected:
            failures.append(f"slug of {heading!r}: {got!r}, expected {expected!r}")
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp) / "repo"
        for name, content in SELF_TEST_FILES.items():
            (root / name).parent.mkdir(parents=True, exist_ok=True)
            (root / name).write_text(content, encoding="utf-8")
        (root / "docs" / "untracked.md").write_text("# Untracked\n", encoding="utf-8")
        (Path(tmp) / "outside").mkdir()
        (Path(tmp) / "outside" / "notes.md").write_text("# Outside\n", encoding="utf-8")
        git = ["git", "-C", str(root)]
        subprocess.run(git + ["init", "-q"], check=True)
        subprocess.run(git + ["add"] + list(SELF_TEST_FILES), check=True)
        # the checker as the test suite runs it, on that repository
        done = subprocess.run([sys.executable, __file__, "--root", str(root)],
                              capture_output=True, text=True)
        reported = set()
        for line in done.stdout.splitlines():
            m = re.match(r"^(.+?):(\d+): (.+?): .+$", line)
            if not m:
                failures.append(f"unexpected output line {line!r}")
                continue
            reported.add((m.group(1), int(m.group(2)), m.group(3)))
        planted = {(name, planted_line(name, target), target) for name, target in SELF_TEST_BROKEN}
        for missed in sorted(planted - reported):
            failures.append(f"broken link not reported: {missed}")
        for extra in sorted(reported - planted):
            failures.append(f"good link reported as broken: {extra}")
        if done.returncode != 1:
            failures.append(f"exit status {done.returncode} with broken links, expected 1")
        # without the lines of the broken links, the same files pass
        for name in ("README.md", "docs/guide.md"):
            bad = {planted_line(n, target) for n, target in SELF_TEST_BROKEN if n == name}
            lines = SELF_TEST_FILES[name].split("\n")
            (root / name).write_text("\n".join(line for i, line in enumerate(lines)
                                               if i + 1 not in bad), encoding="utf-8")
        done = subprocess.run([sys.executable, __file__, "--root", str(root)],
                              capture_output=True, text=True)
        if done.returncode != 0 or done.stdout:
            failures.append(f"good links only: exit status {done.returncode}, output "
                            f"{done.stdout!r}, expected 0 and nothing")
    for message in failures:
        print(f"FAIL {message}")
    print(f"check-links self-test: {len(SELF_TEST_SLUGS)} slugs, {len(SELF_TEST_BROKEN)} broken "
          f"links planted, {len(failures)} failures")
    return 1 if failures else 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--root", default=str(Path(__file__).resolve().parents[1]),
                        help="the repository (default: the one holding this script)")
    parser.add_argument("--self-test", action="store_true",
                        help="check the checker on planted good and bad links")
    args = parser.parse_args()
    if args.self_test:
        return self_test()
    files = tracked_files(args.root)
    report = check(args.root, files)
    for line in report:
        print(line)
    count = sum(f.endswith(".md") for f in files)
    print(f"check-links: {count} Markdown files, {len(report)} broken links", file=sys.stderr)
    return 1 if report else 0


if __name__ == "__main__":
    sys.exit(main())
