"""The documentation site under ``docs/``: it builds with warnings as errors, works offline as
files, its start page leads to the three tasks a newcomer looks for, and every code block of
its pages runs as written.

The blocks run in the order of the site's navigation, in the same user's folder as the
README's (:mod:`user_shell`, one session fixture): about 6 minutes with warm model caches
(two FMU builds, trims, a Floquet fan plot, derivatives, a validation, three sweeps, loads and
short simulations), the strict build about 10 s.
"""
from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from user_shell import DATA, ROOT, RUN, SHOWN, blocks, failure, runnable

DOCS = ROOT / "docs"
CONFIG = ROOT / "mkdocs.yml"

SHOWN_BLOCKS = {  # (page, first line): why the block is shown and not run
    ("docs/how-to/sweep-on-a-cluster.md", "$ dask scheduler --port 8786"): "needs a real cluster's nodes",
    ("docs/how-to/sweep-on-a-cluster.md", "$ heli sweep trim forward-flight"): "needs a real cluster's address",
    ("docs/how-to/view-a-run.md", "$ heli view out/view --serve"): "serves until Ctrl-C",
    ("docs/viewer.md", "$ heli view out/ff --serve"): "serves until Ctrl-C",
    ("docs/viewer.md", ">>> from viewer import LiveViewer"): "serves a browser page in real time",
    ("docs/tutorials/trim-and-stability.md", "$ heli validate bo105_flight_test"): "minutes per data set",
    ("docs/validation.md", "$ heli validate bo105_flight_test"): "minutes per data set",
    ("docs/benchmarks/scaling-and-speed.md", "$ heli bench speed --json"): "benchmarks take minutes",
    ("docs/about.md", "$ .venv/bin/pip install -e"): "a checkout's build: test_the_site_builds_with_no_warning",
}

TASKS = {  # the start page's three tasks: page, and what the page must show
    "how-to/aircraft-from-published-tables.md": ("heli aircraft new", "heli aircraft check", 'source = "'),
    "how-to/linearise-the-fmu.md": ("heli fmu linearize", "from fmu.linearize import linearize"),
    "how-to/sweep-on-a-cluster.md": ("--scheduler", "dask scheduler", "dask worker", "MBS_CACHE_DIR"),
}

PACKAGES = ("mbs", "mbs.aircraft", "mbs.analysis", "mbs.aero", "mbs.loads", "mbs.sweep", "mbs.validate", "fmu", "viewer")


def pages() -> list[str]:
    """The pages of the navigation, in its order (paths under ``docs/``)."""
    return re.findall(r"^\s*- (?:[^:\n]+: )?([\w/.-]+\.md)\s*$", CONFIG.read_text(), re.M)


def doc_blocks() -> list:
    return [b for page in pages() for b in blocks(DOCS / page)]


@pytest.fixture(scope="session")
def site(tmp_path_factory) -> tuple[subprocess.CompletedProcess, Path]:
    """The site built with ``mkdocs build --strict``, and its folder."""
    out = tmp_path_factory.mktemp("site")
    env = dict(os.environ, NO_MKDOCS_2_WARNING="1")
    proc = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(out)], cwd=ROOT,
                          env=env, capture_output=True, text=True, timeout=600)
    return proc, out


@pytest.fixture(scope="session")
def docs_runs(user_shell) -> dict[str, subprocess.CompletedProcess]:
    """Each runnable block's process, run in the navigation's order."""
    return {b.name: user_shell.run(b) for b in doc_blocks() if runnable(b) is not None}


def test_the_site_builds_with_no_warning(site):
    proc, out = site
    log = proc.stdout + proc.stderr
    assert proc.returncode == 0, log[-5000:]
    assert "warning" not in log.lower(), log[-5000:]
    assert (out / "index.html").exists()


def test_every_page_is_in_the_navigation():
    listed = set(pages())
    found = {str(p.relative_to(DOCS)) for p in DOCS.rglob("*.md") if "hooks" not in p.parts}
    assert found == listed, (found - listed, listed - found)


def test_the_site_works_offline_as_files(site):
    """No page loads anything from the network (scripts, styles, images, fonts); links are files."""
    _, out = site
    html = list(out.rglob("*.html"))
    assert len(html) >= 30
    loads = re.compile(r"<(?:script|img|iframe)[^>]*\bsrc=\"(?:https?:)?//|<link[^>]*\bhref=\"(?:https?:)?//")
    remote = [str(p.relative_to(out)) for p in html if loads.search(p.read_text())]
    assert not remote, remote
    assert not [p for p in out.rglob("*.css") if "fonts.googleapis" in p.read_text()]
    assert (out / "search" / "search_index.js").read_text().startswith("var __index")
    assert 'href="getting-started.html"' in (out / "index.html").read_text()


def test_search_works_from_files(site, page):
    """Opened as files, the site's search finds the linearisation how-to (no server, no network)."""
    _, out = site
    remote = []
    page.on("request", lambda r: remote.append(r.url) if not r.url.startswith("file:") else None)
    page.goto((out / "index.html").as_uri())
    page.click(".md-search__input", force=True)
    page.keyboard.type("linearize", delay=20)
    page.wait_for_selector('.md-search-result__item a[href*="how-to/linearise-the-fmu.html"]', timeout=20000)
    assert not remote, remote


def test_the_start_page_leads_to_the_three_tasks(site):
    _, out = site
    start = (DOCS / "index.md").read_text()
    first_table = start[start.index("| I want to"):start.index("\n\n", start.index("| I want to"))]
    built = (out / "index.html").read_text()
    for page, shows in TASKS.items():
        assert f"]({page})" in first_table, page
        assert f'href="{page.replace(".md", ".html")}"' in built, page
        text = (DOCS / page).read_text()
        assert all(s in text for s in shows), (page, [s for s in shows if s not in text])


def test_the_api_reference_covers_the_packages(site):
    _, out = site
    for package in PACKAGES:
        assert f"::: {package}\n" in (DOCS / "reference" / "api" / f"{package}.md").read_text()
        page = (out / "reference" / "api" / f"{package}.html").read_text()
        assert f'id="{package}"' in page, package
        assert page.count('class="doc doc-heading"') >= 3, package


def test_the_blocks_follow_the_conventions():
    """Every block has a language; shown-only blocks are the listed few; output holds no command."""
    every = doc_blocks()
    assert {b.language for b in every} <= RUN | SHOWN | DATA, {b.name for b in every if b.language not in RUN | SHOWN | DATA}
    shown = {(b.path, line) for b in every if b.language in SHOWN
             for line in [b.text.lstrip().splitlines()[0]]}
    matched = {key for key in SHOWN_BLOCKS if any(p == key[0] and line.startswith(key[1]) for p, line in shown)}
    assert matched == set(SHOWN_BLOCKS), set(SHOWN_BLOCKS) - matched
    assert len(shown) == len(SHOWN_BLOCKS), sorted(shown)
    commands = [b.name for b in every if b.language in DATA and re.search(r"^(\$ |>>> |source \.venv)", b.text, re.M)]
    assert not commands, commands
    run = [b for b in every if runnable(b) is not None]
    assert len(run) >= 4 * len(SHOWN_BLOCKS), (len(run), len(SHOWN_BLOCKS))


@pytest.mark.parametrize("block", [b for b in doc_blocks() if runnable(b) is not None], ids=lambda b: b.name)
def test_block_runs_as_written(block, docs_runs):
    proc = docs_runs[block.name]
    assert proc.returncode == 0, failure(block, proc)


def test_scene_table_is_heli_scenes_markdown():
    from mbs import commands, scenes

    table = commands.scene_table([commands.scene_row(sc) for sc in scenes.all_scenes().values()])
    page = DOCS / "method" / "helicopter-model.md"
    assert table in page.read_text(), f"the scene table of {page} differs from `heli scenes --markdown`:\n{table}"
