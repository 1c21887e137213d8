"""Nothing lost: results are written whole or not at all, and a folder never mixes two runs.

A real Ctrl-C (SIGINT) reaches ``heli simulate`` while it writes a large ``results.csv`` into a
folder that holds an earlier complete run: the earlier run's files stay byte for byte, and no
partial file is left. ``heli view`` refuses a ``results.csv`` that is not the one its
``run.json`` was written with.
"""
from __future__ import annotations

import json
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from mbs import atomic, cli
from mbs.results import RESULTS_DIGEST, read_results

HELI = Path(sys.executable).with_name("heli")
FILES = ("results.csv", "run.json", "hinge_angles.png", "energy_error.png")


def _contents(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


def _run(folder: Path, revs: str) -> subprocess.CompletedProcess:
    return subprocess.run([str(HELI), "simulate", "structural", "--revs", revs, "--out", str(folder), "--quiet"],
                          capture_output=True, text=True, timeout=600)


def _ctrl_c_default() -> None:
    """Ctrl-C's default action in the child: a test run started in the background by a shell
    inherits SIGINT ignored, and Python then installs no KeyboardInterrupt handler."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def test_ctrl_c_while_results_csv_is_written_keeps_the_earlier_run(tmp_path):
    out = tmp_path / "run"
    assert _run(out, "2").returncode == 0
    before = _contents(out)
    assert sorted(before) == sorted(FILES)
    proc = subprocess.Popen([str(HELI), "simulate", "structural", "--revs", "1000", "--out", str(out), "--quiet"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, preexec_fn=_ctrl_c_default)
    partial, deadline = [], time.monotonic() + 500
    while not partial and proc.poll() is None and time.monotonic() < deadline:
        partial = [p for p in out.glob(".results.csv.*" + atomic.PART + ".csv") if p.stat().st_size > 1_000_000]
        time.sleep(0.01)
    assert partial, "the long run ended before its results.csv was being written"
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert "interrupted" in err and "Traceback" not in err
    assert _contents(out) == before  # the earlier run intact, no partial file left beside it
    columns, meta = read_results(out)
    assert len(columns["time"]) == 201 and meta["revs"] == 2


def test_a_run_records_the_digest_of_its_table(tmp_path):
    out = tmp_path / "run"
    assert _run(out, "1").returncode == 0
    meta = json.loads((out / "run.json").read_text())
    assert meta[RESULTS_DIGEST] == atomic.sha256(out / "results.csv")
    assert not list(out.glob(".*"))


def test_view_refuses_a_table_of_another_run(tmp_path, capsys):
    first, second = tmp_path / "first", tmp_path / "second"
    assert _run(first, "1").returncode == 0 and _run(second, "0.5").returncode == 0
    (first / "results.csv").write_bytes((second / "results.csv").read_bytes())  # a copy mixing two runs
    with pytest.raises(ValueError, match="not of the same run"):
        read_results(first)
    code = cli.main(["view", str(first)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "not of the same run" in err[0] and "run the scene again" in err[0]


def test_files_renamed_together_or_not_at_all(tmp_path):
    old = {"a.txt": b"old a", "b.txt": b"old b", "stale.png": b"old chart"}
    for name, data in old.items():
        (tmp_path / name).write_bytes(data)
    with pytest.raises(KeyboardInterrupt):
        with atomic.Files() as files:
            files.temporary(tmp_path / "a.txt").write_text("new a")
            raise KeyboardInterrupt
    assert _contents(tmp_path) == old
    with atomic.Files(stale=(tmp_path / "stale.png",)) as files:
        files.temporary(tmp_path / "a.txt").write_text("new a")
        files.temporary(tmp_path / "b.txt").write_text("new b")
    assert _contents(tmp_path) == {"a.txt": b"new a", "b.txt": b"new b"}


def test_an_interrupted_single_file_leaves_the_old_one(tmp_path):
    path = tmp_path / "table.csv"
    path.write_text("old")

    def writer(tmp: Path) -> None:
        tmp.write_text("half")
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        atomic.write(path, writer)
    assert _contents(tmp_path) == {"table.csv": b"old"}
    atomic.write(path, lambda tmp: np.savetxt(tmp, np.eye(2)))
    assert np.array_equal(np.loadtxt(path), np.eye(2)) and len(list(tmp_path.iterdir())) == 1
