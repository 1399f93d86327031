"""The mirrors of `rigidref validate` (docs/validation.md): each Python engine (MuJoCo, PyBullet,
Drake), run through `rigidref validate` as a user runs it, reads back from its own model the
masses, inertias, friction and step of the rigidref scene, and flies a free body as rigidref does
to the engine's integrator order.

The engines must be installed in this interpreter (`.ci/run` installs them into target/venv:
pip install mujoco pybullet drake); a missing engine fails these tests, it is not skipped. The
rigidref binary as in test_rigidref_trace.py.
"""

import importlib
import json
import os
import pathlib
import shutil
import subprocess
import sys

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
ENGINES = {"mujoco": "mujoco", "pybullet": "pybullet", "drake": "pydrake"}


def rigidref_bin():
    path = pathlib.Path(os.environ.get("RIGIDREF_BIN", ROOT / "target" / "release" / "rigidref"))
    if not path.is_file():
        pytest.fail(f"{path} is missing: run `cargo build --release` (or cargo test --release) first")
    return str(path)


def require(engine):
    try:
        importlib.import_module(ENGINES[engine])
    except ImportError as e:
        pytest.fail(f"{engine} is not installed in {sys.executable} ({e}): "
                    "pip install mujoco pybullet drake (.ci/run does)")


def validate(engine, scenes, out, scene_dir=ROOT / "scenes"):
    run = subprocess.run([rigidref_bin(), "validate", "--engines", engine, "--scenes", ",".join(scenes),
                          "--scene-dir", str(scene_dir), "--python", sys.executable, "--out", str(out)],
                         capture_output=True, text=True, cwd=ROOT)
    assert run.returncode == 0, run.stderr
    report = json.loads((out / "report.json").read_text())
    status = {e["engine"]: e for e in report["engines"]}
    assert status[engine]["missing"] is None, status[engine]
    return report


def runs(report, scene, engine):
    s = next(s for s in report["scenes"] if s["file"] == scene + ".json")
    return [r for r in s["runs"] if r["engine"] == engine]


def trace(path):
    lines = pathlib.Path(path).read_text().splitlines()
    return json.loads(lines[0]), [json.loads(line) for line in lines[1:]]


@pytest.mark.parametrize("engine", sorted(ENGINES))
def test_the_engines_model_reads_back_the_scenes_masses_inertias_mu_and_step(engine, tmp_path):
    require(engine)
    scenes = ["dragged_cube", "box_stack", "sphere_drop", "projectile"]
    report = validate(engine, scenes, tmp_path / "out")
    for name in scenes:
        description = json.loads((tmp_path / "out" / "descriptions" / f"{name}.mirror.json").read_text())
        for run in runs(report, name, engine):
            assert run["status"] == {"status": "ran"}, (name, run["settings"], run["status"])
            back = run["model"]["readback"]
            # The step and gravity are set, not computed: equal to the bit.
            assert back["h"] == description["h"], (name, back["h"])
            assert back["gravity"] == description["gravity"], (name, back["gravity"])
            for b, d in zip(back["bodies"], description["bodies"]):
                # Masses exact; inertias through each engine's principal-axis storage, to
                # round-off of the largest moment.
                assert b["mass"] == pytest.approx(d["mass"], rel=1e-14), name
                scale = np.abs(d["inertia"]).max()
                assert np.abs(np.array(b["inertia"]) - np.array(d["inertia"])).max() <= 1e-12 * scale, \
                    (name, b["inertia"], d["inertia"])
                if description["check_collisions"]:
                    # Each engine's combination rule applied to what it holds gives the scene's mu.
                    for mu in b["mu"]:
                        for ground in back["ground_mu"]:
                            pair = {"mujoco": max(mu, ground), "pybullet": mu * ground,
                                    "drake": 2 * mu * ground / (mu + ground)}[engine]
                            assert pair == pytest.approx(description["mu"], rel=1e-14), (name, b["mu"])


def final_pose(path):
    _, records = trace(path)
    last = records[-1]["bodies"][0]
    return np.array(last["x"]), np.array(last["R"])


@pytest.mark.parametrize("engine", sorted(ENGINES))
def test_free_flight_agrees_with_rigidref_to_the_engines_integrator_order(engine, tmp_path):
    """The spinning projectile at dt and dt/2: the engine's final position and rotation differ
    from rigidref's either by round-off (the same symplectic Euler step) or by a term of first
    order or higher (halving the step at least halves the difference)."""
    require(engine)
    differences = []
    for k, dt in enumerate([0.01, 0.005]):
        scene_dir = tmp_path / f"h{k}" / "scenes"
        scene_dir.mkdir(parents=True)
        (scene_dir / "data").symlink_to(ROOT / "scenes" / "data")
        scene = json.loads((ROOT / "scenes" / "projectile.json").read_text())
        scene["sim_parameters"][0]["dt"] = dt
        (scene_dir / "projectile.json").write_text(json.dumps(scene))
        out = tmp_path / f"h{k}" / "out"
        validate(engine, ["projectile"], out, scene_dir)
        ours = final_pose(out / "traces" / "rigidref" / "projectile.jsonl")
        default = next(r for r in runs(json.loads((out / "report.json").read_text()), "projectile", engine)
                       if r["settings"] == "default")
        theirs = final_pose(out / default["trace"])
        differences.append((np.linalg.norm(theirs[0] - ours[0]), np.abs(theirs[1] - ours[1]).max()))
    print(engine, "free flight |Δx|, |ΔR| at h and h/2:", differences)
    for what, (coarse, fine) in zip(("position", "rotation"), zip(*differences)):
        if coarse < 1e-9:
            assert fine < 1e-9, (engine, what, coarse, fine)  # the same step: round-off at both
        else:
            # Every engine here steps first-order (semi-implicit Euler) like rigidref: the
            # difference shrinks at least at first order (second where both share the first-order
            # term, as Drake's rotation does).
            order = np.log2(coarse / fine)
            assert order > 0.8, (engine, what, coarse, fine, order)
