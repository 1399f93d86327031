"""MuJoCo mirror (docs/validation.md §"MuJoCo").

Each body is a free body with its mass and full inertia given explicitly (`<inertial
fullinertia>`), a box, sphere or mesh geom (MuJoCo collides a mesh as its convex hull) and
sliding friction mu (condim 3: no torsional or rolling friction; MuJoCo combines a pair's
friction as the larger of the two, so every pair gets mu). The ground is a plane whose normal is
+y (`zaxis="0 1 0"`). rigidref's frame (y up) is kept: gravity is the scene's vector.

Free joints: qvel[0:3] is the body origin's (= centre of mass) velocity in the world frame,
qvel[3:6] the angular velocity in the body frame. Contacts: `mj_contactForce` gives each
contact's force in its frame (normal from geom1 to geom2), the force geom1 exerts on geom2.
"""

import numpy as np

from common import MirrorError, applied_force, matrix_of_quat_wxyz, quat_wxyz, trace_contact

import mujoco


def version():
    return mujoco.__version__


def _floats(values):
    return " ".join(repr(float(v)) for v in np.asarray(values, dtype=float).ravel())


# The settings the MuJoCo documentation recommends for accuracy (docs/validation.md §"MuJoCo"):
# the implicitfast integrator ("The default recommended choice", Modeling §"Performance tuning"),
# and against slip "elliptic cones, large impratio, and the Newton algorithm with very small
# tolerance" (Modeling §"Solver parameters"), tolerance 1e-10 ("aggressive tolerance values, say
# 1e-10"); contacts as stiff as allowed: solref timeconst 2 h ("should be at least two times larger
# than the simulation time step").
def _accurate(h):
    return {"integrator": "implicitfast", "cone": "elliptic", "impratio": 10.0,
            "solver": "Newton", "tolerance": 1e-10, "solref": [2.0 * h, 1.0]}


class Mirror:
    def __init__(self, scene, settings, workdir):
        self.scene = scene
        self.h = scene["h"]
        if settings not in ("default", "accurate"):
            raise MirrorError(f"unknown settings {settings!r}")
        self.requested = {} if settings == "default" else _accurate(self.h)
        xml = self._mjcf()
        self.model = mujoco.MjModel.from_xml_string(xml)
        self.data = mujoco.MjData(self.model)
        for k, body in enumerate(scene["bodies"]):
            adr = self.model.jnt_qposadr[self.model.body_jntadr[k + 1]]
            vadr = self.model.jnt_dofadr[self.model.body_jntadr[k + 1]]
            rotation = np.asarray(body["R0"], dtype=float)
            self.data.qpos[adr:adr + 3] = body["x0"]
            self.data.qpos[adr + 3:adr + 7] = quat_wxyz(rotation)
            self.data.qvel[vadr:vadr + 3] = body["v0"]
            self.data.qvel[vadr + 3:vadr + 6] = rotation.T @ np.asarray(body["omega0"], float)
        mujoco.mj_forward(self.model, self.data)
        self._force = np.zeros(6)

    def _mjcf(self):
        s = self.scene
        opt = [f'timestep="{self.h!r}"', f'gravity="{_floats(s["gravity"])}"']
        for key in ("integrator", "cone", "impratio", "solver", "tolerance"):
            if key in self.requested:
                opt.append(f'{key}="{self.requested[key]}"')
        flags = "" if s["check_collisions"] else '<flag contact="disable"/>'
        solref = (f' solref="{_floats(self.requested["solref"])}"'
                  if "solref" in self.requested else "")
        mu = s["mu"]
        assets, bodies = [], []
        for k, b in enumerate(s["bodies"]):
            shape = b["shape"]
            if shape["kind"] == "box":
                geom = f'type="box" size="{_floats(shape["half_extents"])}"'
            elif shape["kind"] == "sphere":
                geom = f'type="sphere" size="{shape["radius"]!r}"'
            elif shape["kind"] == "hull":
                assets.append(f'<mesh name="hull{k}" vertex="{_floats(shape["vertices"])}"/>')
                geom = f'type="mesh" mesh="hull{k}"'
            else:
                raise MirrorError(f"body {b['name']!r}: no MuJoCo shape for {shape['kind']!r}")
            i = np.asarray(b["inertia"], dtype=float)
            full = [i[0, 0], i[1, 1], i[2, 2], i[0, 1], i[0, 2], i[1, 2]]
            bodies.append(
                f'<body name="b{k}"><freejoint/>'
                f'<inertial pos="0 0 0" mass="{float(b["mass"])!r}" fullinertia="{_floats(full)}"/>'
                f'<geom {geom} friction="{mu!r} 0 0" condim="3"{solref}/></body>')
        ground = (f'<geom name="ground" type="plane" size="0 0 1" zaxis="0 1 0" '
                  f'friction="{mu!r} 0 0" condim="3"{solref}/>') if s["check_collisions"] else ""
        return (f'<mujoco model="rigidref mirror"><compiler angle="radian"/>'
                f'<option {" ".join(opt)}>{flags}</option>'
                f'<asset>{"".join(assets)}</asset>'
                f'<worldbody>{ground}{"".join(bodies)}</worldbody></mujoco>')

    def integrator_name(self):
        return "mujoco:" + mujoco.mjtIntegrator(self.model.opt.integrator).name

    def step(self, t):
        self.data.xfrc_applied[:] = 0.0
        for k, b in enumerate(self.scene["bodies"]):
            self.data.xfrc_applied[k + 1, 0:3] = applied_force(b, t)
        mujoco.mj_step(self.model, self.data)

    def states(self):
        out = []
        for k in range(len(self.scene["bodies"])):
            adr = self.model.jnt_qposadr[self.model.body_jntadr[k + 1]]
            vadr = self.model.jnt_dofadr[self.model.body_jntadr[k + 1]]
            rotation = matrix_of_quat_wxyz(self.data.qpos[adr + 3:adr + 7])
            out.append((self.data.qpos[adr:adr + 3].copy(), rotation,
                        self.data.qvel[vadr:vadr + 3].copy(),
                        rotation @ self.data.qvel[vadr + 3:vadr + 6]))
        return out

    def contacts(self):
        out = []
        for c in range(self.data.ncon):
            contact = self.data.contact[c]
            mujoco.mj_contactForce(self.model, self.data, c, self._force)
            frame = contact.frame.reshape(3, 3)
            force_on_2 = frame.T @ self._force[0:3]
            i = int(self.model.geom_bodyid[contact.geom2]) - 1
            j = int(self.model.geom_bodyid[contact.geom1]) - 1
            out.append(trace_contact(i, j, contact.pos, frame[0], -contact.dist,
                                     force_on_2 * self.h))
        return out

    def settings_used(self):
        o = self.model.opt
        return {
            "timestep": float(o.timestep),
            "integrator": mujoco.mjtIntegrator(o.integrator).name,
            "cone": mujoco.mjtCone(o.cone).name,
            "solver": mujoco.mjtSolver(o.solver).name,
            "impratio": float(o.impratio),
            "iterations": int(o.iterations),
            "tolerance": float(o.tolerance),
            "noslip_iterations": int(o.noslip_iterations),
            "solref": [float(v) for v in self.model.geom_solref[0]] if self.model.ngeom else None,
            "solimp": [float(v) for v in self.model.geom_solimp[0]] if self.model.ngeom else None,
        }

    def readback(self):
        m = self.model
        bodies = []
        for k in range(len(self.scene["bodies"])):
            r = matrix_of_quat_wxyz(m.body_iquat[k + 1])
            inertia = r @ np.diag(m.body_inertia[k + 1]) @ r.T
            geoms = [g for g in range(m.ngeom) if m.geom_bodyid[g] == k + 1]
            bodies.append({"mass": float(m.body_mass[k + 1]),
                           "inertia": inertia.tolist(),
                           "com": [float(v) for v in m.body_ipos[k + 1]],
                           "mu": [float(m.geom_friction[g][0]) for g in geoms]})
        ground = [float(m.geom_friction[g][0]) for g in range(m.ngeom) if m.geom_bodyid[g] == 0]
        return {"h": float(m.opt.timestep), "gravity": [float(v) for v in m.opt.gravity],
                "bodies": bodies, "ground_mu": ground,
                "pair_mu_rule": "max of the two geoms' sliding friction"}
