"""The Python trace module against rigidref itself (docs/grading.md §"From a Python simulator").

The rigidref binary is RIGIDREF_BIN if set, else target/release/rigidref (which
`cargo test --release` builds before pytest runs).
"""

import json
import math
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python"))

from rigidref_trace import TraceWriter, write_problem  # noqa: E402


def rigidref_bin():
    path = pathlib.Path(os.environ.get("RIGIDREF_BIN", ROOT / "target" / "release" / "rigidref"))
    if not path.is_file():
        pytest.fail(f"{path} is missing: run `cargo build --release` (or cargo test --release) first")
    return str(path)


def rigidref(*args, cwd=None):
    return subprocess.run([rigidref_bin(), *map(str, args)], capture_output=True, text=True, cwd=cwd)


def skew(a):
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


def exp_so3(theta):
    """exp([theta]x), as rigidref's rotation::exp_so3 (Rodrigues, series near 0)."""
    angle_sq = float(theta @ theta)
    if angle_sq < 1e-8:
        a = 1.0 - angle_sq / 6.0 + angle_sq * angle_sq / 120.0
        b = 0.5 - angle_sq / 24.0 + angle_sq * angle_sq / 720.0
    else:
        angle = math.sqrt(angle_sq)
        a, b = math.sin(angle) / angle, (1.0 - math.cos(angle)) / angle_sq
    k = skew(theta)
    return np.eye(3) + k * a + k @ k * b


def reorthonormalize(r):
    return r @ (np.eye(3) * 3.0 - r.T @ r) * 0.5


def free_flight_in_python(scene_path, out_path, steps):
    """The assignment's explicit spatial-frame step, as a student's starter would write it:
    v += h g; omega += h Jw^-1 (tau - omega x Jw omega); x += h v; R <- exp(h [omega]x) R."""
    scene = json.loads(scene_path.read_text())
    params = scene["sim_parameters"][0]
    dt, substeps = params["dt"], params.get("substeps", 1)
    g = np.array(params.get("gravity", [0, 0, 0]), dtype=float)
    h = dt / substeps
    bodies = []
    for b in scene["bodies"]:
        body_file = json.loads((scene_path.parent / (b["file_root"] + ".json")).read_text())
        bodies.append({
            "name": b["name"], "mass": body_file["mass"], "J0": np.array(body_file["J"]),
            "x": np.array(b["x0"], float), "R": np.array(b.get("R0", np.eye(3)), float),
            "v": np.array(b.get("v0", [0, 0, 0]), float),
            "omega": np.array(b.get("omega0", [0, 0, 0]), float),
        })
    with TraceWriter(out_path, scene=params["name"], dt=dt, substeps=substeps, gravity=g,
                     bodies=[(b["name"], b["mass"], b["J0"]) for b in bodies]) as trace:
        def record(step):
            trace.record(step, step * dt, [(b["x"], b["R"], b["v"], b["omega"]) for b in bodies])
        record(0)
        for step in range(1, steps + 1):
            for _ in range(substeps):
                for b in bodies:
                    b["v"] = b["v"] + g * h
                    jw = b["R"] @ b["J0"] @ b["R"].T
                    jw_inv = b["R"] @ np.linalg.inv(b["J0"]) @ b["R"].T
                    b["omega"] = b["omega"] + jw_inv @ (-np.cross(b["omega"], jw @ b["omega"])) * h
                    b["x"] = b["x"] + b["v"] * h
                    b["R"] = reorthonormalize(exp_so3(b["omega"] * h) @ b["R"])
            record(step)


def test_free_flight_trace_from_python_agrees_with_rigidref_to_round_off(tmp_path):
    scene = ROOT / "scenes" / "tumbling_brick.json"
    ref = tmp_path / "ref.jsonl"
    out = rigidref("run", scene, "--time", "5", "--quiet", "--out", ref)
    assert out.returncode == 0, out.stderr
    mine = tmp_path / "python.jsonl"
    free_flight_in_python(scene, mine, 500)
    # To round-off: 1e-9 in every quantity (m, rad, m/s, rad/s; relative for energy, momentum).
    out = rigidref("compare", ref, mine, "--tolerance", "1e-9")
    assert out.returncode == 0, out.stdout + out.stderr
    assert "verdict          agree" in out.stdout
    # A student's slip (the gyroscopic term's sign) is caught, naming the body and the time.
    bad = tmp_path / "bad.jsonl"
    lines = mine.read_text().splitlines()
    records = [json.loads(l) for l in lines[1:]]
    for r in records[100:]:
        r["bodies"][0]["omega"][0] += 1e-3 * (r["step"] - 99)
    bad.write_text("\n".join([lines[0]] + [json.dumps(r) for r in records]) + "\n")
    out = rigidref("compare", ref, bad)
    assert out.returncode == 1, out.stdout + out.stderr
    assert 'body 0 ("block") angular velocity' in out.stderr


def test_trace_writer_refuses_non_finite_states(tmp_path):
    with TraceWriter(tmp_path / "t.jsonl", scene="s", dt=0.01, gravity=[0, -9.8, 0],
                     bodies=[("b", 1.0, np.eye(3))]) as trace:
        with pytest.raises(ValueError, match="x of 'b' is not finite"):
            trace.record(0, 0.0, [([0, float("nan"), 0], np.eye(3), [0, 0, 0], [0, 0, 0])])


def rotate_tangents(problem, k, angle):
    """The same contact problem with contact k's tangent basis turned by `angle` about n."""
    c, s = math.cos(angle), math.sin(angle)
    q = np.array([[1, 0, 0], [0, c, s], [0, -s, c]])
    contact = problem["contacts"][k]
    contact["jacobian"] = [(q @ np.array(j)).tolist() for j in contact["jacobian"]]
    contact["b"] = (q @ np.array(contact["b"])).tolist()
    contact["lambda0"] = (q @ np.array(contact["lambda0"])).tolist()
    if "solution" in problem:
        problem["solution"]["lambda"][k] = (q @ np.array(problem["solution"]["lambda"][k])).tolist()


def test_problem_files_written_from_python_are_compared_up_to_the_tangent_basis(tmp_path):
    dumps = tmp_path / "problems"
    out = rigidref("run", ROOT / "scenes" / "box_stack.json", "--time", "0.05", "--quiet",
                   "--out", tmp_path / "t.jsonl", "--dump-problems", dumps)
    assert out.returncode == 0, out.stderr
    ref_path = sorted(dumps.glob("*.json"))[0]
    ref = json.loads(ref_path.read_text())
    # Rewritten through the module, from the parts a simulator has.
    mine = tmp_path / "mine.json"
    write_problem(
        mine,
        bodies=[(b["inverse_mass"], b["velocity"]) for b in ref["bodies"]],
        contacts=ref["contacts"],
        friction=ref["friction"],
        lam=ref["solution"]["lambda"],
    )
    out = rigidref("compare-problem", ref_path, mine)
    assert out.returncode == 0, out.stdout + out.stderr
    # Another simulator's tangent basis, turned by a random angle about n at every contact.
    rotated = json.loads(mine.read_text())
    rng = np.random.default_rng(20261123)
    for k in range(len(rotated["contacts"])):
        rotate_tangents(rotated, k, rng.uniform(0, 2 * math.pi))
    (tmp_path / "rotated.json").write_text(json.dumps(rotated))
    out = rigidref("compare-problem", ref_path, tmp_path / "rotated.json")
    assert out.returncode == 0, out.stdout + out.stderr
    # One Jacobian column's sign flipped (body 1's ω_x at contact 2): differs, and says where.
    flipped = json.loads(mine.read_text())
    for row in flipped["contacts"][2]["jacobian"][0]:
        row[3] = -row[3]
    (tmp_path / "flipped.json").write_text(json.dumps(flipped))
    out = rigidref("compare-problem", ref_path, tmp_path / "flipped.json")
    assert out.returncode == 1, out.stdout + out.stderr
    assert "contact 2: normal row, body 1 entry 3 (ω_x)" in out.stderr
