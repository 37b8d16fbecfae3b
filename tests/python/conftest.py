"""What the Python module's tests share: where the build put gonio and the
samples (ctest passes them in the environment), the corpus, and the rule
that a missing prerequisite skips, but fails under CI=true (as
GONIO_MISSING does for the C++ suites)."""
import json
import os
import pathlib
import subprocess

import pytest


def missing(what):
    """Skips the test because `what` is missing; fails it under CI=true."""
    if os.environ.get("CI") in ("true", "1"):
        pytest.fail(f"missing under CI=true (a skip would pass unseen): {what}")
    pytest.skip(f"missing: {what} (skipped; under CI=true this fails)")


def _env_path(name):
    value = os.environ.get(name)
    if not value:
        missing(f"${name} (ctest sets it; run these tests with `ctest -L python`)")
    return pathlib.Path(value)


@pytest.fixture(scope="session")
def gonio_exe():
    return _env_path("GONIO_EXECUTABLE")


@pytest.fixture(scope="session")
def samples():
    return _env_path("GONIO_SAMPLES_DIR")


@pytest.fixture(scope="session")
def curves():
    return _env_path("GONIO_SOURCE_DIR") / "samples" / "curves"


@pytest.fixture(scope="session")
def corpus():
    root = pathlib.Path(os.environ.get("GONIO_CORPUS") or os.environ.get("GONIO_CORPUS_DIR", ""))
    if not str(root) or not root.is_dir():
        missing(f"the photometric corpus (../shared/corpus beside the checkout, or $GONIO_CORPUS): {root}")
    return root


def run_gonio(exe, *args):
    """The gonio command: (exit code, stdout, stderr)."""
    r = subprocess.run([str(exe), *map(str, args)], capture_output=True, text=True)
    return r.returncode, r.stdout, r.stderr


def info_json(exe, path, *args):
    code, out, err = run_gonio(exe, "info", "--json", path, *args)
    assert code == 0, err
    return json.loads(out)
