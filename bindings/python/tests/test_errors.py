"""Bad input from Python is an exception carrying the CLI's one-line message, never a crash."""

import pytest

import rigidref
from conftest import cli_error


def test_a_missing_scene_is_a_scene_error_with_the_clis_message(cli, tmp_path):
    missing = tmp_path / "none.json"
    with pytest.raises(rigidref.SceneError) as e:
        rigidref.World.load(missing)
    assert str(e.value) == cli_error(cli, "run", missing, "--quiet", "--out", tmp_path / "t.jsonl")


def test_a_malformed_scene_is_a_scene_error_with_the_clis_message(cli, tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text('{"sim_parameters": {"dt": 0.01,}')
    with pytest.raises(rigidref.SceneError) as e:
        rigidref.World.load(bad)
    assert str(e.value) == cli_error(cli, "run", bad, "--quiet", "--out", tmp_path / "t.jsonl")
    neither = tmp_path / "neither.json"
    neither.write_text('{"bodies": []}')
    with pytest.raises(rigidref.SceneError, match="neither a 3D scene"):
        rigidref.World.load(neither)


def test_a_bad_override_value_is_a_scene_error_with_the_clis_message(root, cli, tmp_path):
    scene = root / "scenes" / "box_stack.json"
    with pytest.raises(rigidref.SceneError) as e:
        rigidref.World.load(scene, {"pgs_iterations": -3})
    assert str(e.value) == cli_error(cli, "run", scene, "--set", "pgs_iterations=-3", "--quiet",
                                     "--out", tmp_path / "t.jsonl")


def test_a_broken_image_is_a_scene_error_with_the_clis_message(cli, tmp_path):
    png = tmp_path / "broken.png"
    png.write_bytes(b"\x89PNG\r\n\x1a\n not an image")
    with pytest.raises(rigidref.SceneError) as e:
        rigidref.World.load(png)
    assert str(png) in str(e.value)
    assert str(e.value) == cli_error(cli, "run", png, "--quiet", "--out", tmp_path / "t.jsonl")


def test_bad_solver_options_are_errors_not_crashes():
    import numpy as np
    J = np.zeros((3, 6)); J[0, 1] = 1; J[1, 0] = 1; J[2, 2] = 1
    p = rigidref.ContactProblem.from_arrays(J, np.eye(6), [-1, 0, 0], 0.3)
    with pytest.raises(rigidref.ProblemError, match="order"):
        rigidref.solve_pgs(p, order="sideways")
    with pytest.raises(rigidref.ProblemError, match="tolerance"):
        rigidref.solve_pgs(p, tolerance=float("nan"))
    with pytest.raises(rigidref.ProblemError, match="fixed_normal"):
        rigidref.solve_clarabel(p, formulation="box_fixed")
    with pytest.raises(rigidref.ProblemError, match="fixed_normal: NaN is not a normal impulse"):
        rigidref.solve_clarabel(p, formulation="box_fixed", fixed_normal=[float("nan")])
    with pytest.raises(rigidref.ProblemError, match="tolerance"):
        rigidref.solve_clarabel(p, tolerance=0.0)
    with pytest.raises(rigidref.ProblemError, match="friction_model"):
        rigidref.ContactProblem.from_arrays(J, np.eye(6), [-1, 0, 0], 0.3, friction_model="pyramid")
