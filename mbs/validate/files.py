"""A validation file by name or path: the packaged ones (``mbs/validate/data``), read as TOML
(:func:`mbs.validate.data.from_dict`) or CSV (:func:`mbs.validate.csvdata.load_csv`) by its suffix."""
from __future__ import annotations

import sys
from pathlib import Path

from mbs.validate.csvdata import load_csv
from mbs.validate.data import Validation, ValidationError, from_dict

tomllib = __import__("tomllib" if sys.version_info >= (3, 11) else "tomli")

PACKAGED = Path(__file__).resolve().parent / "data"


def packaged() -> list[str]:
    """Names of the validation files shipped with the package."""
    return sorted(p.stem for p in PACKAGED.glob("*.toml"))


def resolve(text: str) -> Path:
    """The validation file ``text``: a path, or the name of a packaged one."""
    path = Path(text).expanduser()
    if path.is_file():
        return path
    if (PACKAGED / f"{text}.toml").is_file():
        return PACKAGED / f"{text}.toml"
    if path.exists():
        raise ValidationError(f"{text!r} is not a file")
    raise ValidationError(f"no validation file {text!r}: give a .toml or .csv file or one of the packaged "
                          f"validations ({', '.join(packaged())})")


def load(text: str | Path) -> Validation:
    """Read and check the validation file ``text`` (a path or a packaged name)."""
    path = resolve(str(text))
    if path.suffix.lower() == ".csv":
        return load_csv(path)
    try:
        raw = tomllib.loads(path.read_text())
    except (ValueError, UnicodeDecodeError) as exc:
        raise ValidationError(f"{path}: not a TOML file ({exc})") from None
    return from_dict(raw, path)
