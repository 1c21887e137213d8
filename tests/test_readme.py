"""The README: at most 15 kB, its links resolve, and its code blocks run as written, in README
order, in the user's folder of :mod:`user_shell` (a fresh ``.venv`` made by set-up command 1).

The blocks run once per session with the docs' blocks (``tests/test_docs.py``) in one folder:
about a minute to install ``.venv`` from pip's cache, then the demo and the quick start; each
block is then one test with its own output.
"""
from __future__ import annotations

import re

import pytest

from user_shell import DATA, ROOT, RUN, TEST_COMMAND, blocks, failure, runnable

README = ROOT / "README.md"
LIMIT = 15 * 1024  # bytes


@pytest.fixture(scope="session")
def readme_runs(user_shell) -> dict[int, object]:
    """Each runnable block's process, run in README order."""
    return {b.line: user_shell.run(b) for b in blocks(README) if runnable(b) is not None}


def test_the_readme_is_at_most_15_kB():
    assert len(README.read_bytes()) <= LIMIT, f"README.md is {len(README.read_bytes())} bytes, limit {LIMIT}"


def test_the_readme_has_its_blocks():
    langs = [b.language for b in blocks(README)]
    assert len(langs) >= 4 and {"sh", "python"} <= set(langs) <= RUN | DATA, langs
    assert all(b.text.strip() for b in blocks(README))


def test_the_readmes_links_resolve():
    """Relative links (``docs/...md`` pages, figures) name files that exist, on GitHub as in the site."""
    links = re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", README.read_text())
    local = [link for link in links if not re.match(r"\w+:", link)]
    assert len([link for link in local if link.startswith("docs/")]) >= 10, local
    missing = [link for link in local if not (ROOT / link).exists()]
    assert not missing, missing


@pytest.mark.parametrize("block", [b for b in blocks(README) if runnable(b) is not None], ids=lambda b: b.name)
def test_block_runs_as_written(block, readme_runs):
    proc = readme_runs[block.line]
    assert proc.returncode == 0, failure(block, proc)


def test_the_test_command_is_what_ci_runs():
    ci = (ROOT / ".ci" / "run").read_text().strip().splitlines()
    assert ci[-1] == TEST_COMMAND
    assert [b for b in blocks(README) if b.text.strip() == TEST_COMMAND] != []
