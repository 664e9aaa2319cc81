"""The examples of the README and of docs/*.md run as written.

Every ```sh and ```python block runs: the blocks of one page in order, in one fresh folder (a
later block may use the files an earlier one wrote), ``.venv/bin/`` standing for this test's
own environment. A block preceded by a ``<!-- not run: reason -->`` line is skipped.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
BLOCK = re.compile(r"^```(?P<lang>[^\n`]*)\n(?P<code>.*?)^```[ \t]*$", re.S | re.M)
NOT_RUN = re.compile(r"<!-- not run: \S.* -->")
RUN = {"sh", "python"}
BIN = Path(sys.executable).parent


def blocks(page: Path) -> list[tuple[str, str, bool]]:
    """``(language, code, runs)`` of each fenced block of a page, in order."""
    text = page.read_text(encoding="utf-8")
    out = []
    for m in BLOCK.finditer(text):
        above = text[:m.start()].rstrip("\n").rsplit("\n", 1)[-1]
        out.append((m.group("lang").strip(), m.group("code"), not NOT_RUN.fullmatch(above)))
    return out


def _examples(page: Path) -> list[tuple[str, str]]:
    return [(lang, code) for lang, code, runs in blocks(page) if lang in RUN and runs]


def _run(lang: str, code: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    env = dict(os.environ, PATH=f"{BIN}{os.pathsep}{os.environ.get('PATH', '')}",
               MPLBACKEND="Agg")
    if lang == "sh":
        cmd = ["bash", "-euo", "pipefail", "-c", code.replace(".venv/bin/", f"{BIN}/")]
    else:
        cmd = [sys.executable, "-c", code]
    return subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True, timeout=900)


def test_the_pages_fence_their_blocks_with_a_language():
    for page in PAGES:
        for lang, code, _ in blocks(page):
            assert lang, f"{page.name}: a block without a language: {code[:60]!r}"


def test_a_block_left_out_says_why_just_above_it():
    for page in PAGES:
        lines = page.read_text(encoding="utf-8").splitlines()
        for i, line in enumerate(lines):
            if line.startswith("<!-- not run"):
                assert NOT_RUN.fullmatch(line), f"{page.name}:{i + 1}: no reason: {line}"
                assert lines[i + 1].startswith("```"), f"{page.name}:{i + 1}: no block below"


@pytest.mark.slow
@pytest.mark.parametrize("page", [p for p in PAGES if _examples(p)], ids=lambda p: p.name)
def test_the_examples_of_a_page_run(page: Path, tmp_path: Path):
    for lang, code in _examples(page):
        res = _run(lang, code, tmp_path)
        assert res.returncode == 0, (f"{page.name} ```{lang} block failed "
                                     f"({res.returncode}):\n{code}\n{res.stdout[-2000:]}"
                                     f"\n{res.stderr[-3000:]}")


def _slug(heading: str) -> str:
    """A heading's anchor as GitHub and myst-parser make it."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


LINK = re.compile(r"\]\((?P<target>[^)\s]+)\)")


def test_the_links_of_the_pages_reach_files_and_headings():
    for page in PAGES:
        text = BLOCK.sub("", page.read_text(encoding="utf-8"))
        for m in LINK.finditer(text):
            target = m.group("target")
            if re.match(r"[a-z]+:", target):
                continue  # a web address
            path, _, anchor = target.partition("#")
            dest = (page.parent / path).resolve() if path else page
            assert dest.exists(), f"{page.name}: link to a missing file: {target}"
            if anchor:
                heads = re.findall(r"^#+ (.+)$", BLOCK.sub("", dest.read_text(encoding="utf-8")),
                                   re.M)
                assert anchor in {_slug(h) for h in heads}, f"{page.name}: no heading #{anchor}"
