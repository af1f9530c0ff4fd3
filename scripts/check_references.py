#!/usr/bin/env python3
"""Checks that every repository file named in a comment or in Markdown exists, and that every
equation number cited there comes with the paper it is from.

Reads the comments of C++ files (// and /* */), of Python, shell and CMake files (#), and the
whole text of Markdown files, and finds the tokens that look like repository paths: they contain
a '/' and start with one of the repository's top folders (apps/, coupling/, docs/, ...), or they
are a bare C++ file name (`name.cpp`, `name.hpp`). A path must exist relative to the repository
root or to the citing file's folder (Markdown links), or be the stem of such a file
(`mesh/io/vtu_reader` for vtu_reader.hpp and .cpp, a test or bench target); a glob
(`apps/scene/blocks/*.cpp`) must match a file; a bare C++ file name must be the name of some file in the repository. Paths outside
the repository (a machine's absolute folders such as `/home/...` or `/root/...`, and `../shared/...`)
are never allowed. URLs and placeholders (`NAME`,
`NNNNN`, `<dir>`) are skipped.

An equation reference (`eq. (7)`, `eqs. 60, 61`, `equation 5`) in a file's comments or Markdown
needs a paper named by author and year (`Chentanez et al. 2006`, `Lian, Liu & Zhang 2014`,
`Bathe 1996`) in the same file's comments or in the README.md of its folder or the nearest folder
above it (the repository's top README does not count: it would cover every file).

Docs are reference, not a diary: "seed paper", "session" and "this round / the round before"
wording is refused too (a paper is cited by author and year, a measurement by its date).

Prints file:line: message for each problem and exits 1 if there is any, else 0.

    python3 scripts/check_references.py [--root DIR]

Hand-written (standard library only) because it must run in CI without extra packages, and
link checkers (lychee, markdown-link-check) read Markdown links, not paths in code comments.
"""
import argparse
import glob
import os
import re
import sys

SKIP_DIRS = {".git", "__pycache__"}
CPP_EXT = (".cpp", ".hpp", ".h", ".cc", ".c")
HASH_EXT = (".py", ".sh", ".cmake")
# A path-like token: components of letters, digits, _ . - * joined by '/'.
TOKEN = re.compile(r"(?<![\w./:*~-])(\.{0,2}/?[\w.*-]+(?:/[\w.*-]+)*/?)")
BARE_CPP = re.compile(r"(?<![\w./*<>-])([A-Za-z_][\w-]+\.(?:cpp|hpp))\b(?!/)")
PLACEHOLDER = re.compile(r"\b(?:[A-Z]{2,}[A-Z0-9_]*|N{2,})\b|\bX+\b|\.\.\.")
# A machine's own folders (home, root and the sandbox's work tree), named by their first component.
OUTSIDE = re.compile(r"(?:\.\./shared\b|(?<![\w.~-])/(?:home|root|work)/)")
DIARY = re.compile(r"\bseed paper|(?<![\w-])sessions?\b|\b(?:this|earlier) rounds?\b|"
                   r"\b(?:the|two|three|four|five|\d+) rounds? before\b|\bthe round after\b", re.IGNORECASE)
EQUATION = re.compile(r"\beqs?\.\s*\(?\d|\bequations?\s+\(?\d", re.IGNORECASE)
NAME = r"[A-Z][A-Za-z\u00C0-\u017F'-]+"
# Author and year: "Bathe 1996", "Chentanez et al. 2006", "Lian, Liu & Zhang 2014", "Ghia, Ghia & Shin (1982)".
PAPER = re.compile(NAME + r"(?: et al\.?|(?:, " + NAME + r")*,? (?:&|and) " + NAME + r")?,? \(?(?:1[6-9]|20)\d\d\b")


def output_folder(name):
    """Top folders that builds and runs make (see .gitignore): not part of the sources."""
    return name.startswith("build") or name == "out" or name.startswith("out-")


def top_folders(root):
    return {d for d in os.listdir(root)
            if os.path.isdir(os.path.join(root, d)) and d not in SKIP_DIRS and not output_folder(d)}


def repository_files(root):
    """Every file of the repository (output folders and .git left out)."""
    for dirpath, dirnames, filenames in os.walk(root):
        top = os.path.relpath(dirpath, root) == "."
        dirnames[:] = [d for d in dirnames if d not in SKIP_DIRS and not (top and output_folder(d))]
        for name in filenames:
            yield os.path.join(dirpath, name)


def source_files(paths):
    return [p for p in paths
            if p.endswith(CPP_EXT + HASH_EXT + (".md",)) or os.path.basename(p) == "CMakeLists.txt"]


def comment_lines(path, text):
    """Yields (line number, text to check) for the comments of a source file or a Markdown file."""
    lines = text.split("\n")
    if path.endswith(".md"):
        yield from enumerate(lines, 1)
        return
    if path.endswith(CPP_EXT):
        in_block = False
        for n, line in enumerate(lines, 1):
            if in_block:
                end = line.find("*/")
                yield n, line if end < 0 else line[:end]
                in_block = end < 0
                continue
            code, _, comment = line.partition("//")
            start = code.find("/*")
            if start >= 0 and '"' not in code[:start]:
                end = code.find("*/", start + 2)
                yield n, code[start + 2:] if end < 0 else code[start + 2:end]
                in_block = end < 0
            if comment and code.count('"') % 2 == 0:
                yield n, comment
        return
    for n, line in enumerate(lines, 1):  # Python, shell, CMake: '#' outside a string
        hash_at = line.find("#")
        if hash_at >= 0 and line[:hash_at].count('"') % 2 == 0 and line[:hash_at].count("'") % 2 == 0:
            yield n, line[hash_at + 1:]


def nearest_readme(root, path):
    """The README.md of path's folder or of the nearest folder above it, below the root; or None."""
    folder = os.path.dirname(path)
    while os.path.abspath(folder) != root:
        readme = os.path.join(folder, "README.md")
        if readme != path and os.path.exists(readme):
            return readme
        folder = os.path.dirname(folder)
    return None


def names_paper(path, cache):
    if path not in cache:
        with open(path, encoding="utf-8", errors="replace") as f:
            cache[path] = bool(PAPER.search(f.read()))
    return cache[path]


def exists(root, citing_dir, token):
    for base in (root, citing_dir):
        candidate = os.path.normpath(os.path.join(base, token))
        if "*" in token:
            if glob.glob(candidate):
                return True
        elif os.path.exists(candidate) or glob.glob(candidate + ".*"):
            return True  # a file, a folder, or a file named by its stem (mesh/io/vtu_reader)
    return False


def check(root):
    tops = top_folders(root)
    everything = list(repository_files(root))
    basenames = {os.path.basename(p) for p in everything}
    files = source_files(everything)
    problems = []
    readme_cache = {}
    for path in files:
        rel = os.path.relpath(path, root)
        if rel == os.path.join("scripts", "check_references.py"):
            continue
        with open(path, encoding="utf-8", errors="replace") as f:
            text = f.read()
        citing_dir = os.path.dirname(path)
        comments = list(comment_lines(path, text))
        first_equation = next((n for n, line in comments if EQUATION.search(line)), None)
        if first_equation is not None and not PAPER.search(" ".join(line.strip() for _, line in comments)):
            readme = nearest_readme(root, path)
            if readme is None or not names_paper(readme, readme_cache):
                problems.append(f"{rel}:{first_equation}: cites an equation number but names no paper "
                                f"(author and year) in the file or its folder's README")
        for n, line in comments:
            diary = DIARY.search(line)
            if diary:
                problems.append(f"{rel}:{n}: diary wording \"{diary.group(0)}\": cite by author and year, "
                                f"date a measurement")
            if OUTSIDE.search(line):
                problems.append(f"{rel}:{n}: names a path outside the repository: {line.strip()[:100]}")
            line = re.sub(r"[a-z][a-z0-9+.-]*://\S+", " ", line)  # URLs
            for m in TOKEN.finditer(line):
                token = m.group(1).rstrip(".")
                parts = [p for p in token.split("/") if p not in ("", ".")]
                if "/" not in token or not parts or PLACEHOLDER.search(token):
                    continue
                if parts[0] == "..":
                    parts = [p for p in parts if p != ".."]
                if not parts or parts[0] not in tops:
                    continue
                if token.startswith("/"):
                    continue  # an absolute path of the system (e.g. /usr/include/...)
                if not exists(root, citing_dir, token):
                    problems.append(f"{rel}:{n}: no such file or folder: {token}")
            for m in BARE_CPP.finditer(line):
                if m.group(1) not in basenames and not PLACEHOLDER.search(m.group(1)):
                    problems.append(f"{rel}:{n}: no file of this name in the repository: {m.group(1)}")
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--root", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    args = parser.parse_args()
    problems = check(os.path.abspath(args.root))
    for p in problems:
        print(p)
    if problems:
        print(f"{len(problems)} problem(s)", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
