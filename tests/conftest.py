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
