"""Drake mirror (docs/validation.md §"Drake").

A discrete MultibodyPlant with time step h (`MultibodyPlantConfig`), each body a free rigid body
with the scene's mass and central inertia (`SpatialInertia.MakeFromCentralInertia`) whose frame
is at its centre of mass, its collision geometry a Box, Sphere or Convex (a hull written as an OBJ
beside the trace; Drake collides a Convex as the hull of its vertices) with Coulomb friction mu
(Drake combines a pair's friction as 2 mu1 mu2 / (mu1 + mu2), so every pair gets mu). The ground is
a HalfSpace with normal +y. No geometry has hydroelastic properties, so the default contact model
`hydroelastic_with_fallback` uses point contact everywhere.

Contacts: the plant's contact results after each step (sampled output ports, the default: the
results the step used); a point pair's force is on body B, its normal points from B into A.
"""

import importlib.metadata
import os

import numpy as np

from common import MirrorError, applied_force, principal_frame, trace_contact, write_obj

from pydrake.geometry import (AddCompliantHydroelasticProperties, AddContactMaterial,
                              AddRigidHydroelasticProperties, Box, Convex, HalfSpace,
                              ProximityProperties, Sphere)
from pydrake.math import RigidTransform, RotationMatrix
from pydrake.multibody.math import SpatialForce, SpatialVelocity
from pydrake.multibody.plant import (AddMultibodyPlant, CoulombFriction,
                                     ExternallyAppliedSpatialForce, MultibodyPlantConfig)
from pydrake.multibody.tree import RotationalInertia, SpatialInertia
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import DiagramBuilder


def version():
    return importlib.metadata.version("drake")


# What Drake's documentation recommends for accuracy (docs/validation.md §"Drake"):
# DiscreteContactApproximation: "If strong transients do need to be accurately resolved [...]
# kSimilar is the preferred approximation" (impacts, a heavy body landing on a light one);
# set_stiction_tolerance: the slip one is "willing to allow" in stiction, here 1e-5 m/s (ten times
# below the default 1e-4) against the closed forms' sticking phases; set_penetration_allowance:
# the point-contact stiffness is estimated from it, here 1e-4 m (ten times stiffer).
ACCURATE = {"discrete_contact_approximation": "similar", "stiction_tolerance": 1e-5,
            "penetration_allowance": 1e-4}
# And hydroelastic contact: Drake's point contact gives one point per pair of convex shapes (a box
# on the ground rocks on its deepest corner), its documentation's answer for surfaces in contact
# is the hydroelastic model, compliant bodies against a rigid ground ("Hydroelastic Contact"
# user guide). Modulus 1e7 Pa (stiff: a 1 kg cube of 0.2 m rests 2.5 µm deep; softer than rubber-like 1e6, and
# not so stiff that the scenes' starting overlap of 0.1 mm throws a body off); the resolution hint a tenth of
# the body's smallest half size (tessellated spheres and hulls).
HYDROELASTIC_MODULUS = 1e7


class Mirror:
    def __init__(self, scene, settings, workdir):
        if settings not in ("default", "accurate"):
            raise MirrorError(f"unknown settings {settings!r}")
        self.scene = scene
        self.h = scene["h"]
        self.requested = dict(ACCURATE) if settings == "accurate" else {}
        config = MultibodyPlantConfig(time_step=self.h, **self.requested)
        builder = DiagramBuilder()
        plant, scene_graph = AddMultibodyPlant(config, builder)
        plant.mutable_gravity_field().set_gravity_vector(np.asarray(scene["gravity"], float))
        friction = CoulombFriction(scene["mu"], scene["mu"])
        self.hydroelastic = settings == "accurate"

        def properties(rigid, size):
            props = ProximityProperties()
            AddContactMaterial(friction=friction, properties=props)
            if rigid:
                AddRigidHydroelasticProperties(props)
            else:
                AddCompliantHydroelasticProperties(0.1 * size, HYDROELASTIC_MODULUS, props)
            return props
        self.bodies = []
        for k, b in enumerate(scene["bodies"]):
            i = np.asarray(b["inertia"], dtype=float)
            inertia = SpatialInertia.MakeFromCentralInertia(
                b["mass"], np.zeros(3),
                RotationalInertia(i[0, 0], i[1, 1], i[2, 2], i[0, 1], i[0, 2], i[1, 2]))
            body = plant.AddRigidBody(f"b{k}", inertia)
            if scene["check_collisions"]:
                shape = b["shape"]
                if shape["kind"] == "box":
                    geometry = Box(*(2.0 * np.asarray(shape["half_extents"], float)))
                elif shape["kind"] == "sphere":
                    geometry = Sphere(shape["radius"])
                elif shape["kind"] == "hull":
                    path = os.path.join(workdir, f"{scene['scene_file']}-hull{k}.obj")
                    write_obj(path, shape["vertices"])
                    geometry = Convex(path)
                else:
                    raise MirrorError(f"body {b['name']!r}: no Drake shape for {shape['kind']!r}")
                if self.hydroelastic:
                    size = float(np.min(shape.get("half_extents", [shape.get("radius", 0.0)])))
                    if shape["kind"] == "hull":
                        v = np.asarray(shape["vertices"], float)
                        size = float(np.min(v.max(axis=0) - v.min(axis=0))) / 2
                    plant.RegisterCollisionGeometry(body, RigidTransform(), geometry, f"g{k}",
                                                    properties(False, size))
                else:
                    plant.RegisterCollisionGeometry(body, RigidTransform(), geometry, f"g{k}",
                                                    friction)
            self.bodies.append(body)
        if scene["check_collisions"]:
            plant.RegisterCollisionGeometry(
                plant.world_body(), RigidTransform(HalfSpace.MakePose([0, 1, 0], [0, 0, 0])),
                HalfSpace(), "ground", properties(True, 0.0) if self.hydroelastic else friction)
        plant.Finalize()
        self.plant = plant
        self.scene_graph = scene_graph
        diagram = builder.Build()
        self.simulator = Simulator(diagram)
        self.context = self.simulator.get_mutable_context()
        self.plant_context = plant.GetMyMutableContextFromRoot(self.context)
        for body, b in zip(self.bodies, scene["bodies"]):
            pose = RigidTransform(RotationMatrix(np.asarray(b["R0"], float)),
                                  np.asarray(b["x0"], float))
            plant.SetFreeBodyPose(self.plant_context, body, pose)
            plant.SetFreeBodySpatialVelocity(
                self.plant_context, body,
                SpatialVelocity(np.asarray(b["omega0"], float), np.asarray(b["v0"], float)))
        self.loaded = any(np.any(np.asarray(b["force"]) != 0) or np.any(np.asarray(b["force_rate"]) != 0)
                          for b in scene["bodies"])
        self.index = {body.index(): k for k, body in enumerate(self.bodies)}
        self.time = 0.0
        self.steps = 0
        self.simulator.Initialize()

    def integrator_name(self):
        return "drake:discrete-" + str(self.plant.get_discrete_contact_approximation()).split(".")[-1]

    def step(self, t):
        if self.loaded:
            forces = []
            for body, b in zip(self.bodies, self.scene["bodies"]):
                force = ExternallyAppliedSpatialForce()
                force.body_index = body.index()
                force.p_BoBq_B = np.zeros(3)
                force.F_Bq_W = SpatialForce(np.zeros(3), applied_force(b, t))
                forces.append(force)
            self.plant.get_applied_spatial_force_input_port().FixValue(self.plant_context, forces)
        self.steps += 1
        self.simulator.AdvanceTo(self.steps * self.h)

    def states(self):
        out = []
        for body in self.bodies:
            pose = self.plant.EvalBodyPoseInWorld(self.plant_context, body)
            velocity = self.plant.EvalBodySpatialVelocityInWorld(self.plant_context, body)
            out.append((pose.translation(), pose.rotation().matrix(),
                        velocity.translational(), velocity.rotational()))
        return out

    def contacts(self):
        if not self.scene["check_collisions"]:
            return []
        results = self.plant.get_contact_results_output_port().Eval(self.plant_context)
        out = []
        for c in range(results.num_point_pair_contacts()):
            info = results.point_pair_contact_info(c)
            pair = info.point_pair()
            a = self.index.get(info.bodyA_index(), -1)
            b = self.index.get(info.bodyB_index(), -1)
            n = np.asarray(pair.nhat_BA_W)
            force_on_a = -np.asarray(info.contact_force())
            if a < 0:
                a, b, n, force_on_a = b, a, -n, -force_on_a
            out.append(trace_contact(a, b, info.contact_point(), n, pair.depth,
                                     force_on_a * self.h))
        inspector = self.scene_graph.model_inspector()
        for c in range(results.num_hydroelastic_contacts()):
            # One trace contact per contact surface: at its centroid, the area-weighted normal
            # (out of N, into M), the integrated traction's force on M's body (A). The moment of
            # the pressure about the centroid is not in the trace.
            info = results.hydroelastic_contact_info(c)
            surface = info.contact_surface()
            normal = np.zeros(3)
            for f in range(surface.num_faces()):
                normal += surface.area(f) * np.asarray(surface.face_normal(f))
            a = self.index.get(self.plant.GetBodyFromFrameId(
                inspector.GetFrameId(surface.id_M())).index(), -1)
            b = self.index.get(self.plant.GetBodyFromFrameId(
                inspector.GetFrameId(surface.id_N())).index(), -1)
            if not np.linalg.norm(normal) > 0.0:
                continue  # a surface of zero area (the step it first touches): no normal, no force
            force_on_a = np.asarray(info.F_Ac_W().translational())
            n = normal / np.linalg.norm(normal)
            if a < 0:
                a, b, n, force_on_a = b, a, -n, -force_on_a
            out.append(trace_contact(a, b, surface.centroid(), n, 0.0, force_on_a * self.h))
        return out

    def settings_used(self):
        p = self.plant
        return {"time_step": p.time_step(),
                "discrete_contact_approximation":
                    str(p.get_discrete_contact_approximation()).split(".")[-1],
                "contact_model": str(p.get_contact_model()).split(".")[-1],
                "penetration_allowance": self.requested.get("penetration_allowance", 1e-3),
                "stiction_tolerance": self.requested.get("stiction_tolerance", 1e-4),
                "sap_near_rigid_threshold": p.get_sap_near_rigid_threshold(),
                "use_sampled_output_ports": True,
                "geometry": ("compliant hydroelastic bodies (modulus %g Pa) on a rigid hydroelastic ground"
                             % HYDROELASTIC_MODULUS) if self.hydroelastic
                            else "point contact (no hydroelastic properties)"}

    def readback(self):
        inspector = self.scene_graph.model_inspector()
        bodies = []
        for body in self.bodies:
            inertia = body.default_rotational_inertia().CopyToFullMatrix3()
            mu = []
            for g in self.plant.GetCollisionGeometriesForBody(body):
                props = inspector.GetProximityProperties(g)
                mu.append(props.GetProperty("material", "coulomb_friction").dynamic_friction())
            bodies.append({"mass": float(body.default_mass()), "inertia": inertia.tolist(),
                           "com": list(body.default_com()), "mu": mu})
        ground = []
        for g in self.plant.GetCollisionGeometriesForBody(self.plant.world_body()):
            props = inspector.GetProximityProperties(g)
            ground.append(props.GetProperty("material", "coulomb_friction").dynamic_friction())
        return {"h": self.plant.time_step(),
                "gravity": list(self.plant.gravity_field().gravity_vector()),
                "bodies": bodies, "ground_mu": ground,
                "pair_mu_rule": "2 mu1 mu2 / (mu1 + mu2)"}
