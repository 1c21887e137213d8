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


def test_the_quick_start_flies_a_trimmed_aircraft(readme_runs, user_shell):
    """The new aircraft of the quick start flies from its periodic trim: ``run.json`` says so and
    holds the initial state, and the roll stays within 0.5 deg of the trim's over the 5
    revolutions (from the closed-form estimate it went from -2.9 to +6.1 deg)."""
    import json

    import numpy as np

    folder = user_shell.folder
    out = folder / "out" / "mine"
    meta = json.loads((out / "run.json").read_text())
    start = meta["initial_state"]
    assert meta["revs"] == 5 and start["from"] == "periodic trim" and not start["computed_now"]  # the stored one
    assert start["file"] == str(folder / "share" / "rotor-mbs" / "trims.toml")
    data = np.genfromtxt(out / "results.csv", delimiter=",", names=True, deletechars="")
    w, x, y, z = (data[f"fuselage.q{c}"] for c in "wxyz")
    roll = np.degrees(np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y)))
    assert roll[0] == pytest.approx(start["roll_deg"], abs=1e-9) and start["state"]["fuselage.qw"] == w[0]
    assert np.abs(roll - start["roll_deg"]).max() < 0.5


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
