"""Fixtures of the vkvo pytest suites (run by ctest, see CMakeLists.txt beside this file)."""
import os
import pathlib
import subprocess

import pytest
import vkvo

SOURCE_DIR = pathlib.Path(__file__).resolve().parents[2]


def shared_data_dir():
    """$VKVO_DATA, else ../shared next to the checkout (as tests/common/test_support.cpp); None when absent."""
    env = os.environ.get("VKVO_DATA")
    if env:
        return pathlib.Path(env) if os.path.isdir(env) else None
    sibling = SOURCE_DIR.parent / "shared"
    return sibling if sibling.is_dir() else None


@pytest.fixture(scope="session")
def shared_data():
    """A function from a path inside the shared data to the full path; skips the test when it is absent."""
    root = shared_data_dir()

    def require(relative):
        if root is None:
            pytest.skip("shared data not found: set VKVO_DATA or put ../shared next to the checkout "
                        f"(needed: {relative})")
        path = root / relative
        if not path.exists():
            pytest.skip(f"shared data lacks {path}")
        return path

    return require


def required_env(name):
    value = os.environ.get(name)
    if not value:
        pytest.fail(f"${name} is not set: run this suite through ctest (ctest -R python)")
    return value


@pytest.fixture(scope="session")
def random_packs(tmp_path_factory):
    """A folder with random_superpoint.vkvopack and random_superglue.vkvopack (random weights)."""
    out = tmp_path_factory.mktemp("packs")
    subprocess.run([required_env("VKVO_TEST_PACK_TOOL"), str(out)], check=True)
    return out


@pytest.fixture(scope="session")
def cli():
    """The `vkvo` executable of this build."""
    return required_env("VKVO_CLI")


@pytest.fixture(autouse=True)
def no_validation_messages():
    """Every test fails on a Vulkan validation message (ctest sets VKVO_VALIDATION=1), as the C++ suites do."""
    before = vkvo._validation_message_count()
    yield
    assert vkvo._validation_message_count() == before, "Vulkan validation messages: see the log"
