"""World: a scene loaded and stepped from Python is the CLI's run, to the bit."""

import json
import time

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
    # While one thread steps, another counts in Python. Were the interpreter held for the whole
    # step, the counter would move only at the 0.2 s signal checks (a few thousand counts);
    # released, it counts all along: 10⁵ is far below what one core counts in the time (≥ 10⁶ in
    # 0.5 s even on a loaded machine) and far above what the checks alone allow.
    import threading
    world = rigidref.World.load(root / "scenes" / "box_stack.json")
    world.step(10)
    start = time.perf_counter()
    world.step(200)
    per_step = (time.perf_counter() - start) / 200
    stepping = threading.Thread(target=world.step, args=(max(200, int(0.5 / per_step)),))
    count = 0
    stepping.start()
    while stepping.is_alive():
        count += 1
    stepping.join()
    assert count > 100_000, count
    # And two worlds on two threads end as each alone: nothing is shared between worlds.
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


def test_a_step_that_ends_non_finite_raises_and_the_world_refuses_to_go_on(root, cli, tmp_path):
    # The explicit gyroscopic term's energy grows without bound at this spin and overflows at
    # step 39 (as in the CLI's test of the same scene).
    (tmp_path / "scenes").mkdir()
    scene = tmp_path / "scenes" / "s.json"
    scene.write_text(json.dumps({
        "sim_parameters": [{"name": "t", "dt": 0.01, "gravity": [0, -9.8, 0], "substeps": 1,
                            "check_collisions": False}],
        "bodies": [{"name": "b", "file_root": str(root / "scenes" / "data" / "block"),
                    "x0": [0, 1, 0], "omega0": [60, 40, 20]}]}))
    world = rigidref.World.load(scene)
    with pytest.raises(rigidref.SceneError) as e:
        world.step(100)
    message = str(e.value)
    assert "non-finite" in message and 'body 0 ("b")' in message and "at step" in message
    from conftest import cli_error
    assert message == cli_error(cli, "run", scene, "--steps", 100, "--quiet", "--out", tmp_path / "t.jsonl").split(
        "; the trace up to")[0]
    assert world.steps < 100
    with pytest.raises(rigidref.SceneError) as again:
        world.step()
    assert str(again.value) == message


def test_ctrl_c_stops_a_long_step_and_keeps_the_steps_done(root):
    import _thread
    import signal
    import threading
    world = rigidref.World.load(root / "scenes" / "box_stack.json")
    start = time.perf_counter()
    world.step(200)
    per_step = (time.perf_counter() - start) / 200
    # A process started in the background (as CI may run the suite) inherits SIGINT ignored, and
    # then Python has no handler and interrupt_main does nothing: install Python's own here.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    # About 30 s of steps if nothing stopped them: long against the 0.5 s the timer waits, short
    # enough that a broken stop fails the test instead of hanging it.
    n = world.steps + int(30.0 / per_step)
    timer = threading.Timer(0.5, _thread.interrupt_main)
    try:
        timer.start()
        with pytest.raises(KeyboardInterrupt):
            world.step(n - world.steps)
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    assert 200 < world.steps < n
    # The world is whole: it steps on from where it was stopped, as one that was never stopped.
    k = world.steps
    world.step(3)
    again = rigidref.World.load(root / "scenes" / "box_stack.json")
    again.step(k + 3)
    assert world.state()["x"].tolist() == again.state()["x"].tolist()
