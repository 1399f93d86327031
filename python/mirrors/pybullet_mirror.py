"""PyBullet mirror (docs/validation.md §"PyBullet").

Each body is a base-only multibody with the scene's mass, its inertia given as principal moments
(`localInertiaDiagonal`) in its principal frame, and a box, sphere or convex mesh collision shape
(Bullet collides a dynamic mesh as its convex hull). The ground is a plane with normal +y.
Bullet combines a pair's friction as the product of the two (btManifoldResult's combined
friction), so every collider, the ground included, gets sqrt(mu) and every pair mu. Restitution
0, no damping, no rolling or spinning friction, no sleeping.

Contacts (`getContactPoints` after the step): the normal on B points from B into A, the forces
are the last (sub)step's impulses divided by its length, normal along it and the two lateral
frictions along their directions, all acting on A.
"""

import math

import numpy as np

from common import MirrorError, applied_force, principal_frame, trace_contact

import pybullet


def version():
    return str(pybullet.getAPIVersion())


# What the PyBullet Quickstart Guide says buys accuracy (docs/validation.md §"PyBullet"):
# numSubSteps "Subdivide the physics simulation step further by 'numSubSteps'. This will trade
# performance over accuracy"; numSolverIterations "Choose the maximum number of constraint solver
# iterations" (stopping early at solverResidualThreshold, here tightened); the Coulomb cone rather
# than the pyramid (enableConeFriction).
ACCURATE = {"numSolverIterations": 500, "numSubSteps": 4, "solverResidualThreshold": 1e-10,
            "enableConeFriction": 1}


def _xyzw(r):
    from common import quat_wxyz
    w, x, y, z = quat_wxyz(r)
    return [x, y, z, w]


class Mirror:
    def __init__(self, scene, settings, workdir):
        if settings not in ("default", "accurate"):
            raise MirrorError(f"unknown settings {settings!r}")
        self.scene = scene
        self.h = scene["h"]
        self.client = pybullet.connect(pybullet.DIRECT)
        c = self.client
        pybullet.setGravity(*scene["gravity"], physicsClientId=c)
        pybullet.setTimeStep(self.h, physicsClientId=c)
        self.requested = dict(ACCURATE) if settings == "accurate" else {}
        if self.requested:
            pybullet.setPhysicsEngineParameter(physicsClientId=c, **self.requested)
        self.substeps = max(1, int(self.requested.get("numSubSteps", 0)))
        friction = math.sqrt(scene["mu"])
        self.ids = []
        self.frames = []
        for b in scene["bodies"]:
            shape = b["shape"]
            if not scene["check_collisions"]:
                cs = -1
            elif shape["kind"] == "box":
                cs = pybullet.createCollisionShape(pybullet.GEOM_BOX,
                                                   halfExtents=shape["half_extents"],
                                                   physicsClientId=c)
            elif shape["kind"] == "sphere":
                cs = pybullet.createCollisionShape(pybullet.GEOM_SPHERE, radius=shape["radius"],
                                                   physicsClientId=c)
            elif shape["kind"] == "hull":
                cs = pybullet.createCollisionShape(pybullet.GEOM_MESH,
                                                   vertices=shape["vertices"], physicsClientId=c)
            else:
                raise MirrorError(f"body {b['name']!r}: no PyBullet shape for {shape['kind']!r}")
            moments, frame = principal_frame(b["inertia"])
            r0 = np.asarray(b["R0"], dtype=float)
            body = pybullet.createMultiBody(
                baseMass=b["mass"], baseCollisionShapeIndex=cs,
                basePosition=b["x0"], baseOrientation=_xyzw(r0 @ frame),
                baseInertialFramePosition=[0, 0, 0], baseInertialFrameOrientation=_xyzw(frame),
                physicsClientId=c)
            pybullet.changeDynamics(body, -1, localInertiaDiagonal=list(moments),
                                    lateralFriction=friction, restitution=0.0,
                                    rollingFriction=0.0, spinningFriction=0.0,
                                    linearDamping=0.0, angularDamping=0.0,
                                    activationState=pybullet.ACTIVATION_STATE_DISABLE_SLEEPING,
                                    physicsClientId=c)
            pybullet.resetBaseVelocity(body, linearVelocity=b["v0"], angularVelocity=b["omega0"],
                                       physicsClientId=c)
            self.ids.append(body)
            self.frames.append(frame)
        self.ground = None
        if scene["check_collisions"]:
            plane = pybullet.createCollisionShape(pybullet.GEOM_PLANE, planeNormal=[0, 1, 0],
                                                  physicsClientId=c)
            self.ground = pybullet.createMultiBody(baseMass=0, baseCollisionShapeIndex=plane,
                                                   physicsClientId=c)
            pybullet.changeDynamics(self.ground, -1, lateralFriction=friction, restitution=0.0,
                                    rollingFriction=0.0, spinningFriction=0.0, physicsClientId=c)
        self.index = {body: k for k, body in enumerate(self.ids)}

    def integrator_name(self):
        return "bullet:semi-implicit-euler"

    def step(self, t):
        for body, b in zip(self.ids, self.scene["bodies"]):
            f = applied_force(b, t)
            if np.any(f != 0):
                x, _ = pybullet.getBasePositionAndOrientation(body, physicsClientId=self.client)
                pybullet.applyExternalForce(body, -1, list(f), list(x), pybullet.WORLD_FRAME,
                                            physicsClientId=self.client)
        pybullet.stepSimulation(physicsClientId=self.client)

    def states(self):
        out = []
        for body, frame in zip(self.ids, self.frames):
            # The base's reported pose is its inertial frame's: body rotation = Q F^T.
            x, q = pybullet.getBasePositionAndOrientation(body, physicsClientId=self.client)
            v, w = pybullet.getBaseVelocity(body, physicsClientId=self.client)
            rq = np.array(pybullet.getMatrixFromQuaternion(q)).reshape(3, 3)
            out.append((np.array(x), rq @ frame.T, np.array(v), np.array(w)))
        return out

    def contacts(self):
        out = []
        h = self.h / self.substeps
        for p in pybullet.getContactPoints(physicsClientId=self.client):
            a, b = p[1], p[2]
            n = np.array(p[7])
            force_on_a = (p[9] * n + p[10] * np.array(p[11]) + p[12] * np.array(p[13]))
            i = self.index.get(a, -1)
            j = self.index.get(b, -1)
            if i < 0:  # the ground is A: write the contact from the body's side
                i, j, n, force_on_a = j, i, -n, -force_on_a
                point = p[6]
            else:
                point = p[5]
            out.append(trace_contact(i, j, point, n, -p[8], force_on_a * h))
        return out

    def settings_used(self):
        used = dict(pybullet.getPhysicsEngineParameters(physicsClientId=self.client))
        for key in ("gravityAccelerationX", "gravityAccelerationY", "gravityAccelerationZ"):
            used.pop(key, None)
        for key, value in self.requested.items():
            used.setdefault(key, value)
        return used

    def readback(self):
        bodies = []
        for body, frame in zip(self.ids, self.frames):
            info = pybullet.getDynamicsInfo(body, -1, physicsClientId=self.client)
            moments = np.array(info[2])
            inertia = frame @ np.diag(moments) @ frame.T
            bodies.append({"mass": float(info[0]), "inertia": inertia.tolist(),
                           "com": [float(v) for v in info[3]],
                           "mu": [float(info[1])]})
        ground = []
        if self.ground is not None:
            ground = [float(pybullet.getDynamicsInfo(self.ground, -1,
                                                     physicsClientId=self.client)[1])]
        params = pybullet.getPhysicsEngineParameters(physicsClientId=self.client)
        return {"h": float(params["fixedTimeStep"]),
                "gravity": [params["gravityAccelerationX"], params["gravityAccelerationY"],
                            params["gravityAccelerationZ"]],
                "bodies": bodies, "ground_mu": ground,
                "pair_mu_rule": "product of the two colliders' lateral friction"}
