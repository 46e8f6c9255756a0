#!/usr/bin/python3
"""CTest 'doc_links': every relative link in the repository's Markdown files (README.md,
docs/, bench/, scripts/, tools/, scenes/, tests/) names a file that exists, and every link to a
heading (FILE.md#anchor, or #anchor within the page) names a heading that exists, with
GitHub's rule for turning a heading into an anchor. Links to web addresses are not checked.

    /usr/bin/python3 tests/scripts/test_doc_links.py"""
import os
import re
import subprocess
import sys
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
LINK = re.compile(r"\]\(([^)\s]+)\)")


def markdown_files():
    """The Markdown files git tracks, or every .md under ROOT outside build folders."""
    try:
        out = subprocess.run(["git", "-C", ROOT, "ls-files", "*.md"], capture_output=True,
                             text=True, check=True).stdout.split()
        if out:
            return [os.path.join(ROOT, f) for f in out]
    except (OSError, subprocess.CalledProcessError):
        pass
    found = []
    for folder, dirs, files in os.walk(ROOT):
        dirs[:] = [d for d in dirs if not d.startswith((".", "build", "out"))]
        found += [os.path.join(folder, f) for f in files if f.endswith(".md")]
    return found


def strip_code(text):
    """The text without fenced code blocks and inline code, where brackets are not links."""
    text = re.sub(r"```.*?```", "", text, flags=re.S)
    return re.sub(r"`[^`\n]*`", "", text)


def slug(heading):
    """GitHub's anchor for a heading: lower case, punctuation dropped, spaces to hyphens."""
    heading = heading.replace("`", "").strip().lower()
    heading = re.sub(r"[^\w\- ]", "", heading)
    return heading.replace(" ", "-")


def anchors(path):
    result, fenced = set(), False
    with open(path, encoding="utf-8") as f:
        for line in f:
            if line.startswith("```"):
                fenced = not fenced
            elif not fenced and re.match(r"#{1,6} ", line):
                result.add(slug(re.sub(r"^#+ ", "", line)))
    return result


def broken_links(path):
    with open(path, encoding="utf-8") as f:
        text = strip_code(f.read())
    broken = []
    for target in LINK.findall(text):
        if re.match(r"[a-z]+:", target):
            continue
        file_part, _, fragment = target.partition("#")
        resolved = os.path.normpath(os.path.join(os.path.dirname(path), file_part)) \
            if file_part else path
        if not os.path.exists(resolved):
            broken.append(f"{target} (no such file)")
        elif fragment and resolved.endswith(".md") and fragment not in anchors(resolved):
            broken.append(f"{target} (no such heading)")
    return broken


class DocLinks(unittest.TestCase):
    def test_every_relative_link_resolves(self):
        files = markdown_files()
        self.assertIn(os.path.join(ROOT, "README.md"), files)
        problems = []
        for path in files:
            problems += [f"{os.path.relpath(path, ROOT)}: {b}" for b in broken_links(path)]
        self.assertEqual(problems, [], "\n".join(problems))

    def test_checker_sees_a_broken_link(self):
        import tempfile
        with tempfile.TemporaryDirectory() as tmp:
            page = os.path.join(tmp, "page.md")
            with open(page, "w", encoding="utf-8") as f:
                f.write("# A title\n\n[ok](page.md#a-title) [self](#a-title) `[code](none.md)`\n"
                        "[gone](none.md) [no heading](page.md#b) [web](https://example.org)\n")
            self.assertEqual(broken_links(page),
                             ["none.md (no such file)", "page.md#b (no such heading)"])


if __name__ == "__main__":
    sys.exit(unittest.main())
