"""What every engine mirror shares: the mirror description (docs/validation.md §"Mirror
description"), rotations, rigidref's contact frame, and the trace contacts.

The description is written by rigidref (`src/tools/validation/mirror.rs::MirrorScene`) from the
scene file, so every mirror reads the same bodies, masses, inertias, shapes, friction, gravity and
step: nothing here parses a scene. Units are SI, y up, as everywhere in rigidref.
"""

import json
import math

import numpy as np

MIRROR_FORMAT = "rigidref-mirror"
MIRROR_VERSION = 1


class MirrorError(Exception):
    """A mirror that cannot be built or run; its message is one line."""


def load_description(path):
    with open(path, encoding="utf-8") as f:
        scene = json.load(f)
    if scene.get("format") != MIRROR_FORMAT or scene.get("version") != MIRROR_VERSION:
        raise MirrorError(f"{path}: not a {MIRROR_FORMAT} version {MIRROR_VERSION} file")
    return scene


def contact_frame(n):
    """rigidref's contact frame for a unit normal n (src/rigid3d/frame.rs::ContactFrame::from_normal):
    t1 = n x e / |n x e| with e the world axis least aligned with n, t2 = n x t1."""
    n = np.asarray(n, dtype=float)
    ax, ay, az = abs(n[0]), abs(n[1]), abs(n[2])
    if ax <= ay and ax <= az:
        axis = np.array([1.0, 0.0, 0.0])
    elif ay <= az:
        axis = np.array([0.0, 1.0, 0.0])
    else:
        axis = np.array([0.0, 0.0, 1.0])
    t1 = np.cross(n, axis)
    t1 /= np.linalg.norm(t1)
    t2 = np.cross(n, t1)
    return n, t1, t2


def trace_contact(i, j, p, n, depth, impulse_on_i):
    """A trace contact (docs/trace-format.md): body i pushed by `impulse_on_i` (N s, world frame)
    from body j (-1 the ground), n the unit normal from j into i, the impulse written in rigidref's
    frame (n, t1, t2) of n."""
    n = np.asarray(n, dtype=float)
    n = n / np.linalg.norm(n)
    n, t1, t2 = contact_frame(n)
    impulse = np.asarray(impulse_on_i, dtype=float)
    return {
        "bodies": [int(i), int(j)],
        "p": [float(x) for x in p],
        "n": [float(x) for x in n],
        "depth": float(depth),
        "lambda": [float(impulse @ n), float(impulse @ t1), float(impulse @ t2)],
    }


def quat_wxyz(r):
    """The unit quaternion (w, x, y, z) of a rotation matrix (Shepperd's method)."""
    r = np.asarray(r, dtype=float)
    t = np.trace(r)
    if t > 0:
        s = math.sqrt(t + 1.0) * 2
        q = [0.25 * s, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s]
    elif r[0, 0] > r[1, 1] and r[0, 0] > r[2, 2]:
        s = math.sqrt(1.0 + r[0, 0] - r[1, 1] - r[2, 2]) * 2
        q = [(r[2, 1] - r[1, 2]) / s, 0.25 * s, (r[0, 1] + r[1, 0]) / s, (r[0, 2] + r[2, 0]) / s]
    elif r[1, 1] > r[2, 2]:
        s = math.sqrt(1.0 + r[1, 1] - r[0, 0] - r[2, 2]) * 2
        q = [(r[0, 2] - r[2, 0]) / s, (r[0, 1] + r[1, 0]) / s, 0.25 * s, (r[1, 2] + r[2, 1]) / s]
    else:
        s = math.sqrt(1.0 + r[2, 2] - r[0, 0] - r[1, 1]) * 2
        q = [(r[1, 0] - r[0, 1]) / s, (r[0, 2] + r[2, 0]) / s, (r[1, 2] + r[2, 1]) / s, 0.25 * s]
    q = np.array(q)
    return q / np.linalg.norm(q)


def matrix_of_quat_wxyz(q):
    w, x, y, z = (float(c) for c in q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def principal_frame(inertia):
    """Principal moments and a right-handed frame (columns) of a symmetric inertia; a diagonal
    inertia (off-diagonals below 1e-12 of its trace) keeps the identity frame and its diagonal."""
    inertia = np.asarray(inertia, dtype=float)
    off = np.abs(inertia - np.diag(np.diag(inertia))).max()
    if off <= 1e-12 * np.trace(inertia):
        return np.diag(inertia).copy(), np.eye(3)
    moments, frame = np.linalg.eigh(inertia)
    if np.linalg.det(frame) < 0:
        frame[:, 2] *= -1
    return moments, frame


def applied_force(body, t):
    """The scene's load on a body at time t (s): force + force_rate t, N (rigidref applies it at
    each step's start: src/rigid3d/world.rs)."""
    return np.asarray(body["force"], dtype=float) + np.asarray(body["force_rate"], dtype=float) * t


def write_obj(path, vertices):
    """The hull's vertices as an OBJ point set with one dummy face list (engines that load a convex
    mesh from a file take the convex hull of its vertices)."""
    vertices = np.asarray(vertices, dtype=float)
    with open(path, "w", encoding="utf-8") as f:
        for v in vertices:
            f.write(f"v {float(v[0])!r} {float(v[1])!r} {float(v[2])!r}\n")
        faces = _hull_faces(vertices)
        for a, b, c in faces:
            f.write(f"f {a + 1} {b + 1} {c + 1}\n")


def _hull_faces(vertices):
    """Triangles of the convex hull of `vertices` (scipy's Qhull), wound outward."""
    try:
        from scipy.spatial import ConvexHull
        hull = ConvexHull(vertices)
        faces = []
        centre = vertices.mean(axis=0)
        for simplex in hull.simplices:
            a, b, c = (int(k) for k in simplex)
            normal = np.cross(vertices[b] - vertices[a], vertices[c] - vertices[a])
            if normal @ (vertices[a] - centre) < 0:
                b, c = c, b
            faces.append((a, b, c))
        return faces
    except ImportError as e:
        raise MirrorError("writing a convex mesh needs scipy (pip install scipy)") from e
