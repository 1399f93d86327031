"""Siconos' own error of chosen non-solutions λ, kept as test data for rigidref's `siconos_error`.

Run with Debian's python3-siconos (Siconos 4.4): `/usr/bin/python3 make_errors.py > errors.json`
in this folder. For each problem and each λ it calls Siconos' C function (fc3d_compute_error for
3D, fc2d_compute_error for 2D, the latter through ctypes since the Python module does not wrap
it) with norm = ‖q‖, as Siconos' solvers call it, and with norm = 0 (the bare max(‖λ‖, ‖w‖)
scaling), and writes λ (each number with 17 significant digits) and the two errors.
tests/suite/solve/siconos_error.rs reads errors.json and checks rigidref against it.
"""
import ctypes
import json

import numpy as np
import siconos.numerics as sn

lib = ctypes.CDLL("libsiconos_numerics.so.7")
DOUBLE_P = ctypes.POINTER(ctypes.c_double)
lib.fc2d_compute_error.restype = ctypes.c_int
lib.fc2d_compute_error.argtypes = [
    ctypes.c_void_p, DOUBLE_P, DOUBLE_P, ctypes.c_double, ctypes.c_double, DOUBLE_P]

# (file relative to tests/data, λ generators' seeds)
PROBLEMS = [
    ("siconos/Confeti-ex13-4contact-Fc3D-SBM.dat", [1, 2]),
    ("siconos/FC3D_Example1_SBM.dat", [3]),
    ("siconos/Rover11035.dat", [4]),
    ("siconos_error/fc2d_three_contacts.dat", [5, 6]),
]


def error(problem, dim, lam, norm):
    n = lam.size
    w = np.zeros(n)
    if dim == 3:
        info, e = sn.fc3d_compute_error(problem, lam, w, 1e-300, None, norm)
        return e
    e = ctypes.c_double()
    lib.fc2d_compute_error(int(problem.this), lam.ctypes.data_as(DOUBLE_P),
                           w.ctypes.data_as(DOUBLE_P), 1e-300, norm, ctypes.byref(e))
    return e.value


out = []
for path, seeds in PROBLEMS:
    problem = sn.frictionContact_new_from_filename("../" + path)
    dim, nc = problem.dimension, problem.numberOfContacts
    q = np.array(problem.q)
    for seed in seeds:
        rng = np.random.default_rng(seed)
        # Impulses of the size of q's entries, some outside the cone and some with λn < 0.
        scale = max(np.abs(q).max(), 1.0)
        lam = np.array([float("%.17g" % v) for v in rng.uniform(-0.5, 1.0, dim * nc) * scale])
        out.append({
            "file": path,
            "lambda": [float(v) for v in lam],
            "error_norm_q": error(problem, dim, lam.copy(), float(np.linalg.norm(q))),
            "error_norm_0": error(problem, dim, lam.copy(), 0.0),
        })
print(json.dumps({"siconos": "4.4.0 (Debian python3-siconos 4.4.0+dfsg-2)", "cases": out}, indent=1))
