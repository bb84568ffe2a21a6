# The module under test is the one the build made: ctest puts its folder first on PYTHONPATH
# (python/CMakeLists.txt), with HAIL_BENCH naming hail-bench and HAIL_SOURCE_DIR the tree.
import os
import pathlib

import pytest

import hail  # noqa: F401  (an import error here names the module path problem once)

SOURCE_DIR = pathlib.Path(os.environ.get("HAIL_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))


@pytest.fixture
def source_dir():
    return SOURCE_DIR


@pytest.fixture
def hail_bench():
    path = os.environ.get("HAIL_BENCH")
    if not path or not os.path.exists(path):
        pytest.skip("hail-bench not built (HAIL_BENCH unset)")
    return path
