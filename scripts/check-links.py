#!/usr/bin/env python3
"""check-links.py: every link of the repository's Markdown files resolves.

A link `](#anchor)` must name a heading of the same file, `](path)` a file or folder of
the repository (relative to the file that links), and `](path#anchor)` a heading of that
file. Anchors are made from headings as GitHub makes them: lower case, punctuation but
`-` and `_` dropped, each space a `-`, a repeated heading given `-1`, `-2`, ….
Links to other sites (`http…`, `mailto:`) are not followed. Prints one line per broken
link, `FILE:LINE: …`, and exits 1 if there is any, 0 otherwise.

    scripts/check-links.py [FILE.md…]   (default: every *.md file git tracks; without
                                         git, README.md, CONTRIBUTING.md and docs/*.md)
"""

import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
LINK = re.compile(r"\]\(([^)\s]+)\)")
HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")


def slug(text):
    text = text.strip().lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(path):
    found, seen, fenced = set(), {}, False
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.lstrip().startswith("```"):
            fenced = not fenced
            continue
        m = None if fenced else HEADING.match(line)
        if m:
            base = slug(m.group(2))
            n = seen.get(base, 0)
            seen[base] = n + 1
            found.add(base if n == 0 else f"{base}-{n}")
    return found


def check(path):
    problems, fenced = [], False
    for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        if line.lstrip().startswith("```"):
            fenced = not fenced
            continue
        if fenced:
            continue
        # Inline code spans are not links.
        for target in LINK.findall(re.sub(r"`[^`]*`", "", line)):
            if re.match(r"^[a-z]+:", target):
                continue
            file_part, _, anchor = target.partition("#")
            linked = (path.parent / file_part).resolve() if file_part else path
            where = f"{path.relative_to(ROOT)}:{number}"
            if not linked.exists():
                problems.append(f"{where}: {target}: no such file")
            elif anchor and linked.suffix == ".md" and anchor not in anchors(linked):
                problems.append(f"{where}: {target}: no heading #{anchor}")
    return problems


def tracked_markdown():
    """Every Markdown file git tracks here, or the top-level documents and docs/*.md."""
    try:
        out = subprocess.run(
            ["git", "-C", str(ROOT), "ls-files", "-z", "*.md"],
            capture_output=True,
            check=True,
        ).stdout.decode()
        return [ROOT / name for name in sorted(out.split("\0")) if name]
    except (OSError, subprocess.CalledProcessError):
        return [ROOT / "README.md", ROOT / "CONTRIBUTING.md"] + sorted(
            (ROOT / "docs").glob("*.md")
        )


def main():
    files = [Path(a).resolve() for a in sys.argv[1:]] or tracked_markdown()
    problems = [p for f in files for p in check(f)]
    for p in problems:
        print(p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
