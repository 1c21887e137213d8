import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent))

import mbs  # noqa: E402
from mbs.models.demo import spinning_rotor  # noqa: E402


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
