"""Integrity and writability of cached artefacts (compiled models, FMUs).

Every artefact written to the cache gets a digest file next to it, ``<name>.digest``: one
JSON object with the artefact's SHA-256 and size, recorded at build time (:func:`record`).
Before a cached artefact is used it is checked against that record (:func:`problem`,
:func:`verified`); a truncated or changed artefact, or one without a record, is rebuilt,
never used. :func:`writable_dir` checks a cache folder before anything is built into it,
and :func:`replace_dir` installs a freshly built folder in place of a bad one.

Only the standard library is used.
"""
from __future__ import annotations

import hashlib
import json
import os
import shutil
import tempfile
from pathlib import Path

DIGEST_SUFFIX = ".digest"
_CHUNK = 1 << 20


class CacheNotWritable(ValueError):
    """A cache folder cannot be created or written (a ValueError: a bad setting)."""


class CacheCorrupt(ValueError):
    """A cached artefact does not match the digest recorded when it was built."""


def digest_path(path: Path) -> Path:
    """The digest file of the artefact ``path``: ``<path>.digest`` in the same folder."""
    path = Path(path)
    return path.with_name(path.name + DIGEST_SUFFIX)


def sha256(path: Path) -> str:
    """Hex SHA-256 of the file ``path``, read in chunks."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(_CHUNK), b""):
            h.update(chunk)
    return h.hexdigest()


def record(path: Path) -> Path:
    """Write the SHA-256 and size of the artefact ``path`` to its digest file (atomically,
    so a reader never sees half a record); returns the digest file."""
    path = Path(path)
    target = digest_path(path)
    text = json.dumps({"sha256": sha256(path), "size": path.stat().st_size}) + "\n"
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{target.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w") as f:
            f.write(text)
        os.chmod(tmp, path.stat().st_mode & 0o666)  # readable by whoever may read the artefact
        os.replace(tmp, target)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return target


def problem(path: Path) -> str | None:
    """Why the artefact ``path`` must not be used (missing, no or unreadable digest file,
    size or SHA-256 differing from the record), or None when it matches its record."""
    path = Path(path)
    if not path.is_file():
        return f"{path} is missing"
    try:
        recorded = json.loads(digest_path(path).read_text())
        want_hash, want_size = str(recorded["sha256"]), int(recorded["size"])
    except FileNotFoundError:
        return f"{path} has no digest file {digest_path(path).name}"
    except (OSError, ValueError, TypeError, KeyError) as exc:
        return f"the digest file of {path} is unreadable ({exc})"
    size = path.stat().st_size
    if size != want_size:
        return f"{path} has {size} bytes, {want_size} were recorded (truncated or changed)"
    if sha256(path) != want_hash:
        return f"the SHA-256 of {path} differs from the recorded one (changed)"
    return None


def verified(path: Path) -> bool:
    """True when the artefact ``path`` exists and matches the digest recorded for it."""
    return problem(path) is None


def writable_dir(path: Path, what: str = "cache") -> Path:
    """Create the folder ``path`` (and its parents) and check, by writing a temporary file
    in it, that it can be written; returns ``path``. Raises :class:`CacheNotWritable` with a
    one-line message naming the folder and ``what`` it is for."""
    path = Path(path)
    try:
        path.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=path, prefix=".write-test-"):
            pass
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        raise CacheNotWritable(f"the {what} folder {path} is not writable ({reason}); set MBS_CACHE_DIR "
                               "to a writable folder") from None
    return path


def replace_dir(new: Path, dest: Path) -> Path:
    """Install the freshly built folder ``new`` as ``dest`` (same file system), moving an
    existing ``dest`` aside first and deleting it; a process that loaded files of the old
    folder keeps them. If another process installs ``dest`` first, ``new`` is discarded.
    Returns ``dest``."""
    new, dest = Path(new), Path(dest)
    stale = Path(tempfile.mkdtemp(dir=dest.parent, prefix=".stale-"))
    try:
        try:
            dest.rename(stale / dest.name)
        except FileNotFoundError:
            pass
        try:
            new.rename(dest)
        except OSError:  # another process installed its build in between; keep that one
            shutil.rmtree(new, ignore_errors=True)
    finally:
        shutil.rmtree(stale, ignore_errors=True)
    return dest
