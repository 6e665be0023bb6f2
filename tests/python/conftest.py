"""Fixtures several test files share."""
import pytest

from benchmark_folder import make_benchmark_folder


@pytest.fixture(scope="session")
def benchmark_folder(tmp_path_factory):
    """A small bench_dynamic-style folder (tests/python/benchmark_folder.py), made once per session."""
    return make_benchmark_folder(tmp_path_factory.mktemp("benchmark"))
