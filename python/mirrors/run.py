"""Runs rigidref scenes in other engines and writes rigidref traces: the mirrors of
`rigidref validate` (docs/validation.md). rigidref writes this folder next to its report and
calls, with the Python that has the engines:

    python run.py probe mujoco,pybullet,drake,pymunk      # each engine's version, or why not
    python run.py run JOBS.json                           # the jobs of one engine

JOBS.json: {"engine": NAME, "jobs": [{"description": PATH, "settings": "default"|"accurate",
"trace": PATH, "model": PATH}]}. Each job writes its trace and a model file: the settings used
and what the engine's own model reads back (masses, inertias, friction, step), or
{"error": ONE LINE} when the job failed. Deterministic: the engines run single-threaded.
"""

import importlib
import json
import os
import sys
import traceback

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

ENGINES = {
    "mujoco": ("mujoco_mirror", "mujoco"),
    "pybullet": ("pybullet_mirror", "pybullet"),
    "drake": ("drake_mirror", "pydrake"),
    "pymunk": ("pymunk_mirror", "pymunk"),
}


def one_line(e):
    text = f"{type(e).__name__}: {e}".replace("\n", " ").strip()
    return text[:400]


def probe(names):
    out = {}
    for name in names:
        if name not in ENGINES:
            out[name] = {"installed": False, "reason": f"no mirror for engine {name!r}"}
            continue
        module, package = ENGINES[name]
        try:
            mirror = importlib.import_module(module)
            out[name] = {"installed": True, "version": mirror.version()}
        except ImportError as e:
            out[name] = {"installed": False, "reason": f"cannot import {package}: {one_line(e)}"}
        except Exception as e:  # an engine that is there but broken is reported, never dropped
            out[name] = {"installed": False, "reason": one_line(e)}
    print(json.dumps(out))


def write_json(path, obj):
    with open(path, "w", encoding="utf-8") as f:
        json.dump(obj, f, indent=1, allow_nan=False)
        f.write("\n")


def run_jobs(path):
    from common import load_description
    from rigidref_trace import TraceWriter
    with open(path, encoding="utf-8") as f:
        jobs = json.load(f)
    engine = jobs["engine"]
    mirror_module = importlib.import_module(ENGINES[engine][0])
    for job in jobs["jobs"]:
        try:
            scene = load_description(job["description"])
            if hasattr(mirror_module, "run_job"):  # a 2D mirror writes its own 2D trace
                model = mirror_module.run_job(scene, job["settings"], job["trace"])
                model.update({"engine": engine, "version": mirror_module.version(),
                              "settings_name": job["settings"]})
                write_json(job["model"], model)
                continue
            workdir = os.path.dirname(os.path.abspath(job["trace"]))
            mirror = mirror_module.Mirror(scene, job["settings"], workdir)
            bodies = [(b["name"], b["mass"], b["inertia"]) for b in scene["bodies"]]
            substeps = scene["substeps"]
            h = scene["h"]
            with TraceWriter(job["trace"], scene=scene["scene"], dt=scene["dt"],
                             gravity=scene["gravity"], bodies=bodies, substeps=substeps,
                             source=f"{engine} mirror of {scene['source']}",
                             integrator=mirror.integrator_name(),
                             collision=engine) as trace:
                trace.record(0, 0.0, mirror.states())
                k = 0
                for frame in range(1, scene["frames"] + 1):
                    contacts = []
                    for _ in range(substeps):
                        mirror.step(k * h)
                        k += 1
                        found = mirror.contacts()
                        if found:
                            contacts = found
                    trace.record(frame, frame * scene["dt"], mirror.states(), contacts)
            model = {"engine": engine, "version": mirror_module.version(),
                     "settings_name": job["settings"], "settings": mirror.settings_used(),
                     "readback": mirror.readback()}
            write_json(job["model"], model)
        except Exception as e:
            write_json(job["model"], {"engine": engine, "settings_name": job["settings"],
                                      "error": one_line(e),
                                      "where": traceback.format_exc().splitlines()[-3:]})


def main(argv):
    if len(argv) == 3 and argv[1] == "probe":
        probe([n for n in argv[2].split(",") if n])
    elif len(argv) == 3 and argv[1] == "run":
        run_jobs(argv[2])
    else:
        print("usage: run.py probe ENGINES | run.py run JOBS.json", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
