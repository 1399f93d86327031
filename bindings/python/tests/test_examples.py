"""The examples run as scripts, and the docs list every test here."""

import re
import subprocess
import sys

from conftest import ROOT


def test_the_box_stack_example_runs_and_reproduces_the_steps_lambda(tmp_path):
    example = ROOT / "bindings" / "python" / "examples" / "box_stack.py"
    done = subprocess.run([sys.executable, str(example), "--time", "0.5", "--plot", str(tmp_path / "e.png")],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "same lambda as the step: True" in done.stdout
    assert "|w_clarabel - w_Newton|" in done.stdout


def test_every_python_test_is_listed_in_the_verification_table():
    table = (ROOT / "docs" / "verification.md").read_text()
    here = ROOT / "bindings" / "python" / "tests"
    missing = []
    for path in sorted(here.glob("test_*.py")):
        for name in re.findall(r"^def (test_\w+)\(", path.read_text(), re.M):
            ref = f"bindings/python/tests/{path.name}::{name}"
            if ref not in table:
                missing.append(ref)
    assert not missing, "docs/verification.md does not list: " + ", ".join(missing)
