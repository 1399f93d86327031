"""The 3D assignment's Python starter itself against `rigidref run SCENE --preset starter`
(docs/scene-format.md §"The starter preset", docs/contact.md §"The starter's collision
detection").

The starter's four files (tests/data/python-starter3d, as handed out) are copied and their TODO
methods filled in with the assignment's equations, as a correct student does: the spatial-frame
step (objective 1), the contact Jacobian and inverse effective mass (3, 4), and 100 sweeps of
projected Gauss-Seidel over the contacts in the order found, normal row then the two friction
rows bounded by mu * lambda_n, with Erleben's delta velocities (5-7); no stabilisation, no warm
start. Everything else is the starter's own code, unchanged: its collision detection
(collision.py with libigl's signed distance), its contact frames (contact.py), its main loop
(a2comp559.py). The program runs headless (python/headless) on the assignment's contact scenes
and must agree with rigidref's starter preset to 1e-9 in every state, contact for contact.

The starter needs libigl 2.4.1, whose wheels are built against numpy 1.x: the test uses the
Python named by RIGIDREF_IGL_PYTHON, else target/venv-igl/bin/python (.ci/run makes it), else
this one, whichever imports igl first; without one, or without ../shared, it is skipped, saying
so. The tangent test needs numpy only.
"""

import json
import os
import pathlib
import shutil
import subprocess
import sys

import numpy as np
import pytest

from test_rigidref_trace import ROOT, rigidref

STARTER = ROOT / "tests" / "data" / "python-starter3d"
ASSIGNMENT = ROOT.parent / "shared" / "assignments" / "rigid3d"

# The student's part: each (file, the starter's text, what a correct student writes there). The
# starter's text must occur exactly once, so a different starter is noticed, not half-filled.
STUDENT = [
    ("rigidbody.py", "\t\t# TODO: keep track of rotational inertia in the world aligned frame!\n", """\
\t\t# TODO: keep track of rotational inertia in the world aligned frame!
\t\tself.update_inertia()

\tdef update_inertia(self):
\t\tself.J = self.R @ self.J0 @ self.R.T
\t\tself.Jinv = self.R @ self.Jinv0 @ self.R.T
"""),
    ("rigidbody.py", """\
\tdef step_vel(self, h):
\t\t# TODO: implement this function
\t\treturn
""", """\
\tdef step_vel(self, h):
\t\tself.v = self.v + self.force * (h * self.mass_inv)
\t\tself.omega = self.omega + self.Jinv @ (self.torque - np.cross(self.omega, self.J @ self.omega)) * h
"""),
    ("rigidbody.py", """\
\tdef step_pos(self, h):\t
\t\t# TODO: implement this function
\t\treturn""", """\
\tdef step_pos(self, h):
\t\tself.x = self.x + self.v * h
\t\ttheta = self.omega * h
\t\ta2 = float(theta @ theta)
\t\tk = np.array([[0, -theta[2], theta[1]], [theta[2], 0, -theta[0]], [-theta[1], theta[0], 0]])
\t\tif a2 < 1e-8:
\t\t\ta, c = 1 - a2 / 6, 0.5 - a2 / 24
\t\telse:
\t\t\ts = np.sqrt(a2)
\t\t\ta, c = np.sin(s) / s, (1 - np.cos(s)) / a2
\t\tr = (np.eye(3) + k * a + k @ k * c) @ self.R
\t\tself.R = r @ (np.eye(3) * 3.0 - r.T @ r) * 0.5
\t\tself.update_inertia()"""),
    ("contact.py", """\
\tdef compute_jacobian(self):
\t\t# TODO: implement this function
\t\treturn

\tdef compute_inv_effective_mass(self):
\t\t# TODO: implement this function
\t\treturn""", """\
\tdef compute_jacobian(self):
\t\tr1 = self.p - self.body1.x
\t\tr2 = self.p - self.body2.x
\t\trows = [np.concatenate((-d, -np.cross(r1, d), d, np.cross(r2, d))) for d in (self.n, self.t1, self.t2)]
\t\tself.J = np.array(rows, dtype=float)

\tdef compute_inv_effective_mass(self):
\t\tMinv = np.zeros((12, 12))
\t\tfor k, b in ((0, self.body1), (6, self.body2)):
\t\t\tMinv[k:k+3, k:k+3] = np.eye(3) * b.mass_inv
\t\t\tMinv[k+3:k+6, k+3:k+6] = b.Jinv
\t\tself.MinvJT = Minv @ self.J.T
\t\tself.A = self.J @ self.MinvJT"""),
    ("collision.py", """\
\tdef process(self, rigid_body_list, mu):
\t\t#TODO: implement this function
\t\treturn""", """\
\tdef process(self, rigid_body_list, mu):
\t\tfor rb in rigid_body_list + [self.ground_body]:
\t\t\trb.du = np.zeros(6)
\t\tfor c in self.contacts:
\t\t\tc.compute_jacobian()
\t\t\tc.compute_inv_effective_mass()
\t\t\tc.b = c.J @ np.concatenate((c.body1.v, c.body1.omega, c.body2.v, c.body2.omega))
\t\tfor _ in range(100):
\t\t\tfor c in self.contacts:
\t\t\t\tfor r in range(3):
\t\t\t\t\tw = c.b[r] + c.J[r, 0:6] @ c.body1.du + c.J[r, 6:12] @ c.body2.du
\t\t\t\t\tnew = c.lamb[r] - w / c.A[r, r]
\t\t\t\t\tif r == 0:
\t\t\t\t\t\tnew = max(new, 0.0)
\t\t\t\t\telse:
\t\t\t\t\t\tnew = min(max(new, -mu * c.lamb[0]), mu * c.lamb[0])
\t\t\t\t\tdelta = new - c.lamb[r]
\t\t\t\t\tc.lamb[r] = new
\t\t\t\t\tc.body1.du = c.body1.du + c.MinvJT[0:6, r] * delta
\t\t\t\t\tc.body2.du = c.body2.du + c.MinvJT[6:12, r] * delta
\t\tfor rb in rigid_body_list:
\t\t\trb.v = rb.v + rb.du[0:3]
\t\t\trb.omega = rb.omega + rb.du[3:6]"""),
]


def skip(reason):
    # Printed as well as reported: pytest -q shows a skip's reason only with -rs.
    sys.__stderr__.write(f"SKIPPED {reason}\n")
    pytest.skip(reason)


def igl_python():
    candidates = [os.environ.get("RIGIDREF_IGL_PYTHON"), ROOT / "target" / "venv-igl" / "bin" / "python",
                  sys.executable]
    for python in candidates:
        if python and pathlib.Path(python).is_file():
            probe = subprocess.run([str(python), "-c", "import igl, numpy; igl.read_obj; igl.signed_distance"],
                                   capture_output=True)
            if probe.returncode == 0:
                return str(python)
    skip("no Python with libigl 2.4.1 (the starter's): make one with `python3 -m venv target/venv-igl && "
         "target/venv-igl/bin/pip install numpy==1.26.4 libigl==2.4.1`, or set RIGIDREF_IGL_PYTHON")


def student_program(folder):
    """The starter's files in `folder`, with the student's part filled in."""
    folder.mkdir()
    for name in ["a2comp559.py", "collision.py", "contact.py", "rigidbody.py"]:
        shutil.copy(STARTER / name, folder / name)
    for name, old, new in STUDENT:
        text = (folder / name).read_text()
        assert text.count(old) == 1, f"{name}: the starter's text to fill in is not there once: {old!r}"
        (folder / name).write_text(text.replace(old, new))
    return folder / "a2comp559.py"


def records(path):
    lines = path.read_text().splitlines()
    return json.loads(lines[0]), [json.loads(line) for line in lines[1:]]


def test_the_starters_own_code_agrees_with_the_starter_preset_contact_for_contact(tmp_path):
    if not (ASSIGNMENT / "scenes").is_dir():
        skip(f"{ASSIGNMENT} is absent (the assignment's scenes and meshes)")
    python = igl_python()
    program = student_program(tmp_path / "student")
    # The assignment's scenes whose bodies touch and whose R0 are rotations (scene2, 5 and 6
    # give reflections, which the starter keeps and rigidref turns into rotations): sphere
    # against cube both ways round (scene3, scene4: the sphere's vertices against the cube
    # either way), the stack (scene7: brick, sphere, brick, mu 2). And scene5 (friction impact)
    # with a rotation for its R0.
    scene5 = json.loads((ASSIGNMENT / "scenes" / "scene5.json").read_text())
    scene5["bodies"][0]["R0"] = [[0, 1, 0], [-1, 0, 0], [0, 0, 1]]
    (tmp_path / "scene5r.json").write_text(json.dumps(scene5))
    scenes = [ASSIGNMENT / "scenes" / f"{s}.json" for s in ["scene3", "scene4", "scene7"]]
    scenes.append(tmp_path / "scene5r.json")
    env = dict(os.environ, RIGIDREF_TIME="3",
               PYTHONPATH=os.pathsep.join([str(ROOT / "python" / "headless"), str(ROOT / "python")]))
    pair_contacts = 0
    for scene in scenes:
        mine = tmp_path / f"{scene.stem}.student.jsonl"
        # The starter reads file_root relative to the folder it runs in: the assignment's.
        run = subprocess.run([python, str(program), "--file", str(scene)], cwd=ASSIGNMENT,
                             env=dict(env, RIGIDREF_TRACE=str(mine)), capture_output=True, text=True)
        assert run.returncode == 0, run.stderr
        ref = tmp_path / f"{scene.stem}.ref.jsonl"
        out = rigidref("run", scene, "--preset", "starter", "--time", "3", "--quiet", "--out", ref,
                       cwd=ASSIGNMENT)
        assert out.returncode == 0, out.stderr
        out = rigidref("compare", ref, mine, "--tolerance", "1e-9")
        assert out.returncode == 0 and "verdict          agree" in out.stdout, out.stdout + out.stderr
        # Contact for contact, in order: the same bodies, points, normals and depths (to 1e-9,
        # as the states; measured within 2e-14).
        (_, a), (_, b) = records(ref), records(mine)
        assert len(a) == len(b) == 301
        touched = 0
        for ra, rb in zip(a, b):
            ca, cb = ra["contacts"], rb.get("contacts", [])
            assert len(ca) == len(cb), f"{scene.stem} t = {ra['t']}: {len(ca)} contacts, the starter {len(cb)}"
            for x, y in zip(ca, cb):
                assert x["bodies"] == y["bodies"], (scene.stem, ra["t"], x, y)
                for key in ["p", "n"]:
                    assert np.abs(np.subtract(x[key], y[key])).max() < 1e-9, (scene.stem, ra["t"], key, x, y)
                assert abs(x["depth"] - y["depth"]) < 1e-9, (scene.stem, ra["t"], x, y)
                touched += 1
                pair_contacts += x["bodies"][1] != -1
        assert touched > 0, f"{scene.stem}: no contacts in 3 s"
    assert pair_contacts > 100, pair_contacts
    # Each of the starter's rules matters: without its detection, or without its tangents, the
    # stack (whose brick turns on the sphere) parts from the starter from t = 0.5 s.
    for key in ["collision=vertices", "tangents=orthonormal"]:
        other = tmp_path / "other.jsonl"
        out = rigidref("run", scenes[2], "--preset", "starter", "--set", key, "--time", "3", "--quiet",
                       "--out", other, cwd=ASSIGNMENT)
        assert out.returncode == 0, out.stderr
        out = rigidref("compare", other, tmp_path / "scene7.student.jsonl", "--tolerance", "1e-9")
        assert out.returncode != 0 and "differ" in out.stdout, (key, out.stdout)


def test_the_starters_contact_frame_is_the_one_rigidref_calls_starter():
    """contact.py's axis test, run by Python itself, on the normals of
    src/rigid3d/frame.rs's test (the_starter_frame_follows_contact_py_including_its_precedence_slip):
    the same axis each time, t2 = n x axis and t1 = t2 x n, not normalised."""
    sys.path.insert(0, str(STARTER))
    try:
        import contact
    finally:
        sys.path.pop(0)
    x, y, z = np.eye(3)
    cases = [(y, z), ((0.0, 0.0, 1.0), y), ((0.1, 0.5, 0.86), x), ((0.3, 0.1, 0.9), x),
             ((0.8, 0.2, 0.3), y), ((0.8, 0.4, 0.3), z), ((-1.0, -0.0, 0.0), z)]
    for n, axis in cases:
        n = np.asarray(n, dtype=float)
        n = n / np.linalg.norm(n)
        c = contact.Contact(None, None, np.zeros(3), n, 0.0)
        assert np.array_equal(c.t2, np.cross(n, axis)), (n, c.t2)
        assert np.array_equal(c.t1, np.cross(c.t2, n))
    # Not unit: |t1| = |t2| = |n x axis|.
    c = contact.Contact(None, None, np.zeros(3), np.array([0.1, 0.5, 0.86]) / np.linalg.norm([0.1, 0.5, 0.86]),
                        0.0)
    assert np.linalg.norm(c.t2) < 0.999
