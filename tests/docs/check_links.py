#!/usr/bin/python3
"""Every relative link in README.md and docs/*.md resolves: the file (or folder) exists and,
for a link with #anchor into a Markdown file, a heading of that file has that anchor (GitHub's
rule: lower case, punctuation other than '-' and '_' dropped, spaces to '-', -1, -2, ... for
repeats). Links inside code blocks and code spans are not links. Web links are not checked.
    check_links.py REPO_ROOT
Prints one line per broken link (file:line: link: why) and exits 1 if there is any."""
import pathlib
import re
import sys

LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")


def text_lines(path):
    """(line number, line) outside fenced code blocks, with code spans blanked."""
    fenced = False
    for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        if line.lstrip().startswith("```"):
            fenced = not fenced
            continue
        if not fenced:
            yield n, re.sub(r"`[^`]*`", "``", line)


def anchors(path):
    seen = {}
    out = set()
    fenced = False
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.lstrip().startswith("```"):
            fenced = not fenced
        m = re.match(r"#{1,6}\s+(.*?)\s*#*\s*$", line)
        if fenced or not m:
            continue
        slug = re.sub(r"[^\w\- ]", "", m.group(1).lower()).replace(" ", "-")
        k = seen.get(slug, 0)
        seen[slug] = k + 1
        out.add(slug if k == 0 else f"{slug}-{k}")
    return out


def main(root):
    root = pathlib.Path(root).resolve()
    files = [root / "README.md"] + sorted((root / "docs").glob("*.md"))
    bad = []
    checked = 0
    for f in files:
        for n, line in text_lines(f):
            for target in LINK.findall(line):
                if re.match(r"[a-z]+:", target):
                    continue
                checked += 1
                where = f"{f.relative_to(root)}:{n}: {target}"
                path, _, anchor = target.partition("#")
                dest = (f.parent / path).resolve() if path else f
                if not dest.exists():
                    bad.append(f"{where}: no such file {dest.relative_to(root) if dest.is_relative_to(root) else dest}")
                elif anchor and dest.suffix == ".md" and anchor not in anchors(dest):
                    bad.append(f"{where}: no heading with anchor #{anchor} in {dest.relative_to(root)}")
    for b in bad:
        print(b)
    print(f"{checked} relative links in {len(files)} files, {len(bad)} broken", file=sys.stderr)
    return 1 if bad or checked == 0 else 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: check_links.py REPO_ROOT")
    sys.exit(main(sys.argv[1]))
