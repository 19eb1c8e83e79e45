"""Shared fixtures of the Python tests (run by ctest, label python, or by hand:
PYTHONPATH=build/<dir>/python /usr/bin/python3 -m pytest python/tests).

Environment: PPCR_DATA_DIR (default ../shared/data beside the repository) holds the real scans,
read in place; PPCR_CLI is the ppcr_cli of the same build (ctest sets both). Tests needing one
that is absent are skipped with a message naming it, or fail under CI=true or PPCR_STRICT=1
(tools/test.sh in CI), where every test must run. A file missing from a data folder that is
there fails: the data set is broken, not absent.
"""
import os
import pathlib

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]


def strict():
    """True where nothing may be skipped (CI=true, or PPCR_STRICT=1)."""
    return os.environ.get("CI") == "true" or os.environ.get("PPCR_STRICT") == "1"


def skip_or_fail(reason):
    if strict():
        pytest.fail(f"{reason}; CI=true or PPCR_STRICT=1 requires it", pytrace=False)
    pytest.skip(reason)


@pytest.fixture(scope="session")
def data_dir():
    path = pathlib.Path(os.environ.get("PPCR_DATA_DIR", REPO.parent / "shared" / "data"))
    if not path.is_dir():
        skip_or_fail(f"real scans not found: {path} (set PPCR_DATA_DIR)")
    return path


@pytest.fixture(scope="session")
def cli():
    path = os.environ.get("PPCR_CLI")
    if not path or not os.access(path, os.X_OK):
        skip_or_fail("ppcr_cli not given: set PPCR_CLI to the build's tools/ppcr_cli")
    return path
