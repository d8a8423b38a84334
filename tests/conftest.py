def pytest_addoption(parser):
    parser.addoption("--update-golden", action="store_true",
                     help="rewrite generated/ from the current code instead of comparing bytes")


import pytest  # noqa: E402


@pytest.fixture(scope="session", autouse=True)
def _compiled_code_cache(tmp_path_factory):
    """Compiled generated C goes to a per-run cache, not the user's ~/.cache/symgen."""
    import os

    old = os.environ.get("SYMGEN_CACHE")
    os.environ["SYMGEN_CACHE"] = str(tmp_path_factory.mktemp("symgen-cache"))
    yield
    if old is None:
        os.environ.pop("SYMGEN_CACHE", None)
    else:
        os.environ["SYMGEN_CACHE"] = old


@pytest.fixture(scope="session", autouse=True)
def _scalar_batch_loops():
    """Generated C compiled through the ctypes binding takes its scalar batch loop here
    (``SYMGEN_NO_LANES``): the lanes double the compile time of every generated file, and
    ``test_codegen_lanes.py`` compiles and checks them itself, on every built-in, with explicit
    flags. A user's binding compiles the lanes."""
    import os

    old = os.environ.get("SYMGEN_NO_LANES")
    os.environ.setdefault("SYMGEN_NO_LANES", "1")
    yield
    if old is None:
        os.environ.pop("SYMGEN_NO_LANES", None)
