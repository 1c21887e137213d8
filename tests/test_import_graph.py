"""The import graph of the packages has no circle.

The graph is read from the source with ``ast``: every import counts, those inside functions too.
``import a.b`` and ``from a import b`` where ``a.b`` is a module are edges to that module;
``from a import name`` (a function, class or constant) is an edge to the package ``a``'s
``__init__``. Layers (aircraft data below the models, the models below the analyses, loads and
interfaces) keep it a tree of layers; a circle names the modules that must be split.
"""
from __future__ import annotations

import ast
import graphlib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("mbs", "fmu", "viewer")


def modules(root: Path, packages) -> dict[str, Path]:
    """Dotted name -> file of every module of ``packages`` under ``root`` (a package is its ``__init__``)."""
    out = {}
    for package in packages:
        for path in sorted((root / package).rglob("*.py")):
            parts = path.relative_to(root).with_suffix("").parts
            out[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return out


def owner(name: str, known) -> str | None:
    """The module of ``known`` that ``name`` lies in: itself or its nearest parent; None outside."""
    while name and name not in known:
        name = name.rpartition(".")[0]
    return name or None


def source_of(node: ast.ImportFrom, module: str, package: bool) -> str:
    """The absolute name of the module a ``from ... import`` statement in ``module`` reads from."""
    if not node.level:
        return node.module
    base = module if package else module.rpartition(".")[0]
    for _ in range(node.level - 1):
        base = base.rpartition(".")[0]
    return ".".join(filter(None, (base, node.module)))


def targets(node, module: str, package: bool, known) -> set[str]:
    """The modules of ``known`` that the import statement ``node`` in ``module`` depends on."""
    if isinstance(node, ast.Import):
        found = {owner(a.name, known) for a in node.names}
    else:
        source = source_of(node, module, package)
        found = {f"{source}.{a.name}" if f"{source}.{a.name}" in known else owner(source, known)
                 for a in node.names}
    return found - {None, module}


def graph(root: Path, packages) -> dict[str, set[str]]:
    """Module -> the modules it imports, over ``packages`` under ``root``."""
    known = modules(root, packages)
    out = {}
    for module, path in known.items():
        tree = ast.parse(path.read_text(), str(path))
        imports = (n for n in ast.walk(tree) if isinstance(n, (ast.Import, ast.ImportFrom)))
        out[module] = set().union(*(targets(n, module, path.name == "__init__.py", known) for n in imports))
    return out


def circle(edges: dict[str, set[str]]) -> list[str]:
    """One circle of ``edges`` as ``[a, b, ..., a]`` (each module imports the next); [] when there is none."""
    try:
        graphlib.TopologicalSorter(edges).prepare()
    except graphlib.CycleError as exc:
        return exc.args[1][::-1]
    return []


def test_the_import_graph_has_no_circle():
    found = circle(graph(ROOT, PACKAGES))
    assert not found, "import circle: " + " -> ".join(found)


def _package(root: Path, files: dict[str, str]) -> Path:
    for name, text in files.items():
        (root / name).parent.mkdir(parents=True, exist_ok=True)
        (root / name).write_text(text)
    return root


def test_a_circle_through_an_import_inside_a_function_is_found(tmp_path):
    root = _package(tmp_path, {"pkg/__init__.py": "", "pkg/low.py": "def f():\n    from pkg import high\n",
                               "pkg/high.py": "import pkg.low\n", "pkg/side.py": "from .low import f\n"})
    edges = graph(root, ["pkg"])
    assert edges["pkg.side"] == {"pkg.low"} and edges["pkg.low"] == {"pkg.high"}
    assert set(circle(edges)) == {"pkg.low", "pkg.high"} and circle(edges)[0] == circle(edges)[-1]


def test_a_circle_is_named_in_the_direction_of_the_imports():
    found = circle({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}})
    assert found in (["a", "b", "c", "a"], ["b", "c", "a", "b"], ["c", "a", "b", "c"])


def test_a_name_imported_from_a_package_is_an_edge_to_its_init(tmp_path):
    root = _package(tmp_path, {"pkg/__init__.py": "from pkg.data import load\n",
                               "pkg/data.py": "def load():\n    from pkg import check\n"})
    assert graph(root, ["pkg"])["pkg.data"] == {"pkg"}
    assert set(circle(graph(root, ["pkg"]))) == {"pkg", "pkg.data"}


def test_layers_without_a_circle_pass(tmp_path):
    root = _package(tmp_path, {"pkg/__init__.py": "", "pkg/low.py": "import numpy\n",
                               "pkg/sub/__init__.py": "from .. import low\n", "pkg/sub/high.py": "from ..low import x\n"})
    edges = graph(root, ["pkg"])
    assert edges == {"pkg": set(), "pkg.low": set(), "pkg.sub": {"pkg.low"}, "pkg.sub.high": {"pkg.low"}}
    assert circle(edges) == []
