"""The shape of the product packages: no ``fmu`` module over 700 lines, and the test hosts and
probes (``tests/fmu_hosts``) outside the product, which never imports them or the test tools."""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PRODUCT = ("mbs", "fmu", "viewer")
TEST_ONLY = ("fmu_hosts", "tests", "pytest", "conftest")
LIMIT = 700  # lines of one fmu module


def imported_roots(path: Path) -> set[str]:
    """Top-level names of every absolute import in ``path`` (those inside functions too)."""
    roots = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            roots |= {alias.name.partition(".")[0] for alias in node.names}
        elif isinstance(node, ast.ImportFrom) and not node.level:
            roots.add(node.module.partition(".")[0])
    return roots


def test_no_fmu_module_over_700_lines():
    sizes = {p.relative_to(ROOT).as_posix(): len(p.read_text().splitlines()) for p in (ROOT / "fmu").rglob("*.py")}
    assert sizes and max(sizes.values()) <= LIMIT, {k: n for k, n in sizes.items() if n > LIMIT}


@pytest.mark.parametrize("package", PRODUCT)
def test_the_product_never_imports_the_test_hosts(package):
    offenders = {p.relative_to(ROOT).as_posix(): sorted(imported_roots(p) & set(TEST_ONLY))
                 for p in (ROOT / package).rglob("*.py")}
    assert not {k: v for k, v in offenders.items() if v}


def test_the_hosts_and_probes_live_under_tests():
    hosts = {p.name for p in (ROOT / "tests" / "fmu_hosts").iterdir()}
    assert {"probe.py", "probe_fmi.py", "script_host.c", "python_host.c", "exit_check.py"} <= hosts
    assert not [p for p in (ROOT / "fmu").rglob("*") if p.name in hosts and p.name != "__init__.py"]


def test_the_import_reader_sees_imports_inside_functions(tmp_path):
    module = tmp_path / "m.py"
    module.write_text("import os\n\ndef f():\n    from fmu_hosts import probe\n")
    assert imported_roots(module) == {"os", "fmu_hosts"}
