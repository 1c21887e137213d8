"""Files written whole or not at all.

Every result file (``results.csv``, ``run.json``, charts, sweep tables, FMUs, HTML pages, trim
files) is written under a temporary name in its own folder (``.results.csv.<random>.part``)
and renamed to its name when complete: a rename within a folder is atomic, so a reader, a
crash or Ctrl-C sees the earlier file or the new one, never a truncated one. A temporary file
is removed when its writing fails or is interrupted.

:class:`Files` writes the files of one run together: each to its temporary name, then all
renamed at the end with Ctrl-C held off for those few renames, so that a folder never mixes
the files of two runs (``heli view`` checks this too: ``run.json`` records the SHA-256 of
``results.csv``).
"""
from __future__ import annotations

import contextlib
import hashlib
import os
import signal
import tempfile
import threading
from pathlib import Path
from typing import Callable, Iterator

PART = ".part"


def _temporary(path: Path) -> Path:
    """A new empty file beside ``path`` (same folder, same suffix, so that writers that infer
    the format from the suffix still do) with the permissions of a newly created file."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, name = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=PART + path.suffix)
    os.close(fd)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(name, 0o666 & ~umask)
    return Path(name)


def _remove(path: Path) -> None:
    with contextlib.suppress(OSError):
        os.unlink(path)


@contextlib.contextmanager
def replacing(path: Path) -> Iterator[Path]:
    """``with replacing(path) as tmp:`` write ``tmp``; when the block ends normally ``tmp``
    replaces ``path``, otherwise (an error, Ctrl-C) it is removed and ``path`` is untouched."""
    path = Path(path)
    tmp = _temporary(path)
    try:
        yield tmp
    except BaseException:
        _remove(tmp)
        raise
    os.replace(tmp, path)


def write(path: Path, writer: Callable[[Path], object]) -> Path:
    """``writer(tmp)`` writes the file, which then replaces ``path``; returns ``path``."""
    with replacing(path) as tmp:
        writer(tmp)
    return Path(path)


def write_text(path: Path, text: str) -> Path:
    """``text`` (UTF-8) as ``path``, atomically."""
    return write(path, lambda tmp: tmp.write_text(text, encoding="utf-8"))


def write_bytes(path: Path, data: bytes) -> Path:
    """``data`` as ``path``, atomically."""
    return write(path, lambda tmp: tmp.write_bytes(data))


def savefig(fig, path: Path, **options) -> Path:
    """Matplotlib's ``fig.savefig`` to ``path``, atomically (the format from the suffix)."""
    return write(path, lambda tmp: fig.savefig(tmp, format=Path(path).suffix.lstrip(".") or None, **options))


def copy(source: Path, path: Path) -> Path:
    """A copy of the file ``source`` as ``path``, atomically."""
    import shutil

    return write(path, lambda tmp: shutil.copyfile(source, tmp))


def sha256(path: Path) -> str:
    """SHA-256 of the file ``path`` (hex)."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


@contextlib.contextmanager
def interrupts_held() -> Iterator[None]:
    """Ctrl-C (SIGINT) held off inside the block and delivered when it ends (main thread only;
    elsewhere the block runs as it is)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught = []
    previous = signal.signal(signal.SIGINT, lambda signum, frame: caught.append(signum))
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
    if caught:
        raise KeyboardInterrupt


class Files:
    """The files of one run, written together::

        with Files() as files:
            write_csv(columns, files.temporary(out / "results.csv"))
            files.temporary(out / "run.json").write_text(...)

    Each :meth:`temporary` path is renamed to its final name when the block ends normally, all
    of them with Ctrl-C held off; on an error or Ctrl-C inside the block they are all removed
    and the folder keeps what it had. ``stale``: files of an earlier run that this run does
    not write, removed at the same time (e.g. a chart the new run does not draw)."""

    def __init__(self, stale: tuple[Path, ...] = ()):
        self.pending: list[tuple[Path, Path]] = []
        self.stale = [Path(p) for p in stale]

    def temporary(self, path: Path) -> Path:
        """A temporary file that becomes ``path`` when the block ends."""
        tmp = _temporary(Path(path))
        self.pending.append((tmp, Path(path)))
        return tmp

    def __enter__(self) -> "Files":
        return self

    def __exit__(self, kind, value, tb) -> None:
        if kind is not None:
            for tmp, _ in self.pending:
                _remove(tmp)
            return
        finals = {final for _, final in self.pending}
        with interrupts_held():
            for tmp, final in self.pending:
                os.replace(tmp, final)
            for path in self.stale:
                if path not in finals:
                    _remove(path)
