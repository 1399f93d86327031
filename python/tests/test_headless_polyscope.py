"""The polyscope stand-in (python/headless/polyscope): a student's polyscope program, unchanged,
run headless and traced (docs/grading.md §"A Python class").

The program here is written for the test in the shape of the 3D assignment's Python starter
(a2comp559.py): it loads a scene, registers meshes, and steps its bodies in the user-interface
callback while the "Run" checkbox is ticked; its step is the assignment's explicit spatial-frame
update (free flight, numpy only). With the stand-in first on PYTHONPATH it runs without a window
and its trace agrees with rigidref's run of the scene to round-off, both with the defaults and
with the 3D starter preset (the Python student path's agreement is unchanged by the preset).
"""

import os
import pathlib
import subprocess
import sys

from test_rigidref_trace import ROOT, rigidref

PROGRAM = r'''
import argparse, json, pathlib
import numpy as np
import polyscope as ps
import polyscope.imgui as psim

parser = argparse.ArgumentParser()
parser.add_argument("--file", type=str, default="scenes/scene1.json")
args = parser.parse_args()
data = json.load(open(args.file))
# file_root is relative to the scene's folder (rigidref's scenes) or its parent (the assignment's).
here = pathlib.Path(args.file).parent
root = here if (here / (data["bodies"][0]["file_root"] + ".json")).exists() else here.parent

class RigidBody:
    def __init__(self, desc):
        self.name = desc["name"]
        body = json.load(open(root / (desc["file_root"] + ".json")))
        self.mass, self.J0 = body["mass"], np.array(body["J"], dtype=float)
        self.x = np.array(desc["x0"], dtype=float)
        self.R = np.array(desc.get("R0", np.eye(3)), dtype=float)
        self.v = np.array(desc.get("v0", (0, 0, 0)), dtype=float)
        self.omega = np.array(desc.get("omega0", (0, 0, 0)), dtype=float)
        self.ps_mesh = ps.register_surface_mesh(self.name, np.zeros((3, 3)), np.zeros((1, 3)))

    def step_vel(self, h, g):
        self.v = self.v + g * h
        jw = self.R @ self.J0 @ self.R.T
        self.omega = self.omega + np.linalg.inv(jw) @ (-np.cross(self.omega, jw @ self.omega)) * h

    def step_pos(self, h):
        self.x = self.x + self.v * h
        theta = self.omega * h
        a2 = float(theta @ theta)
        k = np.array([[0, -theta[2], theta[1]], [theta[2], 0, -theta[0]], [-theta[1], theta[0], 0]])
        if a2 < 1e-8:
            a, b = 1 - a2 / 6 + a2 * a2 / 120, 0.5 - a2 / 24 + a2 * a2 / 720
        else:
            s = np.sqrt(a2)
            a, b = np.sin(s) / s, (1 - np.cos(s)) / a2
        r = (np.eye(3) + k * a + k @ k * b) @ self.R
        self.R = r @ (np.eye(3) * 3.0 - r.T @ r) * 0.5
        self.ps_mesh.set_transform(np.eye(4))

ps.init()
rigid_body_list = [RigidBody(b) for b in data["bodies"]]
sim_params = data["sim_parameters"][0]
gravity = np.array(sim_params.get("gravity", (0.0, 0.0, 0.0)))
h = sim_params.get("dt", 0.01)
substeps = sim_params.get("substeps", 1)
is_running = False

def main_display_loop():
    global is_running, h, substeps
    psim.TextUnformatted(sim_params["name"])
    do_step = psim.Button("Step")
    _, is_running = psim.Checkbox("Run", is_running)
    _, h = psim.SliderFloat("step size", h, v_min=0.001, v_max=0.1)
    _, substeps = psim.InputInt("substeps", substeps, step=1, step_fast=1)
    if is_running or do_step:
        for _ in range(substeps):
            for rb in rigid_body_list:
                rb.step_vel(h / substeps, gravity)
                rb.step_pos(h / substeps)

ps.set_user_callback(main_display_loop)
ps.show()
'''


def test_a_polyscope_program_runs_headless_and_its_trace_agrees_with_rigidref(tmp_path):
    program = tmp_path / "a2comp559.py"
    program.write_text(PROGRAM)
    scene = ROOT / "scenes" / "tumbling_brick.json"
    env = dict(os.environ, RIGIDREF_TRACE=str(tmp_path / "student.jsonl"), RIGIDREF_TIME="5",
               PYTHONPATH=os.pathsep.join([str(ROOT / "python" / "headless"), str(ROOT / "python")]))
    run = subprocess.run([sys.executable, str(program), "--file", str(scene)], env=env,
                         capture_output=True, text=True, cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    assert "500 frames of 0.01 s (10 substeps)" in run.stderr
    lines = (tmp_path / "student.jsonl").read_text().splitlines()
    assert len(lines) == 1 + 501  # the header, t = 0 and one record per frame
    for extra, name in [((), "ref.jsonl"), (("--set", "preset=starter"), "starter.jsonl")]:
        out = rigidref("run", scene, "--time", "5", "--quiet", "--out", tmp_path / name, *extra)
        assert out.returncode == 0, out.stderr
        # To round-off: the same explicit spatial-frame scheme (1e-9 in every quantity).
        out = rigidref("compare", tmp_path / name, tmp_path / "student.jsonl", "--tolerance", "1e-9")
        assert out.returncode == 0, out.stdout + out.stderr
        assert "verdict          agree" in out.stdout


def test_a_program_without_a_trace_to_write_is_told_so(tmp_path):
    program = tmp_path / "p.py"
    program.write_text("import polyscope as ps\nps.set_user_callback(lambda: None)\nps.show()\n")
    env = dict(os.environ, PYTHONPATH=str(ROOT / "python" / "headless"))
    env.pop("RIGIDREF_TRACE", None)
    run = subprocess.run([sys.executable, str(program)], env=env, capture_output=True, text=True)
    assert run.returncode != 0
    assert "RIGIDREF_TRACE is not set" in run.stderr
