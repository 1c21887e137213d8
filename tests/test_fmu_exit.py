"""The pythonfmu FMU in C hosts linked to libpython exits cleanly, every time: 100 fresh
processes of a host that starts Python itself (it aborted at exit in every run with pythonfmu
0.7.0's double release of its Python state) and 100 of a host that leaves starting Python to
pythonfmu's library (aborted or not depending on the heap layout)."""
from __future__ import annotations

import pytest

from fmu import build
from fmu_hosts import exit_check

RUNS = 100


@pytest.fixture(scope="module")
def host(tmp_path_factory):
    return exit_check.compile_python_host(tmp_path_factory.mktemp("exit-host") / "python_host")


@pytest.fixture(scope="module")
def unzipped(tmp_path_factory) -> dict:
    return exit_check.unzip(build.ensure_fmu(build.DEFAULT_SCENES)[0], tmp_path_factory.mktemp("exit-fmu"))


@pytest.mark.parametrize("mode", ["embed", "linked"])
def test_c_host_linked_to_libpython_never_aborts_at_exit(host, unzipped, mode):
    res = exit_check.runs(host, unzipped, mode, RUNS)
    assert res["codes"] == {0: RUNS}, res
