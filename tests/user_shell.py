"""The code blocks of the README and of the docs, run as a user would run them.

One folder per test session, made as a user's after set-up command 1 alone: a fresh ``.venv``
with the project installed without the test extras. ``sh`` blocks run in bash (``set -e``:
every line must succeed) with the ``PATH`` of the test process minus any virtual environment,
so a block reaches ``heli`` only as a user would, by activating ``.venv`` or naming
``.venv/bin/heli``; ``python`` blocks run as scripts with that environment's Python
(``.venv/bin/python block.py``, so that a block guarded by ``if __name__ == "__main__"``
starts its worker processes as a user's script would). The two set-up blocks begin with the
installation itself: the test command is what CI runs (``.ci/run`` runs exactly that line),
and of the first block the shell runs what follows the installation, ``.venv/bin/heli demo``.

Blocks of other languages are not run: ``console`` (shell, ``$`` prompts) and ``pycon``
(Python, ``>>>`` prompts) are shown-only commands, ``text`` and ``toml`` output, equations and
file contents. A block whose text was already run in the session (the README's quick start is
also the docs' getting started) is not run again: its first run is its result.
"""
from __future__ import annotations

import os
import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
VENV = Path(sys.executable).parent.parent
INSTALL = ("python3 -m venv .venv && .venv/bin/pip install -e . && ",)
TEST_COMMAND = 'python3 -m venv .venv && .venv/bin/pip install -e ".[test]" && .venv/bin/python -m pytest'
RUN = {"sh", "python"}
SHOWN = {"console", "pycon"}
DATA = {"text", "toml"}
TIMEOUT = 1200  # s per block


@dataclass(frozen=True)
class Block:
    path: str
    line: int
    language: str
    text: str

    @property
    def name(self) -> str:
        return f"{self.path}:{self.line} ({self.language})"


def blocks(path: Path) -> list[Block]:
    """Every fenced code block of the Markdown file ``path`` (indented ones in lists included)."""
    text = path.read_text()
    out = []
    for m in re.finditer(r"^( *)```([\w-]*)\n(.*?)^\1```", text, re.S | re.M):
        body = "\n".join(line[len(m.group(1)):] for line in m.group(3).splitlines())
        out.append(Block(str(path.relative_to(ROOT)), text[:m.start()].count("\n") + 1, m.group(2), body + "\n"))
    return out


def runnable(block: Block) -> str | None:
    """The command text the shell runs for ``block`` (None: not run, or the test command itself)."""
    text = block.text.strip()
    if block.language not in RUN or text == TEST_COMMAND:
        return None
    for prefix in INSTALL:
        text = text.removeprefix(prefix)
    return text + "\n"


def user_path() -> str:
    """The ``PATH`` of this process without the folders of virtual environments (this one's)."""
    keep = [p for p in os.environ.get("PATH", "").split(os.pathsep)
            if p and not (Path(p) / "activate").exists() and Path(p) != VENV / "bin"]
    return os.pathsep.join(keep)


def install_command_1(folder: Path) -> None:
    """What command 1 installs, into ``folder/.venv``: the project without the test extras."""
    subprocess.run([sys.executable, "-m", "venv", ".venv"], cwd=folder, check=True)
    proc = subprocess.run([str(folder / ".venv" / "bin" / "pip"), "install", "-q", "-e", str(ROOT)], cwd=folder,
                          capture_output=True, text=True, timeout=TIMEOUT)
    assert proc.returncode == 0, proc.stderr[-3000:]


class UserShell:
    """A user's folder after command 1, in which blocks run one after another."""

    def __init__(self, folder: Path):
        self.folder = folder
        self.done: dict[str, subprocess.CompletedProcess] = {}
        install_command_1(folder)

    def run(self, block: Block) -> subprocess.CompletedProcess:
        """``block`` run in the folder (once per text and session)."""
        text = runnable(block)
        if text not in self.done:
            self.done[text] = self._run(block, text)
        return self.done[text]

    def _run(self, block: Block, text: str) -> subprocess.CompletedProcess:
        env = {k: v for k, v in os.environ.items() if k not in ("VIRTUAL_ENV", "PYTHONHOME", "PYTHONPATH")}
        env.update(PATH=user_path(), MPLBACKEND="Agg", PYTHONUNBUFFERED="1",
                   XDG_DATA_HOME=str(self.folder / "share"))  # a user's empty data folder: no trims stored yet
        stem = re.sub(r"\W", "_", f"{block.path}_{block.line}")
        script = self.folder / f"block_{stem}.{'py' if block.language == 'python' else 'sh'}"
        script.write_text(text)
        python = str(self.folder / ".venv" / "bin" / "python")
        command = [python, script.name] if block.language == "python" else ["bash", "-e", script.name]
        return subprocess.run(command, cwd=self.folder, env=env, capture_output=True, text=True, timeout=TIMEOUT)


def failure(block: Block, proc: subprocess.CompletedProcess) -> str:
    return (f"{block.name} failed:\n{block.text}\nstdout:\n{proc.stdout[-3000:]}\n"
            f"stderr:\n{proc.stderr[-3000:]}")
