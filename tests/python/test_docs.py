"""The documentation holds together: every relative link of README.md and docs/ resolves, and no file
of the repository refers to a file outside it.

- Links: markdown links and images, inline (`[text](target)`, `![alt](target)`) and reference
  definitions (`[name]: target`), outside code blocks and code spans; web addresses are not
  followed. The target must be a file or folder of the repository, and a `#fragment` must be a heading
  of the target page under GitHub's anchor rules (lower case, punctuation dropped, spaces to hyphens,
  repeated headings numbered -1, -2, ...).
- Outside references: every tracked text file is searched for paths into the machine the project
  was built on (the shared folder beside the repository, the notes kept there, absolute /work paths).
"""
import os
import re
import shutil
import subprocess
from pathlib import Path

import pytest

from conftest import REPO_ROOT

FENCE = re.compile(r"^\s*(```|~~~)")
INLINE = re.compile(r"!?\[((?:[^\[\]]|\[[^\[\]]*\])*)\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)", re.S)
REFDEF = re.compile(r"^\s{0,3}\[[^\]]+\]:\s+<?(\S+?)>?(?:\s+\"[^\"]*\")?\s*$", re.M)
CODESPAN = re.compile(r"(`+)(.+?)\1", re.S)
HEADING = re.compile(r"^\s{0,3}(#{1,6})\s+(.*?)\s*#*\s*$")
EXTERNAL = re.compile(r"^[a-zA-Z][a-zA-Z0-9+.-]*:")  # http:, https:, mailto:, ...

# Paths outside the repository, spelled in pieces so that this file does not match itself.
OUTSIDE = [
    "/" + "work/",
    "../" + "shared",
    "shared" + "/notes",
    "shared" + "/seed",
    "notes" + "/validation.md",
    "notes" + "/boundary-integrals.md",
    "notes" + "/petsc-3.18.md",
    "notes" + "/style.md",
]


def doc_files(root=REPO_ROOT):
    """README.md and every markdown file under docs/."""
    return [root / "README.md"] + sorted((root / "docs").rglob("*.md"))


def _prose(text, spans=True):
    """text without fenced code blocks (their lines kept, emptied) and, if spans, code spans."""
    out, fenced = [], False
    for line in text.split("\n"):
        if FENCE.match(line):
            fenced = not fenced
            out.append("")
            continue
        out.append("" if fenced else line)
    text = "\n".join(out)
    return CODESPAN.sub(lambda m: " " * len(m.group(0)), text) if spans else text


def links(path):
    """(line, target) of every markdown link and image of a file, outside code."""
    text = _prose(Path(path).read_text())
    found = [(m.start(), m.group(2)) for m in INLINE.finditer(text)]
    found += [(m.start(), m.group(1)) for m in REFDEF.finditer(text)]
    return sorted((text.count("\n", 0, pos) + 1, target) for pos, target in found)


def slug(heading):
    """GitHub's anchor of a heading's text (before numbering repeats)."""
    text = re.sub(r"`([^`]*)`", r"\1", heading)  # code spans keep their text
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", text)  # links keep their text
    text = re.sub(r"<[^>]+>", "", text).strip().lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(path):
    """The heading anchors of a markdown file, repeats numbered as GitHub does."""
    seen, out = {}, set()
    for line in _prose(Path(path).read_text(), spans=False).split("\n"):
        m = HEADING.match(line)
        if not m:
            continue
        base = slug(m.group(2))
        n = seen.get(base, 0)
        seen[base] = n + 1
        out.add(base if n == 0 else f"{base}-{n}")
    return out


def broken_links(files, root=REPO_ROOT):
    """'file:line: target (why)' for each link that does not resolve."""
    root = Path(os.path.abspath(root))
    bad = []
    for f in files:
        for line, target in links(f):
            if EXTERNAL.match(target):
                continue
            where = f"{Path(f).relative_to(root)}:{line}: {target}"
            path, _, frag = target.partition("#")
            dest = Path(os.path.normpath(Path(f).parent / path)) if path else Path(f)
            if root not in dest.parents and dest != root:
                bad.append(f"{where} (outside the repository)")
            elif not dest.exists():
                bad.append(f"{where} (no such file)")
            elif frag and dest.suffix == ".md" and frag not in anchors(dest):
                bad.append(f"{where} (no heading #{frag} in {dest.name})")
    return bad


def test_slugs():
    """GitHub's anchors of headings like the ones the docs use."""
    assert slug("Output (in `-fs_output_dir`)") == "output-in--fs_output_dir"
    assert slug("Dam break: surge front and residual column (Martin & Moyce 1952)") == \
        "dam-break-surge-front-and-residual-column-martin--moyce-1952"
    assert slug("The liquid: delta-LES-SPH (`src/terms/impls/`)") == "the-liquid-delta-les-sph-srctermsimpls"


def test_links_resolve():
    files = doc_files()
    assert len(files) > 10
    assert sum(len(links(f)) for f in files) > 50, "the link finder found too few links"
    bad = broken_links(files)
    assert not bad, "broken links:\n" + "\n".join(bad)


def test_broken_link_is_caught(tmp_path):
    """A copy of the docs with one link broken (a file, then a heading) fails the check."""
    readme = (REPO_ROOT / "README.md").read_text()
    (tmp_path / "README.md").write_text(readme)
    shutil.copytree(REPO_ROOT / "docs", tmp_path / "docs")  # the pages, images and the validation report
    for extra in ("cases", "src", "tests", "python", "bench", "scripts", "plugins", "include"):
        if (REPO_ROOT / extra).exists():
            (tmp_path / extra).symlink_to(REPO_ROOT / extra)
    assert broken_links(doc_files(tmp_path), tmp_path) == []
    assert "(docs/theory.md)" in readme
    (tmp_path / "README.md").write_text(readme.replace("(docs/theory.md)", "(docs/theroy.md)", 1))
    bad = broken_links(doc_files(tmp_path), tmp_path)
    assert len(bad) == 1 and "docs/theroy.md (no such file)" in bad[0], bad
    guide = (tmp_path / "docs" / "user-guide.md").read_text()
    (tmp_path / "README.md").write_text(readme)
    (tmp_path / "docs" / "user-guide.md").write_text(guide.replace("(#output-formats)", "(#output-format)", 1))
    bad = broken_links(doc_files(tmp_path), tmp_path)
    assert len(bad) == 1 and "no heading #output-format in user-guide.md" in bad[0], bad


def tracked_text_files():
    out = subprocess.run(["git", "ls-files", "-z"], cwd=REPO_ROOT, stdout=subprocess.PIPE, check=False)
    if out.returncode != 0:
        pytest.skip("not a git checkout")
    for name in out.stdout.decode().split("\0"):
        path = REPO_ROOT / name
        if not name or not path.is_file():
            continue
        data = path.read_bytes()
        if b"\0" in data[:8192]:
            continue  # binary (images, ...)
        yield name, data.decode("utf-8", errors="replace")


def test_no_reference_outside_the_repository():
    bad = []
    for name, text in tracked_text_files():
        for n, line in enumerate(text.split("\n"), 1):
            for pattern in OUTSIDE:
                if pattern in line:
                    bad.append(f"{name}:{n}: {pattern!r} in {line.strip()[:120]!r}")
    assert not bad, "files refer to paths outside the repository:\n" + "\n".join(bad)
