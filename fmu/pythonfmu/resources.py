"""What the slave reads from the FMU's resources: the build's spec, the virtual-machine evaluator,
and the core's package in ``sys.path`` / ``sys.modules`` kept pointing at a folder that exists."""
from __future__ import annotations

import json
import sys
from pathlib import Path

from fmu.pythonfmu.errors import BadValue
from mbs.backends.compiled import CompiledSystem
from mbs.backends.info import ModelInfo


def load_vm(folder: Path, info: ModelInfo):
    """The virtual-machine evaluator from the CasADi functions saved at build time (needs
    casadi on the host)."""
    import casadi as ca

    from mbs.backends.system import System
    from mbs.backends.vm import VMSystem

    vm = VMSystem.__new__(VMSystem)
    vm.functions = {f.stem: ca.Function.load(str(f)) for f in sorted((folder / "vm").glob("*.casadi"))}
    System.__init__(vm, info, "float64")
    return vm


def repoint_package(resources: str | None) -> None:
    """Point this package's modules at ``resources`` if the folder they were first imported
    from has gone (an importer deleted an earlier copy of this FMU; the code is identical,
    the package name carries its digest), so that later imports (e.g. the VM) still work."""
    top = CompiledSystem.__module__.split(".")[0]
    own = Path(resources or "") / top
    if not own.is_dir():
        return
    for name, module in list(sys.modules.items()):
        paths = getattr(module, "__path__", None) if name.split(".")[0] == top else None
        if paths and not all(Path(p).is_dir() for p in paths):
            module.__path__ = [str(own.joinpath(*name.split(".")[1:]))]


def keep_one(entry: str | None) -> None:
    """Keep a single ``entry`` in ``sys.path``: pythonfmu inserts the resources folder at
    every instantiate and never removes it."""
    hits = [k for k, p in enumerate(sys.path) if entry and p == entry]
    for k in reversed(hits[1:]):
        del sys.path[k]


def read_spec(path: Path) -> dict:
    """The build's spec (variables, scenes, limits); raises BadValue naming the file."""
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError) as exc:
        raise BadValue(f"{path} cannot be read: {type(exc).__name__}: {exc}") from exc
