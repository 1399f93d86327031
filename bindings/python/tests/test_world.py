"""World: a scene loaded and stepped from Python is the CLI's run, to the bit."""

import json

import numpy as np
import pytest

import rigidref
from conftest import run_cli


def last_record(path):
    with open(path) as f:
        lines = f.read().splitlines()
    return json.loads(lines[-1])


@pytest.mark.parametrize("scene,time", [("box_stack", 1.0), ("tumbling_brick", 0.5)])
def test_a_3d_scene_stepped_from_python_ends_bit_identical_to_the_cli_run(root, cli, tmp_path, scene, time):
    path = root / "scenes" / f"{scene}.json"
    out = tmp_path / "t.jsonl"
    run_cli(cli, "run", path, "--time", time, "--out", out, "--quiet")
    record = last_record(out)
    world = rigidref.World.load(path)
    world.step(record["step"])
    s = world.state()
    # Bit for bit: the trace writes floats with round-trip precision, so == is the test.
    assert s["time"] == record["t"]
    for i, body in enumerate(record["bodies"]):
        assert s["x"][i].tolist() == body["x"]
        assert s["R"][i].tolist() == body["R"]
        assert s["v"][i].tolist() == body["v"]
        assert s["omega"][i].tolist() == body["omega"]
    assert s["energy"]["total"] == record["energy"]["total"]


def test_a_2d_image_stepped_from_python_ends_bit_identical_to_the_cli_run(root, cli, tmp_path):
    path = root / "scenes" / "blocks" / "stack.png"
    out = tmp_path / "t.jsonl"
    run_cli(cli, "run", path, "--steps", 120, "--out", out, "--quiet")
    record = last_record(out)
    world = rigidref.World.load(path)
    assert world.dimension == 2
    world.step(120)
    s = world.state()
    for i, body in enumerate(record["bodies"]):
        assert s["x"][i].tolist() == body["x"]
        assert s["q"][i] == body["theta"]
        assert s["v"][i].tolist() == body["v"]
        assert s["omega"][i] == body["omega"]


def test_overrides_are_the_clis_set_pairs(root, cli, tmp_path):
    path = root / "scenes" / "box_stack.json"
    out = tmp_path / "t.jsonl"
    run_cli(cli, "run", path, "--steps", 50, "--set", "pgs_iterations=7", "--set", "friction_model=cone",
            "--out", out, "--quiet")
    record = last_record(out)
    world = rigidref.World.load(path, {"pgs_iterations": 7, "friction_model": "cone"})
    world.step(50)
    assert world.state()["x"].tolist() == [b["x"] for b in record["bodies"]]
    assert world.solver_settings()["pgs"]["iterations"] == 7
    plain = rigidref.World.load(path)
    plain.step(50)
    assert plain.state()["x"].tolist() != world.state()["x"].tolist()


def test_state_contacts_and_solves_have_their_documented_shapes(root):
    world = rigidref.World.load(root / "scenes" / "box_stack.json")
    world.step(30)
    n = len(world.body_names)
    s = world.state()
    assert s["x"].shape == (n, 3) and s["R"].shape == (n, 3, 3) and s["x"].dtype == np.float64
    assert s["x"].flags["C_CONTIGUOUS"]
    c = world.contacts()
    k = len(c["depth"])
    assert k > 0
    assert c["bodies"].shape == (k, 2) and c["point"].shape == (k, 3) and c["lam"].shape == (k, 3)
    solves = world.last_solves()
    assert solves and solves[-1].lam.tolist() == c["lam"].tolist()
    assert solves[-1].problem.num_contacts == k
    assert set(solves[-1].criteria) == {"primal", "dual", "complementarity", "signorini",
                                        "cone_boundary", "max_dissipation", "max"}
    assert world.time == pytest.approx(30 * world.dt)


def test_step_releases_the_interpreter_to_other_threads(root):
    # Two worlds stepped on two threads end as one world stepped alone: nothing shared.
    import threading
    worlds = [rigidref.World.load(root / "scenes" / "box_stack.json") for _ in range(2)]
    threads = [threading.Thread(target=w.step, args=(40,)) for w in worlds]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    alone = rigidref.World.load(root / "scenes" / "box_stack.json")
    alone.step(40)
    for w in worlds:
        assert w.state()["x"].tolist() == alone.state()["x"].tolist()


def test_ctrl_c_stops_a_long_step_and_keeps_the_steps_done(root):
    import _thread
    import threading
    world = rigidref.World.load(root / "scenes" / "box_stack.json")
    timer = threading.Timer(0.5, _thread.interrupt_main)
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        world.step(10**9)
    timer.cancel()
    assert 0 < world.steps < 10**9
    # The world is whole: it steps on from where it was stopped, as one that was never stopped.
    k = world.steps
    world.step(3)
    again = rigidref.World.load(root / "scenes" / "box_stack.json")
    again.step(k + 3)
    assert world.state()["x"].tolist() == again.state()["x"].tolist()
