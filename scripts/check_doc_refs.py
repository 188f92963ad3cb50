#!/usr/bin/env python3
"""Checks that the sections the project cites exist.

A citation is a document name followed by one or more quoted section names,
    docs/RELIABILITY.md, "Memory and time bounds"
    (docs/PERFORMANCE.md, "Measuring", "Results")
in docs/*.md, README.md and the comments of the sources, scripts and build
files (the quotes may continue on the next comment line); in a document, a
capitalised name in parentheses alone, ("Fuzzing"), or after "section",
cites a heading of that same document. A name matches a heading of the
document (any level) equal to it, or beginning with it followed by " (" or
":". Every docs/*.md must also be listed in README.md's "Documentation".

Usage: check_doc_refs.py [--root DIR]. Prints each broken citation as
FILE:LINE: problem and exits 1 if there is any.
"""
import argparse
import os
import re
import sys

SOURCE_DIRS = ["src", "include", "tools", "tests", "scripts", "examples", "bench", "cmake"]
SOURCE_EXT = (".c", ".h", ".cpp", ".hpp", ".py", ".sh", ".cmake", ".map", ".v", ".sv", ".txt", ".in")
SKIP_DIRS = {"corpus", "data", "golden", "build", ".git", "__pycache__"}

# A comment prefix at the start of a continued line: " * ", "# ", "// ".
CONT = r'(?:\s*\n\s*(?:\*|#|//|--)?)?\s*'
QUOTED = r'"([^"\n]{2,120})"'
CITE = re.compile(r'\b([A-Z][A-Z_]*\.md),?' + CONT + QUOTED + r'((?:\s*,' + CONT + QUOTED + r')*)')
MORE = re.compile(r',' + CONT + QUOTED)
# Same-document references in the documents themselves.
LOCAL = re.compile(r'\("([A-Z][^"\n]{2,80})"\)|\bsections? "([A-Z][^"\n]{2,80})"')


def headings(path):
    """Headings (any level) and run-in headings: a paragraph opening with
    a bold or italic phrase, **Formula.** or *Test vectors.*"""
    out = set()
    fence = False
    with open(path, encoding="utf-8") as f:
        for line in f:
            if line.startswith("```"):
                fence = not fence
            if fence:
                continue
            m = re.match(r"#{1,6}\s+(.*?)\s*#*\s*$", line)
            if m:
                out.add(m.group(1).strip())
            m = re.match(r"(\*\*?)([A-Z][^*\n]{1,80}?)\.?\1", line)
            if m:
                out.add(m.group(2).strip())
    return out


def matches(name, heads):
    """The name is the heading, or its beginning up to " (", ":", " —", ","
    or " `", or one item of the list after the heading's colon."""
    name = name.strip()
    for h in heads:
        if h == name or h.replace("`", "") == name.replace("`", ""):
            return True
        if h.startswith(name) and h[len(name):][:2] in (" (", ": ", " —", ", ", " `", "."):
            return True
        if ":" in h and name in [i.strip() for i in h.split(":", 1)[1].split(",")]:
            return True
    return False


def files(root):
    yield os.path.join(root, "README.md")
    for f in sorted(os.listdir(os.path.join(root, "docs"))):
        if f.endswith(".md"):
            yield os.path.join(root, "docs", f)
    for top in ["CMakeLists.txt", "Makefile"]:
        if os.path.exists(os.path.join(root, top)):
            yield os.path.join(root, top)
    for d in SOURCE_DIRS:
        for dirpath, dirnames, names in os.walk(os.path.join(root, d)):
            dirnames[:] = sorted(n for n in dirnames if n not in SKIP_DIRS)
            for n in sorted(names):
                if n.endswith(SOURCE_EXT) or n.endswith(".md"):
                    yield os.path.join(dirpath, n)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--root", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    a = ap.parse_args()
    root = os.path.abspath(a.root)
    docs = {f: headings(os.path.join(root, "docs", f))
            for f in os.listdir(os.path.join(root, "docs")) if f.endswith(".md")}
    docs["README.md"] = headings(os.path.join(root, "README.md"))
    problems = []
    cited = 0
    for path in files(root):
        try:
            with open(path, encoding="utf-8") as f:
                text = f.read()
        except (UnicodeDecodeError, OSError):
            continue
        rel = os.path.relpath(path, root)
        if rel == os.path.join("scripts", "check_doc_refs.py"):
            continue  # its own patterns are no citations
        for m in CITE.finditer(text):
            doc = m.group(1)
            names = [m.group(2)] + [x.group(1) for x in MORE.finditer(m.group(3) or "")]
            line = text.count("\n", 0, m.start()) + 1
            if doc not in docs:
                continue  # another project's document (a dependency's README.md)
            for name in names:
                cited += 1
                if not matches(name, docs[doc]):
                    problems.append(f'{rel}:{line}: {doc}, "{name}": no such heading in {doc}')
        if path.endswith(".md") and os.path.basename(path) in docs:
            own = docs[os.path.basename(path)]
            spans = [(m.start(), m.end()) for m in CITE.finditer(text)]
            for m in LOCAL.finditer(text):
                if any(s <= m.start() < e for s, e in spans):
                    continue
                name = m.group(1) or m.group(2)
                cited += 1
                if not matches(name, own):
                    line = text.count("\n", 0, m.start()) + 1
                    problems.append(f'{rel}:{line}: "{name}": no such heading in '
                                    f'{os.path.basename(path)}')
    # README's list of documents names every document.
    readme = open(os.path.join(root, "README.md"), encoding="utf-8").read()
    sec = re.search(r"^## Documentation\n(.*?)(?=^## |\Z)", readme, re.S | re.M)
    listed = set(re.findall(r"docs/([A-Z_]+\.md)", sec.group(1))) if sec else set()
    for d in sorted(docs):
        if d != "README.md" and d not in listed:
            problems.append(f'README.md: "Documentation" does not list docs/{d}')
    for p in problems:
        print(p)
    print(f"{cited} section citations checked, {len(problems)} broken", file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
