"""The no-slip rattleback (python/noslip_rattleback.py), and rigidref's rattleback against it
(docs/contact.md §"The rattleback"). The rigidref binary as in test_rigidref_trace.py."""

import csv
import json
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python"))

import noslip_rattleback as nr  # noqa: E402

# RK4 at 2 ms: the reversal time is the same to the step at 0.5, 1 and 2 ms (4.85 s), the energy
# drift 7.5e-5 J of 0.105 J (2e-7 J at 0.5 ms); six seconds cover the reversal.
STEP, SECONDS = 2e-3, 6.0


def test_the_noslip_model_keeps_its_energy_and_does_not_slip():
    body = nr.rattleback(0.8)
    series = nr.simulate(body, [0.05, -3.0, 0.05], SECONDS, STEP)
    e0 = body.energy(body.start([0.05, -3.0, 0.05]))
    drift = max(abs(e) for _, _, e, _ in series)
    slip = max(np.linalg.norm(s) for *_, s in series)
    # RK4's error at 2 ms through the reversal: 1e-3 of the energy, 1 mm/s of contact velocity.
    assert drift < 1e-3 * e0, drift
    assert slip < 1e-3, slip


def test_the_noslip_model_reverses_one_way_and_the_tilt_decides_which():
    # δ = +0.8°: clockwise (ω_y < 0) reverses, counter-clockwise spins on; δ = −0.8° swaps them.
    for delta, reverses in ((0.8, -3.0), (-0.8, 3.0)):
        for spin in (-3.0, 3.0):
            body = nr.rattleback(delta)
            t = nr.first_reversal(nr.simulate(body, [0.05, spin, 0.05], SECONDS, STEP), spin)
            if spin == reverses:
                assert t is not None and 4.0 < t < 5.5, (delta, spin, t)
            else:
                assert t is None, (delta, spin, t)


def rigidref_bin():
    path = pathlib.Path(os.environ.get("RIGIDREF_BIN", ROOT / "target" / "release" / "rigidref"))
    if not path.is_file():
        pytest.fail(f"{path} is missing: run `cargo build --release` (or cargo test --release) first")
    return str(path)


def rigidref_reversal(tmp_path, spin):
    """rigidref on scenes/rattleback.json with ω_y(0) = spin: the first time ω_y has the other
    sign beyond 0.1 rad/s, within SECONDS."""
    scene = json.loads((ROOT / "scenes" / "rattleback.json").read_text())
    body = scene["bodies"][0]
    body["omega0"][1] = spin
    body["file_root"] = str(ROOT / "scenes" / "data" / "rattleback")
    path = tmp_path / f"rattleback{spin:+.0f}.json"
    path.write_text(json.dumps(scene))
    out = tmp_path / f"r{spin:+.0f}.csv"
    run = subprocess.run([rigidref_bin(), "run", str(path), "--time", str(SECONDS), "--quiet",
                          "--format", "csv", "--out", str(out)], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    for row in csv.DictReader(out.open()):
        if float(row["b0_wy"]) * np.sign(spin) < -0.1:
            return float(row["t"])
    return None


def test_rigidref_reverses_the_way_the_noslip_model_does(tmp_path):
    # The same body, the same start (ω = (0.05, ∓3, 0.05)): both reverse the clockwise spin and
    # keep the counter-clockwise one. rigidref's contact may slip and its velocity-level impacts
    # take energy (−6.8% in 10 s), the no-slip model keeps it, so the times differ (measured
    # 4.35 s against 4.85 s); the bound says they are the same event, within a second.
    body = nr.rattleback(0.8)
    for spin in (-3.0, 3.0):
        reference = nr.first_reversal(nr.simulate(body, [0.05, spin, 0.05], SECONDS, STEP), spin)
        ours = rigidref_reversal(tmp_path, spin)
        print(f"spin {spin:+.0f}: no-slip reversal {reference}, rigidref {ours}")
        if spin < 0:
            assert reference is not None and ours is not None
            assert abs(ours - reference) < 1.0, (ours, reference)
        else:
            assert reference is None and ours is None, (ours, reference)


def test_rigidrefs_noslip_reference_is_this_model():
    # `rigidref converge` measures the rattleback's reversal against its own Rust port of this
    # model (src/verify/references/noslip.rs). The two are written independently; the first sign
    # change of ω_y (interpolated between steps) must agree: numpy's RK4 at 1 ms (5 s: the change
    # is at 4.79 s) against the Rust reference at 0.25 ms. The Rust reference moves 3e-6 s when
    # its step doubles to 0.5 ms, so RK4's O(h⁴) error at 1 ms is about 16 times that, 5e-5 s
    # (measured difference 6.4e-5 s); bound 2e-4 s.
    body = nr.rattleback(0.8)
    series = nr.simulate(body, [0.05, -3.0, 0.05], 5.0, 1e-3)
    previous = (0.0, -3.0)
    crossing = None
    for t, wy, _, _ in series:
        if previous[1] < 0 <= wy:
            crossing = previous[0] + (t - previous[0]) * previous[1] / (previous[1] - wy)
            break
        previous = (t, wy)
    assert crossing is not None
    run = subprocess.run([rigidref_bin(), "converge", str(ROOT / "scenes" / "rattleback.json"),
                          "--dt", "1e-3,5e-4", "--observable", "first_reversal", "--time",
                          str(SECONDS), "--json", "--quiet"],
                         capture_output=True, text=True, check=True)
    reference = json.loads(run.stdout)[0]["reference"]
    assert "without slipping" in reference["how"]
    print("no-slip reversal: numpy", crossing, "rigidref", reference["value"])
    assert abs(reference["value"] - crossing) < 2e-4, (reference["value"], crossing)
