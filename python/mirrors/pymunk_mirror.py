"""The pymunk (Chipmunk2D) mirror of rigidref's 2D scenes (docs/validation.md §"2D: pymunk").

Reads the 2D mirror description (`src/tools/validation/two_d/mirror.rs::MirrorScene2`) and builds one
pymunk Body per rigidref body: the scene's mass and moment of inertia set on the body (its shapes
carry none), its centre of mass at the body's origin, and one Circle of radius sqrt(2)/2 per block
at the block's offset. Circles, not boxes: rigidref's 2D contact geometry is exactly these discs
(docs/blocks2d.md §"Collision": every block collides as the disc circumscribing its square), so
the circles give Chipmunk the same contact geometry, and boxes would be another model. A pinned
body is a STATIC body. Chipmunk combines friction (and elasticity) as the product of the two
shapes' values, so every shape gets sqrt(mu) (and sqrt(restitution)). Gravity and the step h =
dt / substeps are the scene's; the scripted impulses are applied at the start of the step at or
after their time, at their point (default: the centre of mass), as rigidref does.

Settings: `default` leaves the Space as pymunk makes it (10 iterations, collision_slop 0.1,
collision_bias (1 - 0.1)^60, no damping, no sleeping); `accurate` sets 100 iterations and
collision_slop to rigidref's own slop (the overlap it lets stand).

Writes a rigidref 2D trace (docs/trace-format.md §"2D traces") whose energy, momentum, contact
count and deepest overlap (Chipmunk's own contact depths) are computed here from pymunk's state,
and whose contacts carry Chipmunk's per-point impulses and the contact velocity after them
(`arbiter_contacts`), for the physical criteria.
"""

import json
import math

import pymunk

from common import MirrorError

ACCURATE_ITERATIONS = 100


def version():
    return f"pymunk {pymunk.version} (Chipmunk2D {pymunk.chipmunk_version.split('-')[0]})"


def build(scene, settings):
    """The pymunk Space of a 2D description with `settings` ("default" or "accurate"): (space,
    bodies, shapes per body, the settings as applied)."""
    if scene.get("dimension") != 2:
        raise MirrorError("pymunk mirrors 2D scenes only")
    if settings not in ("default", "accurate"):
        raise MirrorError(f"unknown settings {settings!r}")
    space = pymunk.Space()
    space.gravity = (float(scene["gravity"][0]), float(scene["gravity"][1]))
    if settings == "accurate":
        space.iterations = ACCURATE_ITERATIONS
        space.collision_slop = float(scene["slop"])
    friction = math.sqrt(scene["mu"])
    elasticity = math.sqrt(scene["restitution"])
    bodies, shapes = [], []
    for b in scene["bodies"]:
        if b["pinned"]:
            body = pymunk.Body(body_type=pymunk.Body.STATIC)
        else:
            body = pymunk.Body(float(b["mass"]), float(b["inertia"]))
        body.position = (float(b["x0"][0]), float(b["x0"][1]))
        body.angle = float(b["theta0"])
        if not b["pinned"]:
            body.velocity = (float(b["v0"][0]), float(b["v0"][1]))
            body.angular_velocity = float(b["omega0"])
        circles = []
        for local in b["blocks"]:
            c = pymunk.Circle(body, float(scene["block_radius"]), offset=(float(local[0]), float(local[1])))
            c.friction = friction
            c.elasticity = elasticity
            circles.append(c)
        space.add(body, *circles)
        bodies.append(body)
        shapes.append(circles)
    applied = {
        "iterations": space.iterations,
        "collision_slop": space.collision_slop,
        "collision_bias": space.collision_bias,
        "collision_persistence": space.collision_persistence,
        "damping": space.damping,
        "sleep_time_threshold": "inf (no sleeping)" if math.isinf(space.sleep_time_threshold) else space.sleep_time_threshold,
        "gravity": list(space.gravity),
        "h": scene["h"],
        "shape": "one Circle of radius block_radius per block (rigidref's contact discs)",
        "friction_per_shape": friction,
        "elasticity_per_shape": elasticity,
    }
    return space, bodies, shapes, applied


def readback(scene, bodies, shapes):
    """pymunk's model read back: each body's mass, moment, type, shape count and radius, and the
    friction (and elasticity) a pair of its shapes gets (Chipmunk's product rule)."""
    out = []
    for b, body, circles in zip(scene["bodies"], bodies, shapes):
        static = body.body_type == pymunk.Body.STATIC
        out.append({
            "name": b["name"],
            "static": static,
            "mass": None if static else body.mass,
            "moment": None if static else body.moment,
            "shapes": len(circles),
            "radius": circles[0].radius if circles else None,
            "offsets": [list(c.offset) for c in circles],
            "pair_friction": circles[0].friction * circles[0].friction if circles else None,
            "pair_elasticity": circles[0].elasticity * circles[0].elasticity if circles else None,
        })
    return out


def arbiter_contacts(bodies, space):
    """Every contact point of the arbiters the last space.step solved, as rigidref 2D trace
    contacts (docs/trace-format.md §"2D traces"), each with Chipmunk's own per-point accumulated
    impulses and the contact velocity after them.

    Chipmunk keeps, per contact point of an arbiter (cpContact), the lever arms r1, r2 from body a's
    and body b's centres and the accumulated normal and tangent impulses jnAcc, jtAcc it applied to
    body b (and their opposite to body a) along the arbiter's normal n (from shape a to shape b) and
    its perpendicular t = (-n_y, n_x). pymunk's public API gives only their sum
    (Arbiter.total_impulse) and the points (contact_point_set); the per-point values are read from
    the cpArbiter struct that pymunk's cffi binding exposes (pymunk's own pickling reads them the
    same way). In rigidref's convention (body 1 pushed along n by lambda_n) body 1 is b, body 2 is a,
    lambda = (jnAcc, jtAcc), and n and t are the same vectors. The contact velocity is
    c = (v_b + w_b x r2 - v_a - w_a x r1) . (n, t): Chipmunk integrates the positions at the start
    of its step and then collides and solves, so the bodies' positions after the step are those the
    lever arms were measured from, and these velocities are the ones its impulses produced (its
    overlap correction goes into separate bias velocities, not into these).
    """
    index = {body._body: i for i, body in enumerate(bodies)}
    out = []
    seen = set()
    for body in bodies:
        for arbiter in _arbiters(body):
            raw = arbiter._arbiter
            key = (int(pymunk._chipmunk.ffi.cast("uintptr_t", raw.a)), int(pymunk._chipmunk.ffi.cast("uintptr_t", raw.b)))
            if key in seen:
                continue
            seen.add(key)
            a, b = index[raw.body_a], index[raw.body_b]
            body_a, body_b = bodies[a], bodies[b]
            n = (raw.n.x, raw.n.y)
            t = (-n[1], n[0])
            for k in range(raw.count):
                contact = raw.contacts[k]
                r1 = (contact.r1.x, contact.r1.y)
                r2 = (contact.r2.x, contact.r2.y)
                pa = (body_a.position.x + r1[0], body_a.position.y + r1[1])
                pb = (body_b.position.x + r2[0], body_b.position.y + r2[1])
                def at(body, r):
                    w = body.angular_velocity
                    return (body.velocity.x - w * r[1], body.velocity.y + w * r[0])
                va, vb = at(body_a, r1), at(body_b, r2)
                rel = (vb[0] - va[0], vb[1] - va[1])
                out.append({
                    "bodies": [b, a],
                    "p": [(pa[0] + pb[0]) / 2, (pa[1] + pb[1]) / 2],
                    "n": [n[0], n[1]],
                    # Chipmunk's distance (pb - pa) . n, negative when overlapping.
                    "depth": -((pb[0] - pa[0]) * n[0] + (pb[1] - pa[1]) * n[1]),
                    "lambda": [contact.jnAcc, contact.jtAcc],
                    "c": [rel[0] * n[0] + rel[1] * n[1], rel[0] * t[0] + rel[1] * t[1]],
                })
    return out


def _arbiters(body):
    found = []
    body.each_arbiter(found.append)
    return found


def record(scene, step, bodies, space):
    g = scene["gravity"]
    kinetic = potential = 0.0
    px = py = angular = 0.0
    states = []
    for b, body in zip(scene["bodies"], bodies):
        x, v = body.position, body.velocity
        states.append({"x": [x.x, x.y], "theta": body.angle, "v": [v.x, v.y], "omega": body.angular_velocity})
        if b["pinned"]:
            continue
        m, inertia = b["mass"], b["inertia"]
        kinetic += 0.5 * m * (v.x * v.x + v.y * v.y) + 0.5 * inertia * body.angular_velocity ** 2
        potential += -m * (g[0] * x.x + g[1] * x.y)
        px += m * v.x
        py += m * v.y
        angular += m * (x.x * v.y - x.y * v.x) + inertia * body.angular_velocity
    contacts = arbiter_contacts(bodies, space)
    deepest = max((c["depth"] for c in contacts), default=0.0)
    return {
        "step": step,
        "t": step * scene["dt"],
        "bodies": states,
        "energy": {"kinetic": kinetic, "potential": potential, "total": kinetic + potential},
        "momentum": {"linear": [px, py], "angular": angular},
        "contact_count": len(contacts),
        "deepest_overlap": deepest,
        "contacts": contacts,
    }


def run_job(scene, settings, trace_path):
    """Runs the description `scene` with `settings`, writing the 2D trace; returns the model
    file's content (settings as applied and pymunk's model read back)."""
    space, bodies, shapes, applied = build(scene, settings)
    model = {"settings": applied, "readback": readback(scene, bodies, shapes)}
    dt, h, substeps = scene["dt"], scene["h"], scene["substeps"]
    pending = list(scene["impulses"])
    header = {
        "format": "rigidref-trace", "version": 2, "dimension": 2,
        "scene": scene["scene"], "source": f"pymunk mirror of {scene['source']}",
        "dt": dt, "substeps": substeps, "gravity": scene["gravity"],
        "bodies": [{"name": b["name"], "mass": b["mass"], "pinned": b["pinned"], "blocks": len(b["blocks"])}
                   for b in scene["bodies"]],
    }
    with open(trace_path, "w", encoding="utf-8") as f:
        def write(obj):
            f.write(json.dumps(obj, allow_nan=False) + "\n")
        write(header)
        write(record(scene, 0, bodies, space))
        for frame in range(1, scene["frames"] + 1):
            now = (frame - 1) * dt
            due = [i for i in pending if i["time"] <= now + 1e-12]
            pending = [i for i in pending if i["time"] > now + 1e-12]
            for i in due:
                body = bodies[i["body"]]
                point = i["point"] if i["point"] is not None else body.position
                body.apply_impulse_at_world_point(tuple(i["impulse"]), tuple(point))
            for _ in range(substeps):
                space.step(h)
            r = record(scene, frame, bodies, space)
            if not all(math.isfinite(c) for s in r["bodies"] for c in (s["x"][0], s["x"][1], s["theta"])):
                raise MirrorError(f"pymunk's state is not finite at step {frame}")
            write(r)
    return model
