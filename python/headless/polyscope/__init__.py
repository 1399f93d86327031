"""A stand-in for polyscope that runs a student's polyscope program headless and traces it.

The 3D assignment's Python starter (a2comp559.py) draws with polyscope and steps its bodies in
the user-interface callback it gives ps.set_user_callback. With this folder first on PYTHONPATH,
`import polyscope` finds this module instead: every drawing call does nothing, the "Run"
checkbox reads as ticked, and ps.show() calls the student's callback once per frame, unchanged,
recording after each call the state of the program's `rigid_body_list` (each body's x, R, v,
omega, name, mass, J0: the starter's names) and the contacts of its `collision` object, through
rigidref's trace writer (python/rigidref_trace.py). The student's files are not edited.

    RIGIDREF_TRACE=scene1.jsonl RIGIDREF_TIME=5 \\
        PYTHONPATH=$RIGIDREF/python/headless:$RIGIDREF/python python3 src/a2comp559.py --file scenes/scene1.json

RIGIDREF_TRACE is the trace to write (required), RIGIDREF_TIME the simulated time in seconds
(default 5). The step is the program's `h` (the scene's dt) and its `substeps`, read once the
program has loaded its scene. docs/grading.md §"A Python class".
"""

import os
import sys

from . import imgui  # noqa: F401  (polyscope.imgui, the user interface: also a stand-in)

_callback = None


class _Drawn:
    """What register_* returns: a structure whose every method does nothing."""

    def __getattr__(self, name):
        return lambda *args, **kwargs: self


def __getattr__(name):
    """Every other polyscope function (init, set_*, register_*, remove_*): does nothing."""
    if name.startswith("__"):
        raise AttributeError(name)
    return lambda *args, **kwargs: _Drawn()


def set_user_callback(callback):
    global _callback
    _callback = callback


def _writer():
    try:
        from rigidref import TraceWriter
    except ImportError:
        from rigidref_trace import TraceWriter
    return TraceWriter


def _states(bodies):
    return [(b.x, b.R, b.v, b.omega) for b in bodies]


def _contacts(program, bodies):
    """The program's collision object's contacts, in the trace's form (j = -1: the ground).

    The starter's Contact(body1, body2, p, n, d) has n pointing from body1 into body2 (the
    ground is body1 of a ground contact; of a pair, body1 owns the penetrating vertex and n
    points into body2, the body it penetrates): body2 is the one n pushes. The trace's
    [i, j] has n pointing from j into i, so a contact is written [body2, body1], the starter's
    normal unchanged (a contact whose body2 is the ground is written [body1, -1])."""
    collision = program.get("collision")
    out = []
    for c in getattr(collision, "contacts", None) or []:
        index = [next((k for k, b in enumerate(bodies) if b is body), -1) for body in (c.body2, c.body1)]
        if index[0] == -1:
            index.reverse()
        entry = {"bodies": index, "p": [float(v) for v in c.p], "n": [float(v) for v in c.n],
                 "depth": abs(float(c.d))}
        lam = getattr(c, "lamb", None)
        if lam is not None:
            entry["lambda"] = [float(v) for v in lam]
        out.append(entry)
    return out


def show(*args, **kwargs):
    """Runs the program's callback once per frame for RIGIDREF_TIME seconds, recording each frame."""
    if _callback is None:
        raise RuntimeError("the program gave polyscope no user callback (ps.set_user_callback)")
    path = os.environ.get("RIGIDREF_TRACE")
    if not path:
        raise RuntimeError("RIGIDREF_TRACE is not set: name the trace to write")
    time = float(os.environ.get("RIGIDREF_TIME", "5"))
    program = vars(sys.modules["__main__"])
    bodies = program["rigid_body_list"]
    dt, substeps = float(program["h"]), int(program.get("substeps", 1))
    params = program.get("sim_params", {})
    source = getattr(program.get("args"), "file", "python")
    frames = round(time / dt)
    writer = _writer()(path, scene=params.get("name", "scene"), dt=dt, substeps=substeps,
                       gravity=program.get("gravity", [0.0, 0.0, 0.0]), source=source,
                       bodies=[(b.name, b.mass, b.J0) for b in bodies])
    with writer:
        writer.record(0, 0.0, _states(bodies))
        for frame in range(1, frames + 1):
            _callback()
            writer.record(frame, frame * dt, _states(bodies), contacts=_contacts(program, bodies))
    print(f"rigidref headless: {len(bodies)} bodies, {frames} frames of {dt} s ({substeps} substeps), "
          f"trace {path}", file=sys.stderr)
