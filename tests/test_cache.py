"""Cached artefacts are verified before use: a truncated or changed compiled model or FMU is
rebuilt, never used; a cached FMU needs no C compiler; an unwritable cache is a one-line
error (exit 2), not a traceback.

Every test works in its own cache folder (``MBS_CACHE_DIR``), never in the shared one.
"""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest

import mbs
from mbs import Hinge, Model
from mbs.backends import cache
from mbs.backends.compiled import CompiledSystem, compile_source, generate, library_problem

FAMILY = ("ground-run",)


def pendulum(mass: float = 1.0) -> Model:
    """The smallest model: one arm of ``mass`` (kg) on a hinge, under gravity."""
    m = Model("cache_pendulum", gravity=(0, 0, 9.81))
    m.add_body("arm", "world", Hinge((0, 1, 0)), mass=mass, com=(0.5, 0, 0), inertia=np.diag([0.01, 0.1, 0.1]))
    return m


def truncate(path: Path, keep: float = 0.5) -> None:
    """Replace ``path`` by its first half (a new file: one mapped by a process stays intact)."""
    tmp = path.with_name(path.name + ".part")
    tmp.write_bytes(path.read_bytes()[: int(path.stat().st_size * keep)])
    tmp.replace(path)


def compile_only(model: Model) -> tuple[Path, object]:
    """Compile ``model`` into the cache without loading the library in this process (a
    library loaded once stays loaded under its path); returns (folder, virtual machine)."""
    vm = mbs.build(model, "vm")
    return compile_source(generate(vm.functions, vm.info, "float64"), vm.info), vm


def heli(args: list[str], cwd: Path, **env: str) -> subprocess.CompletedProcess:
    """``heli ARGS`` in a fresh interpreter with ``env`` replacing the named variables."""
    return subprocess.run([sys.executable, "-m", "mbs", *args], cwd=cwd, capture_output=True, text=True,
                          env={**os.environ, **env}, timeout=600)


@pytest.fixture
def own_cache(tmp_path, monkeypatch) -> Path:
    folder = tmp_path / "cache"
    monkeypatch.setenv("MBS_CACHE_DIR", str(folder))
    return folder


# -- the cache module ---------------------------------------------------------------------------

def test_record_then_verify_detects_truncation_change_and_missing_digest(tmp_path):
    path = tmp_path / "artefact.bin"
    path.write_bytes(bytes(range(256)) * 40)
    assert not cache.verified(path) and "no digest file" in cache.problem(path)
    assert cache.record(path) == tmp_path / "artefact.bin.digest"
    assert cache.verified(path)
    data = bytearray(path.read_bytes())
    data[100] ^= 1
    path.write_bytes(bytes(data))
    assert "SHA-256" in cache.problem(path) and str(path) in cache.problem(path)
    truncate(path)
    assert "truncated" in cache.problem(path)
    cache.digest_path(path).write_text("{not json")
    assert "unreadable" in cache.problem(path)
    assert "missing" in cache.problem(tmp_path / "absent.bin")


@pytest.mark.parametrize("where", ["under /dev/null", "under a file"])
def test_writable_dir_names_the_folder_and_mbs_cache_dir(tmp_path, where):
    (tmp_path / "file").write_text("")
    folder = Path("/dev/null/mbs-cache") if where == "under /dev/null" else tmp_path / "file" / "cache"
    with pytest.raises(cache.CacheNotWritable) as err:
        cache.writable_dir(folder, "test cache")
    message = str(err.value)
    assert isinstance(err.value, ValueError) and "\n" not in message
    assert str(folder) in message and "MBS_CACHE_DIR" in message
    assert cache.writable_dir(tmp_path / "a" / "b") == tmp_path / "a" / "b" and (tmp_path / "a" / "b").is_dir()


# -- compiled models ----------------------------------------------------------------------------

@pytest.mark.parametrize("damage", ["truncated library", "changed description", "missing digest"])
def test_damaged_compiled_model_is_rebuilt_and_the_rebuild_runs(own_cache, damage):
    model = pendulum()
    folder, vm = compile_only(model)
    assert library_problem(folder) is None and folder.parent == own_cache
    if damage == "truncated library":
        truncate(folder / "model.so")
    elif damage == "changed description":
        (folder / "info.json").write_text((folder / "info.json").read_text() + " ")
    else:
        cache.digest_path(folder / "model.so").unlink()
    assert library_problem(folder) is not None
    again = mbs.build(model, "compiled")
    assert again.folder == folder and library_problem(folder) is None
    x0 = vm.x0() + 0.1
    np.testing.assert_allclose(again.step(x0, 0.0, 1e-3, n=10), vm.step(x0, 0.0, 1e-3, n=10), rtol=1e-12, atol=1e-12)
    assert not [p for p in own_cache.iterdir() if p.name.startswith(".")]  # no build or stale folder left


def test_a_built_model_is_found_again_from_its_functions_without_generating_code(own_cache, monkeypatch):
    """The index (mbs.backends.index) maps a key of the serialized functions to the library: a
    second build of the model generates no C; a changed model misses and is generated."""
    from mbs.backends import compiled, index

    first = mbs.build(pendulum(), "compiled")
    entries = list((own_cache / "index").iterdir())
    assert len(entries) == 1 and entries[0].read_text().strip() == first.folder.name
    generated = []
    real = compiled.generate
    monkeypatch.setattr(compiled, "generate", lambda *a: generated.append(a) or real(*a))
    again = mbs.build(pendulum(), "compiled")
    assert again.folder == first.folder and not generated
    heavier = pendulum(2.0)
    other = mbs.build(heavier, "compiled")
    assert len(generated) == 1 and other.folder != first.folder and len(list((own_cache / "index").iterdir())) == 2
    vm = mbs.build(heavier, "vm")
    x0 = vm.x0() + 0.1
    np.testing.assert_allclose(other.step(x0, 0.0, 1e-3, n=10), vm.step(x0, 0.0, 1e-3, n=10), rtol=1e-12, atol=1e-12)
    assert index.lookup("0" * 20) is None
    single = mbs.build(pendulum(), "compiled", dtype="float32")
    assert single.folder not in (first.folder, other.folder) and len(generated) == 2
    functions = {n: f for n, f in vm.functions.items() if not n.startswith(("step_", "incr_"))}
    keys = {index.key(functions, vm.info, "float64", (text,)) for text in ("rk4 as written", "rk4 changed")}
    assert len(keys) == 2  # the steps' code enters the key in their place


@pytest.mark.parametrize("entry", ["damaged library", "outside the cache", "empty"])
def test_an_index_entry_that_is_not_a_good_library_is_rebuilt(own_cache, monkeypatch, entry):
    from mbs.backends import compiled

    model = pendulum()
    folder, vm = compile_only(model)
    mbs.build(model, "compiled")
    (record,) = list((own_cache / "index").iterdir())
    if entry == "damaged library":
        truncate(folder / "model.so")
    else:
        record.write_text("../elsewhere\n" if entry == "outside the cache" else "")
    generated = []
    real = compiled.generate
    monkeypatch.setattr(compiled, "generate", lambda *a: generated.append(a) or real(*a))
    again = mbs.build(model, "compiled")
    assert generated and again.folder == folder and library_problem(folder) is None
    assert record.read_text().strip() == folder.name
    x0 = vm.x0() + 0.1
    np.testing.assert_allclose(again.step(x0, 0.0, 1e-3, n=10), vm.step(x0, 0.0, 1e-3, n=10), rtol=1e-12, atol=1e-12)


def test_compiled_system_refuses_a_library_that_fails_its_digest(own_cache, tmp_path):
    folder, _ = compile_only(pendulum())
    shipped = tmp_path / "shipped"  # as inside the FMU: no digest files, loaded unchecked
    shipped.mkdir()
    for name in ("model.so", "info.json"):
        shutil.copy2(folder / name, shipped / name)
    assert CompiledSystem(shipped).info.name == "cache_pendulum"
    truncate(folder / "model.so")
    with pytest.raises(cache.CacheCorrupt, match="refusing to load the compiled model in .*truncated"):
        CompiledSystem(folder)


def test_heli_announces_a_long_compile_once_and_not_when_quiet(own_cache, tmp_path, monkeypatch, capsys):
    from mbs.backends import compiled
    from mbs.cli import main

    monkeypatch.setattr(compiled, "ANNOUNCE_SOURCE_BYTES", 0)  # every compile counts as long here
    run = ["simulate", "single-blade", "--revs", "0.05", "--out", str(tmp_path / "out")]
    assert main([*run, "--quiet"]) == 0
    assert "compiling" not in capsys.readouterr().err
    shutil.rmtree(own_cache)
    assert main(run) == 0
    announced = [line for line in capsys.readouterr().err.splitlines() if line.startswith("compiling ")]
    assert len(announced) == 1 and "MB of C, once (cached in " in announced[0] and str(own_cache) in announced[0]
    assert main(run) == 0
    assert "compiling" not in capsys.readouterr().err  # cached now


def test_simulate_with_an_unwritable_cache_is_a_one_line_error(tmp_path):
    proc = heli(["simulate", "ground-run", "--revs", "0.01", "--out", str(tmp_path / "out"), "--quiet"], tmp_path,
                MBS_CACHE_DIR="/dev/null/mbs-cache")
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("heli simulate: error: ") and "/dev/null/mbs-cache" in lines[0]
    assert "MBS_CACHE_DIR" in lines[0]


# -- the FMU ------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def fmu_cache(tmp_path_factory) -> Path:
    """A cache folder holding the FMU of a family of one scene (built once, about 10 s)."""
    folder = tmp_path_factory.mktemp("fmu-cache")
    proc = heli(["fmu", "build", "--scenes", ",".join(FAMILY), "--out", str(folder / "out")], folder,
                MBS_CACHE_DIR=str(folder / "cache"))
    assert proc.returncode == 0, proc.stderr[-3000:]
    return folder / "cache"


@pytest.fixture
def fmu_copy(fmu_cache, tmp_path, monkeypatch) -> Path:
    """A private copy of :func:`fmu_cache`, set as ``MBS_CACHE_DIR``: tests may damage it."""
    folder = tmp_path / "cache"
    shutil.copytree(fmu_cache, folder, symlinks=True)
    monkeypatch.setenv("MBS_CACHE_DIR", str(folder))
    return folder


def only_python(tmp_path: Path) -> str:
    """A PATH holding nothing but ``python`` (no C compiler)."""
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    (bin_dir / "python").symlink_to(sys.executable)
    return str(bin_dir)


def fmpy_energy(fmu: Path, cwd: Path) -> float:
    """Total energy at the end of a short fmpy run of ``fmu`` (in a fresh interpreter)."""
    code = ("import sys; from fmpy import simulate_fmu; "
            "r = simulate_fmu(sys.argv[1], stop_time=0.01, output_interval=0.001, output=['total_energy']); "
            "print(float(r['total_energy'][-1]))")
    proc = subprocess.run([sys.executable, "-c", code, str(fmu)], cwd=cwd, capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return float(proc.stdout.strip().splitlines()[-1])


def test_cached_fmu_needs_no_compiler(fmu_copy, tmp_path):
    from fmu import build

    env = {**os.environ, "PATH": only_python(tmp_path), "MBS_CACHE_DIR": str(fmu_copy)}
    env.pop("CC", None)
    assert not any(shutil.which(cc, path=env["PATH"]) for cc in ("cc", "gcc", "clang"))
    proc = subprocess.run([sys.executable, "-m", "mbs", "fmu", "build", "--scenes", ",".join(FAMILY),
                           "--out", str(tmp_path / "out")], cwd=tmp_path, capture_output=True, text=True,
                          env=env, timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert "from the cache" in proc.stdout
    out = tmp_path / "out" / build.cached_path(FAMILY).name
    assert out.read_bytes() == build.cached_path(FAMILY).read_bytes()


def test_truncated_cached_fmu_is_rebuilt(fmu_copy, tmp_path):
    from fmu import build

    path = build.cached_path(FAMILY)
    assert build.fmu_problem(path) is None
    truncate(path)
    messages = []
    rebuilt, seconds = build.ensure_fmu(FAMILY, log=messages.append)
    assert rebuilt == path and seconds > 0 and build.fmu_problem(path) is None
    assert "rebuilding the cached FMU" in messages[0] and "truncated" in messages[0] and str(path) in messages[0]
    assert np.isfinite(fmpy_energy(path, tmp_path))


def test_fmu_with_a_corrupt_member_is_not_used(fmu_copy, tmp_path):
    from fmu import build

    path = build.cached_path(FAMILY)
    with zipfile.ZipFile(path) as z:
        info = max(z.infolist(), key=lambda i: i.compress_size)
    data = bytearray(path.read_bytes())
    data[info.header_offset + 30 + len(info.filename) + info.compress_size // 2] ^= 0xFF
    path.write_bytes(bytes(data))
    cache.record(path)  # the digest matches: only the zip's CRC check can tell
    assert build.fmu_problem(path) is not None


def test_force_never_ships_a_truncated_cached_library(fmu_copy, tmp_path):
    from fmu import build

    [library] = [p / "model.so" for p in fmu_copy.iterdir() if (p / "model.so").exists()]
    truncate(library)
    path, seconds = build.ensure_fmu(FAMILY, force=True)
    assert seconds > 0 and library_problem(library.parent) is None
    with zipfile.ZipFile(path) as z:
        [shipped] = [n for n in z.namelist() if n.endswith("/model.so")]
        assert z.read(shipped) == library.read_bytes()
    assert np.isfinite(fmpy_energy(path, tmp_path))


@pytest.mark.parametrize("where", ["under /dev/null", "under a file"])
def test_fmu_build_with_an_unwritable_cache_is_a_one_line_error(tmp_path, where):
    (tmp_path / "file").write_text("")
    folder = "/dev/null/mbs-cache" if where == "under /dev/null" else str(tmp_path / "file" / "cache")
    proc = heli(["fmu", "build", "--scenes", ",".join(FAMILY), "--out", str(tmp_path / "out")], tmp_path,
                MBS_CACHE_DIR=folder)
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("heli fmu build: error: ") and folder in lines[0], lines
    assert "MBS_CACHE_DIR" in lines[0] and "Traceback" not in proc.stderr
