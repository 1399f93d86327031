"""python/cadoux_fixed_point.py: Cadoux's fixed point on de Saxcé's cone problem
(docs/problem-library.md §"RockPile_tob1", **A convex-programming route**).

The study of RockPile_tob1 reports what this map reaches there; these tests check that the map
is the right one: it solves small Siconos problems to Siconos' tolerance on its own, and an exact
Coulomb answer is its fixed point (a wrong sign in de Saxcé's shift, or the antisymmetric part
of W taken the wrong way, fails both). Skipped, with the reason, where Clarabel or the rigidref
module is missing (.ci/run installs both)."""

import json
import pathlib
import subprocess
import sys

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python"))
pytest.importorskip("clarabel", reason="Clarabel not installed (pip install clarabel)")
pytest.importorskip("scipy", reason="scipy not installed")
rigidref = pytest.importorskip("rigidref", reason="the rigidref module is not installed "
                               "(pip install ./bindings/python)")
import cadoux_fixed_point as cfp  # noqa: E402

DATA = ROOT / "tests" / "data" / "siconos"
SCRIPT = ROOT / "python" / "cadoux_fixed_point.py"
# The project's acceptance of an answer: Siconos' error at most 1e-8 (docs/problem-library.md).
SICONOS_TOLERANCE = 1e-8


def run_script(*args, timeout=300):
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, args)], capture_output=True,
                          text=True, timeout=timeout)


def load(name):
    problem, w, q, mu = cfp.local_form(DATA / name)
    n = len(mu)
    return problem, w, q, mu, lambda lam: rigidref.siconos_error(problem, lam.reshape(n, 3))


@pytest.mark.parametrize("name,bound", [("Rover1039.dat", 40), ("NESpheres_10_1.dat", 80)])
def test_the_fixed_point_alone_solves_small_problems_to_siconos_tolerance(name, bound):
    # Measured: Rover1039 23 iterations, NESpheres_10_1 50 (damping 0.5); the bound leaves room
    # for Clarabel's version, not for a map that does not converge.
    _, w, q, mu, error = load(name)
    lam, best, errors = cfp.fixed_point(w, q, mu, bound, 0.5, error, report=lambda _: None,
                                        tolerance=SICONOS_TOLERANCE)
    assert best <= SICONOS_TOLERANCE, (name, errors[-5:])
    assert error(lam) == best


@pytest.mark.parametrize("name", ["Rover1039.dat", "NESpheres_10_1.dat",
                                  "Confeti-ex13-4contact-Fc3D-SBM.dat"])
def test_an_exact_coulomb_answer_is_a_fixed_point_of_the_map(name):
    # Newton's answer has Siconos' error ~1e-16; one cone program from it (s from its ‖w_T‖)
    # must return an answer as good to the interior-point method's accuracy (~1e-9 relative).
    problem, w, q, mu, error = load(name)
    exact = np.asarray(rigidref.solve_newton(problem, tolerance=1e-13).lam, dtype=float).ravel()
    assert error(exact) <= 1e-12
    lam, best, errors = cfp.fixed_point(w, q, mu, 1, 1.0, error, report=lambda _: None,
                                        start=exact)
    assert len(errors) == 1 and errors[0] <= 1e-7, (name, errors)
    # The contact velocities are unique where λ may not be (redundant contacts).
    assert np.abs((w @ lam + q) - (w @ exact + q)).max() <= 1e-6 * max(1.0, np.abs(q).max())


def test_without_the_fixed_point_the_polish_starts_from_zero(tmp_path):
    out = tmp_path / "zero.json"
    r = run_script(DATA / "Rover1039.dat", "--iterations", "0", "--polish", "1", "--out", out)
    assert r.returncode == 0, r.stderr
    doc = json.loads(out.read_text())
    assert doc["fixed_point_errors"] == [] and doc["error"] <= SICONOS_TOLERANCE
    assert "starts from λ = 0" in r.stdout


def test_the_script_polishes_and_writes_its_answer(tmp_path):
    out = tmp_path / "answer with space.json"
    r = run_script(DATA / "Rover1039.dat", "--iterations", "5", "--polish", "1", "--out", out)
    assert r.returncode == 0, r.stderr
    doc = json.loads(out.read_text())
    assert len(doc["fixed_point_errors"]) == 5 and len(doc["lambda"]) == 4
    assert doc["polish"][0]["error"] <= SICONOS_TOLERANCE
    assert doc["error"] == min([doc["polish"][0]["error"], *doc["fixed_point_errors"]])


@pytest.mark.parametrize("args,message", [
    (["--damping", "0"], "--damping 0.0: must be in (0, 1]"),
    (["--iterations", "-1"], "--iterations -1: must be at least 0"),
    (["--iterations", "0"], "--iterations 0 needs --polish (Newton from λ = 0, restarted from its best)"),
    (["--polish", "-1"], "--polish -1: must be at least 0"),
])
def test_bad_settings_are_one_line_errors(args, message):
    r = run_script(DATA / "Rover1039.dat", *args, timeout=120)
    assert r.returncode != 0 and r.stderr.strip().splitlines() == [message]


def test_an_unreadable_problem_is_a_one_line_error_naming_the_file(tmp_path):
    bad = tmp_path / "not a problem.dat"
    bad.write_text("3\n1\nnonsense\n")
    r = run_script(bad, timeout=120)
    lines = r.stderr.strip().splitlines()
    assert r.returncode != 0 and len(lines) == 1 and str(bad) in lines[0], r.stderr
