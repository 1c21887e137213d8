"""The README's code blocks run as written, in README order, in one fresh working folder.

The folder is a user's after command 1 alone: a fresh ``.venv`` with the project installed
without the test extras. ``sh`` blocks run in bash (``set -e``: every line must succeed) with
the ``PATH`` of the test process minus any virtual environment, so a block reaches ``heli``
only as a user would, by activating ``.venv`` or naming ``.venv/bin/heli``; ``python`` blocks
run as scripts with that environment's Python (``.venv/bin/python block.py``, so that a block
guarded by ``if __name__ == "__main__"`` starts its worker processes as a user's script
would). The two set-up blocks begin with the installation itself: the test command is what
CI runs (``.ci/run`` runs exactly that line), and of the first block the test runs what
follows the installation, ``.venv/bin/heli demo``, so that the FMU snippet further down finds
``out/demo``.

All blocks run once per session (about a minute to install ``.venv`` from pip's cache, then
about three minutes with warm model caches: the demo, the simulations, trims and Floquet
analyses of the usage blocks and three small Dask sweeps);
each block is then one test with its own output. The scene table is checked against
``heli scenes --markdown``.
"""
from __future__ import annotations

import os
import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
VENV = Path(sys.executable).parent.parent
INSTALL = ("python3 -m venv .venv && .venv/bin/pip install -e . && ",)
TEST_COMMAND = 'python3 -m venv .venv && .venv/bin/pip install -e ".[test]" && .venv/bin/python -m pytest'
TIMEOUT = 1200  # s per block


@dataclass
class Block:
    line: int
    language: str
    text: str

    @property
    def name(self) -> str:
        return f"README.md:{self.line} ({self.language})"


def blocks() -> list[Block]:
    """Every fenced code block of the README (indented ones in lists included)."""
    text = README.read_text()
    out = []
    for m in re.finditer(r"^( *)```(\w*)\n(.*?)^\1```", text, re.S | re.M):
        body = "\n".join(line[len(m.group(1)):] for line in m.group(3).splitlines())
        out.append(Block(text[:m.start()].count("\n") + 1, m.group(2), body + "\n"))
    return out


def runnable(block: Block) -> str | None:
    """The command text the test runs for ``block`` (None for the test command itself)."""
    text = block.text.strip()
    if text == TEST_COMMAND:
        return None
    for prefix in INSTALL:
        text = text.removeprefix(prefix)
    return text + "\n"


def user_path() -> str:
    """The ``PATH`` of this process without the folders of virtual environments (this one's)."""
    keep = [p for p in os.environ.get("PATH", "").split(os.pathsep)
            if p and not (Path(p) / "activate").exists() and Path(p) != VENV / "bin"]
    return os.pathsep.join(keep)


def run_block(block: Block, folder: Path) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if k not in ("VIRTUAL_ENV", "PYTHONHOME", "PYTHONPATH")}
    env.update(PATH=user_path(), MPLBACKEND="Agg", PYTHONUNBUFFERED="1",
               XDG_DATA_HOME=str(folder / "share"))  # a user's empty data folder: no trims stored yet
    script = folder / f"block_{block.line}.{'py' if block.language == 'python' else 'sh'}"
    script.write_text(runnable(block))
    python = str(folder / ".venv" / "bin" / "python")
    command = [python, script.name] if block.language == "python" else ["bash", "-e", script.name]
    return subprocess.run(command, cwd=folder, env=env, capture_output=True, text=True, timeout=TIMEOUT)


def install_command_1(folder: Path) -> None:
    """What command 1 installs, into ``folder/.venv``: the project without the test extras."""
    subprocess.run([sys.executable, "-m", "venv", ".venv"], cwd=folder, check=True)
    proc = subprocess.run([str(folder / ".venv" / "bin" / "pip"), "install", "-q", "-e", str(ROOT)], cwd=folder,
                          capture_output=True, text=True, timeout=TIMEOUT)
    assert proc.returncode == 0, proc.stderr[-3000:]


@pytest.fixture(scope="session")
def readme_folder(tmp_path_factory) -> Path:
    """The folder the README's blocks run in."""
    return tmp_path_factory.mktemp("readme")


@pytest.fixture(scope="session")
def readme_runs(readme_folder) -> dict[int, subprocess.CompletedProcess]:
    """Each runnable block's process, run in README order in one folder after command 1."""
    install_command_1(readme_folder)
    return {b.line: run_block(b, readme_folder) for b in blocks() if runnable(b) is not None}


def test_the_readme_has_its_blocks():
    langs = [b.language for b in blocks()]
    assert len(langs) >= 8 and set(langs) == {"sh", "python"}, langs
    assert all(b.text.strip() for b in blocks())


@pytest.mark.parametrize("block", [b for b in blocks() if runnable(b) is not None], ids=lambda b: b.name)
def test_block_runs_as_written(block, readme_runs):
    proc = readme_runs[block.line]
    assert proc.returncode == 0, f"{block.name} failed:\n{block.text}\nstdout:\n{proc.stdout[-3000:]}\n" \
                                 f"stderr:\n{proc.stderr[-3000:]}"


def test_the_quick_start_flies_a_trimmed_aircraft(readme_runs, readme_folder):
    """The new aircraft of the quick start flies from its periodic trim: ``run.json`` says so and
    holds the initial state, and the roll stays within 0.5 deg of the trim's over the 5
    revolutions (from the closed-form estimate it went from -2.9 to +6.1 deg)."""
    import json

    import numpy as np

    out = readme_folder / "out" / "mine"
    meta = json.loads((out / "run.json").read_text())
    start = meta["initial_state"]
    assert meta["revs"] == 5 and start["from"] == "periodic trim" and not start["computed_now"]  # the stored one
    assert start["file"] == str(readme_folder / "share" / "rotor-mbs" / "trims.toml")
    data = np.genfromtxt(out / "results.csv", delimiter=",", names=True, deletechars="")
    w, x, y, z = (data[f"fuselage.q{c}"] for c in "wxyz")
    roll = np.degrees(np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y)))
    assert roll[0] == pytest.approx(start["roll_deg"], abs=1e-9) and start["state"]["fuselage.qw"] == w[0]
    assert np.abs(roll - start["roll_deg"]).max() < 0.5


def test_the_test_command_is_what_ci_runs():
    ci = (ROOT / ".ci" / "run").read_text().strip().splitlines()
    assert ci[-1] == TEST_COMMAND
    assert [b for b in blocks() if runnable(b) is None] != []


def test_scene_table_is_heli_scenes_markdown():
    from mbs import commands, scenes

    table = commands.scene_table([commands.scene_row(sc) for sc in scenes.all_scenes().values()])
    assert table in README.read_text(), f"README's scene table differs from `heli scenes --markdown`:\n{table}"
