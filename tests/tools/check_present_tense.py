#!/usr/bin/python3
"""Docs and comments state the present; the history of a change lives in git.

Fails (exit status 1, one line per hit: FILE:LINE: what was found) when a checked file
names a work session ("session 13", "in an earlier session"), an issue number ("issue 8",
"issues 3 and 4", "#3" in prose), or tells what was tried ("did not pay", "was tried",
"tried, not kept"). Add a path to CHECKED_PATHS to check it too.

Legitimate uses stay possible in two ways:
  * text that is a reference, not history, is removed before the search: URLs, DOIs and
    the bug ids of upstream projects (ALLOWED_REFERENCES, e.g. HDFFV-11052);
  * a line holding the marker `present-tense: allowed` (in a comment: `<!-- ... -->` in
    Markdown, `//` in C++) is not searched.

Usage: /usr/bin/python3 tests/tools/check_present_tense.py [REPOSITORY_ROOT]
Before searching, the script checks its own patterns on the samples below, so that a
broken pattern fails the test instead of passing everything. Standard library only.
"""
import os
import re
import sys

# Files and folders checked, relative to the repository root.
CHECKED_PATHS = [
    "README.md",
    "bench",
    "docs",
    "python",
    "src",
    "tests",
]

# Files never searched: this script, whose samples name what it looks for, and a bad-input
# sample that is not UTF-8 on purpose.
EXCLUDED_FILES = {"tests/tools/check_present_tense.py", "tests/bad_input/config/invalid_utf8.toml"}

# File endings searched inside the checked folders.
CHECKED_SUFFIXES = (".md", ".hpp", ".cpp", ".h", ".py", ".txt", ".toml", ".sh")

# What is history, each with what the message calls it.
HISTORY_PATTERNS = [
    (r"(?<!ssh )(?<!login )(?<!terminal )\bsession(?:s|'s)?(?:\s+\d+(?:\s*-\s*\d+)?)?\b", "a work session"),
    (r"\bissues?\s+#?\d+", "an issue number"),
    (r"(?<![\w&#/])#\d+\b", "an issue number (#N)"),
    (r"\bdid not pay\b", "what did not pay"),
    (r"\b(?:was|were) tried\b", "what was tried"),
    (r"\btried(?:,| and)\s+not kept\b", "what was tried"),
]

# References to other projects and publications: removed from a line before the search.
ALLOWED_REFERENCES = [
    r"\bhttps?://\S+",                 # a URL, e.g. an upstream project's issue page
    r"\bdoi:\s*\S+",                   # doi:10.1000/xyz
    r"\b10\.\d{4,9}/\S+",              # a bare DOI
    r"\bHDFFV-\d+\b",                  # the HDF Group's bug ids
    r"\bGH-\d+\b",                     # upstream GitHub ids written as GH-123
]

ALLOW_MARKER = "present-tense: allowed"

# (line, must it be reported?): the patterns' own test.
SAMPLES = [
    ("measured in session 13", True),
    ("sessions 9-20 used the old defaults", True),
    ("The tables of the previous session are replaced.", True),
    ("see issue 8's catalogue", True),
    ("the targets of issue #3", True),
    ("the format #6 asks for", True),
    ("five exact changes that did not pay", True),
    ("a retune was tried on whole runs", True),
    ("Tried, not kept: per-slot tags", True),
    ("#include <vector>", False),
    ("# Heading of a page", False),
    ("colour #1f77b4 and entity &#38;", False),
    ("HDF5 1.10.8 keeps the ID (HDFFV-11052, fixed in HDF5 1.14.1)", False),
    ("see https://github.com/HDFGroup/hdf5/issues/1234 upstream", False),
    ("Degond et al. 2023, doi:10.1016/j.jcp.2023.112345", False),
    ("the contact is issued before the event", False),
    ("an exception noted here <!-- present-tense: allowed --> session 4", False),
    ("the fall-back does not pay for itself at N = 100", False),
    ("SIGHUP (a closed terminal or ssh session)", False),
]


def hits(line):
    """The history named in one line: a list of (matched text, what it is)."""
    if ALLOW_MARKER in line:
        return []
    for reference in ALLOWED_REFERENCES:
        line = re.sub(reference, " ", line, flags=re.IGNORECASE)
    found, taken = [], []
    for pattern, what in HISTORY_PATTERNS:
        for m in re.finditer(pattern, line, flags=re.IGNORECASE):
            if not any(m.start() < end and start < m.end() for start, end in taken):
                taken.append(m.span())
                found.append((m.group(0), what))
    return found


def self_test():
    wrong = [(text, expected) for text, expected in SAMPLES if bool(hits(text)) != expected]
    for text, expected in wrong:
        print(f"check_present_tense.py: pattern self-test: {'missed' if expected else 'wrongly flagged'}: {text!r}")
    return not wrong


def files_under(root, relative):
    path = os.path.join(root, relative)
    if os.path.isfile(path):
        yield relative
        return
    if not os.path.isdir(path):
        raise SystemExit(f"check_present_tense.py: {relative}: no such file or folder under {root}")
    for folder, subfolders, names in os.walk(path):
        subfolders.sort()
        for name in sorted(names):
            relative_name = os.path.relpath(os.path.join(folder, name), root)
            if name.endswith(CHECKED_SUFFIXES) and relative_name not in EXCLUDED_FILES:
                yield relative_name


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.dirname(os.path.dirname(
        os.path.abspath(__file__))))
    if not self_test():
        return 1
    count = 0
    for relative in CHECKED_PATHS:
        for name in files_under(root, relative):
            with open(os.path.join(root, name), encoding="utf-8") as f:
                for number, line in enumerate(f, 1):
                    for text, what in hits(line):
                        print(f"{name}:{number}: {what}: '{text}' (state the present; history lives in git)")
                        count += 1
    if count:
        print(f"check_present_tense.py: {count} reference(s) to history in {', '.join(CHECKED_PATHS)}")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
