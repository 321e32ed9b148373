"""Shared fixtures: the repository's example data and the `edmd` binary."""

import os
import pathlib
import shutil
import signal

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
DATA = ROOT / "examples" / "data"


def edmd_binary():
    """The `edmd` program: $EDMD_BIN, else the workspace's release or debug build, else PATH."""
    candidates = [os.environ.get("EDMD_BIN")]
    candidates += [str(ROOT / "target" / p / "edmd") for p in ("release", "debug")]
    candidates.append(shutil.which("edmd"))
    for c in candidates:
        if c and os.access(c, os.X_OK):
            return c
    return None


@pytest.fixture
def edmd_cli():
    exe = edmd_binary()
    if exe is None:
        if os.environ.get("EDMD_REQUIRE_CLI"):
            pytest.fail("the edmd binary is needed (cargo build --bin edmd) and was not found")
        pytest.skip("no edmd binary (cargo build --bin edmd, or set EDMD_BIN)")
    return exe


@pytest.fixture
def ctrl_c():
    """Ctrl-C raises KeyboardInterrupt for the test's duration. Python installs that handler only
    if SIGINT is not ignored when it starts, and a shell ignores SIGINT in the commands it runs
    in the background (`bash -c '... &'`), so a test that interrupts itself with SIGINT would
    otherwise run on for ever there."""
    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, old)
