"""The mirrors of `rigidref validate` (docs/validation.md): each Python engine (MuJoCo, PyBullet,
Drake), run through `rigidref validate` as a user runs it, reads back from its own model the
masses, inertias, friction and step of the rigidref scene, and flies a free body as rigidref does
to the engine's integrator order.

The engines must be installed in this interpreter (`.ci/run` installs them into target/venv:
pip install mujoco pybullet drake pymunk); a missing engine fails these tests, it is not skipped. The
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


def test_pymunk_reads_back_the_2d_scenes_masses_moments_mu_and_step_and_writes_the_2d_rows(tmp_path):
    """`rigidref validate --engines pymunk` runs the three 2D scenes in pymunk (both settings):
    pymunk's model read back has every body's mass and moment (to the bit), static for pinned, one
    circle of radius sqrt(2)/2 per block at the block's offset, Chipmunk's product of the shapes'
    frictions equal to the scene's mu to 1e-15, the scene's gravity and step; every run is judged."""
    try:
        importlib.import_module("pymunk")
    except ImportError as e:
        pytest.fail(f"pymunk is not installed in {sys.executable} ({e}): pip install pymunk (.ci/run does)")
    out = tmp_path / "out"
    report = validate("pymunk", ["block_slide", "bar_topple", "stack_rest"], out)
    assert [s["file"] for s in report["scenes"]] == ["block_slide.json", "bar_topple.json", "stack_rest.json"]
    for s in report["scenes"]:
        stem = s["file"][:-5]
        desc = json.loads((out / "descriptions" / f"{stem}.mirror.json").read_text())
        for r in runs(report, stem, "pymunk"):
            assert r["status"]["status"] == "ran", r["status"]
            # Every observable is judged but the criteria, which are reported (as in 3D).
            assert all(m["passed"] is not None for m in r["measured"] if not m["key"].startswith("criterion_")), r["measured"]
            model = json.loads((out / r["trace"]).with_suffix(".model.json").read_text())
            settings = model["settings"]
            assert settings["h"] == desc["h"] == desc["dt"] / desc["substeps"]
            assert settings["gravity"] == desc["gravity"]
            assert settings["iterations"] == (10 if r["settings"] == "default" else 100)
            if r["settings"] == "accurate":
                assert settings["collision_slop"] == desc["slop"]
            for b, got in zip(desc["bodies"], model["readback"]):
                assert got["static"] == b["pinned"]
                if not b["pinned"]:
                    assert (got["mass"], got["moment"]) == (b["mass"], b["inertia"])
                assert got["shapes"] == len(b["blocks"])
                assert got["radius"] == desc["block_radius"] == 2 ** -0.5
                assert got["offsets"] == b["blocks"]
                assert abs(got["pair_friction"] - desc["mu"]) <= 1e-15
                assert got["pair_elasticity"] == 0.0
            header, records = trace(out / r["trace"])
            assert header["dimension"] == 2 and len(records) == desc["frames"] + 1


def test_pymunks_per_point_impulses_sum_to_its_arbiters_total_and_give_the_2d_criteria(tmp_path):
    """The pymunk mirror's per-point contacts (Chipmunk's jnAcc, jtAcc read from its cpArbiter)
    are faithful: on a body resting on a static row of discs, every arbiter's points' impulses
    n jn + t jt (t = perp(n), the impulse on body b) sum to pymunk's public Arbiter.total_impulse
    to round-off (up to its sign for a swapped arbiter), and each point lies at Chipmunk's own
    contact points. Run through `rigidref validate`, every 2D run reports the three criteria and
    rigidref's exact run has them at round-off (1e-9: Newton's tolerance is far below it, velocities
    are O(1) blocks/time)."""
    try:
        pymunk = importlib.import_module("pymunk")
    except ImportError as e:
        pytest.fail(f"pymunk is not installed in {sys.executable} ({e}): pip install pymunk (.ci/run does)")
    sys.path.insert(0, str(ROOT / "python" / "mirrors"))
    import pymunk_mirror
    space = pymunk.Space()
    space.gravity = (0.0, 1.0)
    ground = pymunk.Body(body_type=pymunk.Body.STATIC)
    discs = [pymunk.Circle(ground, 2 ** -0.5, offset=(float(i), 0.0)) for i in range(-3, 4)]
    block = pymunk.Body(2.0, 1.0)
    block.position = (0.3, -1.35)
    block.velocity = (0.4, 0.0)
    mine = [pymunk.Circle(block, 2 ** -0.5, offset=(dx, 0.0)) for dx in (-0.5, 0.5)]
    for s in discs + mine:
        s.friction = 0.33 ** 0.5
    space.add(ground, *discs, block, *mine)
    checked = 0
    for _ in range(60):
        space.step(0.0125)
        contacts = pymunk_mirror.arbiter_contacts([ground, block], space)
        arbiters = []
        block.each_arbiter(arbiters.append)
        total = np.zeros(2)
        for arbiter in arbiters:
            # Seen from body.each_arbiter, shapes[0] is the body's own; total_impulse is the
            # impulse on it (Chipmunk flips its sign for a swapped arbiter).
            sign = 1.0 if arbiter.shapes[0].body is block else -1.0
            total += sign * np.array(arbiter.total_impulse)
        mine_total = np.zeros(2)
        for c in contacts:
            n = np.array(c["n"])
            t = np.array([-n[1], n[0]])
            mine_total += (c["lambda"][0] * n + c["lambda"][1] * t) * (1.0 if c["bodies"][0] == 1 else -1.0)
        assert np.abs(mine_total - total).max() <= 1e-15 + 1e-12 * np.abs(total).max(), (mine_total, total)
        checked += len(contacts)
    assert checked > 0
    out = tmp_path / "out"
    report = validate("pymunk", ["block_slide", "bar_topple", "stack_rest"], out)
    for s in report["scenes"]:
        for r in s["runs"]:
            keys = {m["key"]: m["value"] for m in r["measured"]}
            for k in ("criterion_primal", "criterion_dual", "criterion_complementarity"):
                assert keys.get(k) is not None, (s["file"], r["engine"], r["settings"], k)
                if r["engine"] == "rigidref":
                    assert keys[k] <= 1e-9, (s["file"], k, keys[k])
        assert (out / "plots" / s["file"].replace(".json", ".svg")).is_file()
