"""Shared fixtures of the Python module's tests: the repository's root, and the `rigidref`
command built from the same sources (cargo build --release, once), to hold the module against."""

import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture(scope="session")
def cli():
    """The path of the release `rigidref` binary (built when absent)."""
    exe = ROOT / "target" / "release" / "rigidref"
    if not exe.exists():
        subprocess.run(["cargo", "build", "--release", "--quiet"], cwd=ROOT, check=True)
    return exe


def run_cli(cli, *args, check=True):
    """Runs the command; returns the completed process (stdout and stderr as text)."""
    done = subprocess.run([str(cli), *map(str, args)], capture_output=True, text=True)
    if check and done.returncode != 0:
        raise AssertionError(f"rigidref {' '.join(map(str, args))}: {done.stderr}")
    return done


def cli_error(cli, *args):
    """The CLI's one-line error for a command that fails: its stderr line after "error: "."""
    done = run_cli(cli, *args, check=False)
    assert done.returncode != 0, done.stdout
    lines = [l for l in done.stderr.splitlines() if l.startswith("error: ")]
    assert lines, done.stderr
    return lines[-1][len("error: "):]
