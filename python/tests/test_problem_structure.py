"""python/problem_structure.py: Cadoux's strict-feasibility margin of a contact problem and the
variants written beside it (docs/problem-library.md §"RockPile_tob1").

The margins are checked on two-contact problems whose answer is known in closed form, so that
the study's reading of RockPile_tob1 rests on a calculation that can fail. Skipped, with the
reason printed, where Clarabel is not installed (.ci/run installs it)."""

import json
import pathlib
import subprocess
import sys

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python"))
import problem_structure  # noqa: E402

clarabel = pytest.importorskip("clarabel", reason="Clarabel not installed (pip install clarabel)")

# One body between two contacts of opposite normals along one free direction: w_n1 = y1 − y2 + q1,
# w_n2 = −y1 + y2 + q2, so w_n1 + w_n2 = q1 + q2 whatever the impulses, and the best margin is
# (q1 + q2)/2 (the tangent rows are decoupled and can be made zero). Solver tolerance: Clarabel's
# default ~1e-8 relative, so 1e-6 absolute on margins of order 1.
TOLERANCE = 1e-6


def two_contact_problem(q1, q2, mu=0.5):
    eye = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    minus = [[-1, 0, 0], [0, -1, 0], [0, 0, 1]]
    return {"format": "rigidref-contact-problem", "version": 1, "form": "local",
            "rows_per_contact": 3, "friction": "cone",
            "W": [{"row": 0, "col": 0, "block": eye}, {"row": 0, "col": 1, "block": minus},
                  {"row": 1, "col": 0, "block": minus}, {"row": 1, "col": 1, "block": eye}],
            "contacts": [{"q": [q1, 0, 0], "mu": mu}, {"q": [q2, 0, 0], "mu": mu}]}


@pytest.mark.parametrize("q1,q2", [(-1.0, -1.0), (-1.0, 1.5), (0.2, -0.2)])
def test_margin_is_half_the_sum_of_the_two_opposed_normal_velocities(tmp_path, q1, q2):
    path = tmp_path / "p.json"
    path.write_text(json.dumps(two_contact_problem(q1, q2)))
    w, q, mu, _ = problem_structure.read_local(path)
    t = problem_structure.strict_feasibility_margin(w, q, mu)
    assert t == pytest.approx(min((q1 + q2) / 2, 1.0), abs=TOLERANCE)


def test_squeezed_body_is_not_strictly_feasible_and_is_said_so(tmp_path):
    path = tmp_path / "squeeze.json"
    path.write_text(json.dumps(two_contact_problem(-1.0, -1.0)))
    r = subprocess.run([sys.executable, str(ROOT / "python/problem_structure.py"), str(path)],
                       capture_output=True, text=True, check=True)
    assert "not strictly feasible" in r.stdout, r.stdout


def test_variants_symmetrise_w_and_replace_mu(tmp_path):
    problem = two_contact_problem(-1.0, 1.5)
    problem["W"][1]["block"] = [[-1, 0.25, 0], [0, -1, 0], [0, 0, 1]]  # asymmetric off-diagonal
    path = tmp_path / "p.json"
    path.write_text(json.dumps(problem))
    _, _, _, doc = problem_structure.read_local(path)
    problem_structure.write_variants(doc, tmp_path / "v", [0.3])
    w_sym, _, _, _ = problem_structure.read_local(tmp_path / "v" / "sym.json")
    w, _, _, _ = problem_structure.read_local(path)
    assert np.array_equal(w_sym, 0.5 * (w + w.T))
    assert not np.array_equal(w, w.T)
    _, _, mu, _ = problem_structure.read_local(tmp_path / "v" / "mu0.3.json")
    assert list(mu) == [0.3, 0.3]


@pytest.mark.parametrize("text,says", [(None, "cannot read"), ("{", "cannot read"),
                                       ('{"form": "body"}', "not a local-form problem"),
                                       ('{"form": "local", "rows_per_contact": 3}', "not a well-formed")])
def test_bad_input_is_a_one_line_error_naming_the_file(tmp_path, text, says):
    path = tmp_path / "a problem with spaces.json"
    if text is not None:
        path.write_text(text)
    r = subprocess.run([sys.executable, str(ROOT / "python/problem_structure.py"), str(path)],
                       capture_output=True, text=True)
    assert r.returncode == 1
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(str(path)) and says in lines[0], r.stderr
