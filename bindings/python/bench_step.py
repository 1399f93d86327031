"""The cost of a step from Python against the CLI's, on a 1 000-body scene (docs/python.md
§"Measured"). A benchmark, not a test: run it on a quiet machine.

    python bindings/python/bench_step.py [--rounds 5] [--steps 50]

The scene: 100 stacks of 10 boxes (0.5 m, scenes/data/box), 0.8 m apart, resting on the ground
(`collision: complete`).
The CLI's time per step is (T(10 + steps) − T(10)) / steps over two runs of `rigidref run`
(recording only the last step), which cancels loading and start-up; Python's is
`world.step(steps)` timed after `World.load` and 10 steps. Rounds alternate the two, and each
side's fastest round is kept: what is compared is the step, not the machine's other load.
"""

import argparse
import json
import subprocess
import tempfile
import time
from pathlib import Path

import rigidref

ROOT = Path(__file__).resolve().parents[2]
CLI = ROOT / "target" / "release" / "rigidref"


def write_scene(path):
    bodies = []
    for i in range(10):
        for k in range(10):
            for level in range(10):
                bodies.append({
                    "name": f"box {i} {k} {level}",
                    "file_root": str(ROOT / "scenes" / "data" / "box"),
                    "x0": [0.8 * i, 0.249 + 0.4999 * level, 0.8 * k],
                })
    # Equal boxes stacked need `collision: complete` (the vertex rule misses face-on-face
    # contact between equal boxes and the stacks sink; docs/contact.md).
    scene = {"sim_parameters": [{"name": "1000 boxes", "dt": 0.01, "gravity": [0, -9.8, 0],
                                 "mu": 0.5, "substeps": 1, "collision": "complete"}], "bodies": bodies}
    path.write_text(json.dumps(scene))


def cli_seconds(scene, steps, out):
    start = time.perf_counter()
    subprocess.run([str(CLI), "run", str(scene), "--steps", str(steps), "--every", str(steps),
                    "--quiet", "--out", str(out)], check=True, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--steps", type=int, default=50)
    args = parser.parse_args()
    if not CLI.exists():
        subprocess.run(["cargo", "build", "--release", "--quiet"], cwd=ROOT, check=True)
    with tempfile.TemporaryDirectory() as d:
        scene = Path(d) / "boxes1000.json"
        write_scene(scene)
        out = Path(d) / "t.jsonl"
        cli, py = [], []
        for r in range(args.rounds):
            cli.append((cli_seconds(scene, 10 + args.steps, out) - cli_seconds(scene, 10, out)) / args.steps)
            world = rigidref.World.load(scene)
            world.step(10)
            start = time.perf_counter()
            world.step(args.steps)
            py.append((time.perf_counter() - start) / args.steps)
            print(f"round {r + 1}: CLI {cli[-1] * 1e3:.2f} ms/step, Python {py[-1] * 1e3:.2f} ms/step")
        best_cli, best_py = min(cli), min(py)
        print(f"fastest: CLI {best_cli * 1e3:.2f} ms/step, Python {best_py * 1e3:.2f} ms/step, "
              f"Python / CLI = {best_py / best_cli:.3f}")


if __name__ == "__main__":
    main()
