import json
import os
import sys
import zipfile
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent))
# ... and for the fresh processes that run the test hosts (python -m fmu_hosts.MODULE)
os.environ["PYTHONPATH"] = os.pathsep.join(filter(None, [str(Path(__file__).parent), os.environ.get("PYTHONPATH")]))
pytest_plugins = ["browser_fixtures"]  # one browser for the session, shared by every browser test module

import mbs  # noqa: E402
from mbs.models.demo import spinning_rotor  # noqa: E402


@pytest.fixture(scope="session", autouse=True)
def user_data_folder(tmp_path_factory):
    """An empty user data folder for the session (``XDG_DATA_HOME``): the trims that ``heli
    simulate`` and ``heli trim --write`` store go there, not into the user's own."""
    os.environ["XDG_DATA_HOME"] = str(tmp_path_factory.mktemp("share"))
    return os.environ["XDG_DATA_HOME"]


@pytest.fixture(scope="session")
def rotor_model():
    return spinning_rotor()


@pytest.fixture(scope="session")
def rotor_vm(rotor_model):
    return mbs.build(rotor_model, "vm")


@pytest.fixture(scope="session")
def rotor_compiled(rotor_model):
    return mbs.build(rotor_model, "compiled")


@pytest.fixture(scope="session")
def rotor_compiled32(rotor_model):
    return mbs.build(rotor_model, "compiled", "float32")


@pytest.fixture(scope="session")
def python_fmu() -> Path:
    """The pythonfmu FMU of the default scene family (built once, cached on disk)."""
    from fmu import build

    return build.ensure_fmu(build.DEFAULT_SCENES)[0]


@pytest.fixture(scope="session")
def python_spec(python_fmu) -> dict:
    """The ``spec.json`` shipped in :func:`python_fmu` (variables, scenes, limits)."""
    with zipfile.ZipFile(python_fmu) as z:
        return json.loads(z.read("resources/heli_models/spec.json"))


@pytest.fixture(scope="session")
def user_shell(tmp_path_factory):
    """A user's folder after set-up command 1, shared by the README's and the docs' blocks."""
    from user_shell import UserShell

    return UserShell(tmp_path_factory.mktemp("user"))
