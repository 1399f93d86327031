"""Write rigidref traces and contact-problem files from another simulator (docs/grading.md).

A course's Python starter calls this from its step loop, so that `rigidref compare` and
`rigidref compare-problem` can check its output against the reference:

    from rigidref import TraceWriter, write_problem    # the installed package, or
    from rigidref_trace import TraceWriter, write_problem   # this one file, copied beside the starter

    trace = TraceWriter("scene1.jsonl", scene="scene1", dt=dt, gravity=g,
                        bodies=[(b.name, b.mass, b.J0) for b in bodies])
    trace.record(step, t, [(b.x, b.R, b.v, b.omega) for b in bodies])   # after every step
    ...
    trace.close()

The formats are docs/trace-format.md (version 2) and docs/contact-problem-format.md (version 1).
Units are SI; omega is the angular velocity in the world frame; R maps body to world. The
energies and momenta each record carries are computed here, from the state, exactly as
rigidref defines them (docs/dynamics.md §"Energy and momentum"). Needs only the standard library
and numpy.
"""

import json
import math

import numpy as np

FORMAT_NAME = "rigidref-trace"
FORMAT_VERSION = 2
PROBLEM_FORMAT = "rigidref-contact-problem"
PROBLEM_VERSION = 1


def _floats(a):
    """A list of Python floats (JSON numbers, written with round-trip precision)."""
    return [float(x) for x in np.asarray(a, dtype=float).ravel()]


def _check_finite(what, a):
    a = np.asarray(a, dtype=float)
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{what} is not finite: {a.tolist()}")
    return a


class TraceWriter:
    """Writes a 3D trace: a header line, then one line per recorded step.

    bodies: a list of (name, mass in kg, J0) with J0 the 3x3 inertia about the centre of mass in
    the body frame (kg m^2), in the order record() receives the states.
    """

    def __init__(self, path, scene, dt, gravity, bodies, substeps=1, source="python",
                 integrator="spatial", collision="vertices"):
        self._bodies = []
        for name, mass, inertia in bodies:
            inertia = _check_finite(f"J0 of {name!r}", inertia).reshape(3, 3)
            if not (mass > 0 and math.isfinite(mass)):
                raise ValueError(f"mass of {name!r} must be positive, got {mass}")
            self._bodies.append((str(name), float(mass), inertia))
        self._gravity = _check_finite("gravity", gravity).reshape(3)
        self._file = open(path, "w", encoding="utf-8")
        header = {
            "format": FORMAT_NAME,
            "version": FORMAT_VERSION,
            "dimension": 3,
            "scene": str(scene),
            "source": str(source),
            "dt": float(dt),
            "substeps": int(substeps),
            "gravity": _floats(self._gravity),
            "integrator": str(integrator),
            "collision": str(collision),
            "bodies": [{"name": n, "mass": m} for n, m, _ in self._bodies],
        }
        self._write(header)

    def _write(self, obj):
        self._file.write(json.dumps(obj, separators=(",", ":"), allow_nan=False) + "\n")

    def record(self, step, t, states, contacts=()):
        """One record: states is a list of (x, R, v, omega) per body, in header order.

        contacts (optional): dicts {"bodies": [i, j], "p": [3], "n": [3], "depth": d,
        "lambda": [ln, lt1, lt2]} with j = -1 for the ground (docs/trace-format.md).
        """
        if len(states) != len(self._bodies):
            raise ValueError(f"{len(states)} states for {len(self._bodies)} bodies")
        bodies = []
        kinetic_linear = kinetic_angular = potential = 0.0
        linear = np.zeros(3)
        angular = np.zeros(3)
        total_mass = sum(m for _, m, _ in self._bodies)
        com = np.zeros(3)
        parts = []
        for (name, mass, inertia), (x, rot, v, omega) in zip(self._bodies, states):
            x = _check_finite(f"x of {name!r}", x).reshape(3)
            rot = _check_finite(f"R of {name!r}", rot).reshape(3, 3)
            v = _check_finite(f"v of {name!r}", v).reshape(3)
            omega = _check_finite(f"omega of {name!r}", omega).reshape(3)
            inertia_world = rot @ inertia @ rot.T
            spin = inertia_world @ omega
            p = v * mass
            kinetic_linear += 0.5 * mass * float(v @ v)
            kinetic_angular += 0.5 * float(omega @ spin)
            potential += -mass * float(self._gravity @ x)
            linear += p
            angular += np.cross(x, p) + spin
            com += x * mass
            parts.append((x, p, spin))
            bodies.append({"x": _floats(x), "R": [_floats(row) for row in rot],
                           "v": _floats(v), "omega": _floats(omega)})
        com = com / total_mass if total_mass > 0 else com
        angular_com = np.zeros(3)
        for x, p, spin in parts:
            angular_com += np.cross(x - com, p) + spin
        record = {
            "step": int(step),
            "t": float(t),
            "bodies": bodies,
            "energy": {
                "kinetic_linear": kinetic_linear,
                "kinetic_angular": kinetic_angular,
                "potential": potential,
                "total": kinetic_linear + kinetic_angular + potential,
            },
            "momentum": {"linear": _floats(linear), "angular": _floats(angular),
                         "angular_com": _floats(angular_com)},
            "contacts": [dict(c) for c in contacts],
        }
        self._write(record)

    def close(self):
        self._file.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def jacobian_block(n, t1, t2, r):
    """A body's 3x6 contact Jacobian block: rows d^T [I | [r]x^T] for d in (n, t1, t2), i.e.
    [d, r x d], so that block @ (v, omega) = d . (v + omega x r) (docs/contact.md)."""
    n, t1, t2, r = (np.asarray(a, dtype=float).reshape(3) for a in (n, t1, t2, r))
    return np.array([np.concatenate([d, np.cross(r, d)]) for d in (n, t1, t2)])


def write_problem(path, bodies, contacts, friction="box", lam=None, scene=None, step=None, h=None):
    """Write a 3D contact-problem file (docs/contact-problem-format.md).

    bodies: list of (inverse_mass 6x6, velocity 6) in world coordinates.
    contacts: list of dicts {"bodies": [i, j] (j = -1 for the ground), "jacobian": [J1, J2]
    (3x6 each; zeros for the ground), "b": [3], "mu": mu, "compliance": c (default 0),
    "lambda0": [3] (default zeros), "geometry": {"p", "n", "depth"} (optional)}.
    lam (optional): the solved impulses, one [ln, lt1, lt2] per contact.
    """
    out = {
        "format": PROBLEM_FORMAT,
        "version": PROBLEM_VERSION,
        "dof_per_body": 6,
        "rows_per_contact": 3,
    }
    if scene is not None:
        out["scene"] = str(scene)
    if step is not None:
        out["step"] = int(step)
    if h is not None:
        out["h"] = float(h)
    out["friction"] = friction
    out["bodies"] = [{"inverse_mass": [_floats(row) for row in np.asarray(m, float).reshape(6, 6)],
                      "velocity": _floats(u)} for m, u in bodies]
    out["contacts"] = []
    for c in contacts:
        entry = {
            "bodies": [int(c["bodies"][0]), int(c["bodies"][1])],
            "jacobian": [[_floats(row) for row in np.asarray(j, float).reshape(3, 6)]
                         for j in c["jacobian"]],
            "b": _floats(c["b"]),
            "mu": float(c["mu"]),
            "compliance": float(c.get("compliance", 0.0)),
            "lambda0": _floats(c.get("lambda0", [0.0, 0.0, 0.0])),
        }
        if "geometry" in c:
            g = c["geometry"]
            entry["geometry"] = {"p": _floats(g["p"]), "n": _floats(g["n"]), "depth": float(g["depth"])}
        out["contacts"].append(entry)
    if lam is not None:
        out["solution"] = {"solver": "python", "lambda": [_floats(l) for l in lam],
                           "iterations": 0, "residual": 0.0}
    with open(path, "w", encoding="utf-8") as f:
        json.dump(out, f, allow_nan=False)
        f.write("\n")
