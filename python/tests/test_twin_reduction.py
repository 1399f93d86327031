"""python/twin_reduction.py: leaving one contact of a near-duplicate pair out
(docs/problem-library.md §"RockPile_tob1").

What is checked: the per-contact error is Siconos' (its norm over the contacts, divided as
Siconos divides, is `rigidref.siconos_error`); a contact duplicated exactly is found as the twin
of the contact that carries the error; a problem Newton solves is left whole; bad settings are
one-line errors. The RockPile answer the method found is checked in the Rust suite
(`rockpile_has_an_exact_answer_that_leaves_one_of_three_near_duplicate_contacts_unloaded`).
Skipped, with the reason, where the rigidref module is missing (.ci/run installs it)."""

import pathlib
import subprocess
import sys

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python"))
rigidref = pytest.importorskip("rigidref", reason="the rigidref module is not installed "
                               "(pip install ./bindings/python)")
pytest.importorskip("scipy", reason="scipy not installed")
import cadoux_fixed_point as cfp  # noqa: E402
import twin_reduction as tr  # noqa: E402

DATA = ROOT / "tests" / "data" / "siconos"
SCRIPT = ROOT / "python" / "twin_reduction.py"


def run_script(*args, timeout=300):
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, args)], capture_output=True,
                          text=True, timeout=timeout)


def test_per_contact_errors_make_siconos_error():
    problem, w, q, mu = cfp.local_form(DATA / "Rover1039.dat")
    n = len(mu)
    lam = np.random.default_rng(3).uniform(-1.0, 2.0, size=(n, 3))
    e = tr.per_contact_error(w, q, mu, lam)
    u = w @ lam.ravel() + q
    scale = max(np.linalg.norm(q), np.linalg.norm(lam), np.linalg.norm(u))
    # Relative 1e-12: the same sums in another order.
    assert np.linalg.norm(e) / scale == pytest.approx(rigidref.siconos_error(problem, lam),
                                                      rel=1e-12)


def test_an_exact_duplicate_is_the_twin_of_the_contact_that_carries_the_error():
    _, w, q, mu = cfp.local_form(DATA / "Rover1039.dat")
    n = len(mu)
    # Contact n duplicates contact 0: W's rows and columns repeated, q and μ too.
    idx = np.r_[np.arange(3 * n), 0, 1, 2]
    w2 = w[np.ix_(idx, idx)]
    e = np.zeros(n + 1)
    e[n] = 1.0
    assert tr.twins(w2, e, 1e-8) == [(0, n)]
    # No twin within the cosine asked: no pair.
    e = np.zeros(n + 1)
    e[1] = 1.0
    near = tr.twins(w2, e, 1e-8)
    assert all(1 not in pair for pair in near)


def test_a_problem_newton_solves_is_left_whole():
    out = run_script(DATA / "Rover1039.dat", "--polish", "0")
    assert out.returncode == 0, out.stderr
    assert "contacts left out []" in out.stdout and "without" not in out.stdout


def test_bad_settings_are_one_line_errors():
    out = run_script(DATA / "Rover1039.dat", "--cosine", "2")
    assert out.returncode != 0 and len(out.stderr.strip().splitlines()) == 1
    out = run_script(DATA / "no-such-file.dat")
    assert out.returncode != 0 and "no-such-file.dat" in out.stderr
    assert len(out.stderr.strip().splitlines()) == 1


def test_leave_out_names_contacts_in_range():
    out = run_script(DATA / "Rover1039.dat", "--leave-out", "0,x")
    assert out.returncode != 0 and len(out.stderr.strip().splitlines()) == 1
    out = run_script(DATA / "Rover1039.dat", "--leave-out", "100000")
    assert out.returncode != 0 and "numbered 0 to" in out.stderr
