#!/usr/bin/env python3
"""Cadoux's fixed point on de Saxcé's cone problem, with interior-point subproblems, and an
optional polish by rigidref's Newton solver (issue 48 item 2; docs/problem-library.md
§"RockPile_tob1", **A convex-programming route**).

    python3 python/cadoux_fixed_point.py PROBLEM [--iterations 150] [--damping 0.5]
                                         [--polish 3] [--out answer.json]

PROBLEM is any 3D problem rigidref reads (a Siconos `.dat`, FCLIB `.hdf5` where the bindings
were built with it, or a rigidref problem file), taken in its local form w = W λ + q.

The method (Cadoux 2009; Acary, Cadoux, Lemaréchal and Malick, ZAMM 2011). Coulomb's law per
contact is de Saxcé's complementarity between the friction cone K = {‖λ_T‖ ≤ μ λ_n} and its dual
K* = {μ‖ŵ_T‖ ≤ ŵ_n}, for the modified velocity ŵ = w + μ‖w_T‖ e_n. With s_k (one number per
contact) frozen in place of ‖w_T,k‖, and W symmetric positive semidefinite, the condition

    K ∋ λ ⊥ W λ + q + μ s e_n ∈ K*

is the optimality condition of the convex second-order-cone program

    minimise ½ λᵀ W λ + (q + μ s e_n)ᵀ λ   over λ ∈ K,

which an interior-point method (Clarabel) solves whatever W's null space. A point where
s = ‖w_T(λ)‖ solves the Coulomb problem. The iteration here:

    λ_{k+1} = argmin over K of ½ λᵀ W_s λ + (q + W_a λ_k + μ s_k e_n)ᵀ λ,
    s_{k+1} = (1 − α) s_k + α ‖w_T(λ_{k+1})‖,

with W_s, W_a the symmetric and antisymmetric parts of W (a file's W need not be symmetric; the
antisymmetric part is lagged, so a fixed point still solves the file's problem) and α the
damping. Nothing guarantees convergence of the map for large μ; each iterate is judged by
Siconos' error (rigidref.siconos_error), as every answer in the project is.

--polish K then runs rigidref's Newton solver K times, each warm-started from the best answer so
far (200 iterations per run and its proximal fallback, as `solve-problems` uses it).

Prints the error every tenth iteration and a summary; --out writes λ (one [n, t1, t2] per
contact), the errors and the settings as JSON. Needs numpy, scipy, clarabel and the rigidref
Python module (bindings/python).
"""
import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np


def local_form(path):
    """(problem in local form, dense W, q, μ) of a 3D problem file, or exit with one line."""
    import rigidref

    try:
        problem = rigidref.ContactProblem.read(str(path)).to_local()
    except (rigidref.ProblemError, OSError) as e:
        message = str(e).splitlines()[0] if str(e) else type(e).__name__
        sys.exit(message if str(path) in message else f"{path}: {message}")
    if problem.rows_per_contact != 3 or problem.friction_model != "cone":
        sys.exit(f"{path}: a 3D cone-friction problem is needed (this one has "
                 f"{problem.rows_per_contact} rows per contact, {problem.friction_model} friction)")
    w = problem.W
    w = w.to_dense() if hasattr(w, "to_dense") else np.asarray(w, dtype=float)
    return problem, np.asarray(w, dtype=float), np.asarray(problem.b, dtype=float).ravel(), \
        np.asarray(problem.mu, dtype=float)


def cone_subproblem(w_sym, mu):
    """The fixed parts of Clarabel's program: P (upper triangle of W_s), A, b and the cones, so
    that A λ + s = b with s = (μ λ_n, λ_t1, λ_t2) ∈ SOC(3) per contact, i.e. λ ∈ K."""
    import clarabel
    from scipy import sparse

    n = len(mu)
    scale = np.ones(3 * n)
    scale[0::3] = mu
    p = sparse.triu(sparse.csc_matrix(w_sym)).tocsc()
    a = -sparse.diags(scale).tocsc()
    return p, a, np.zeros(3 * n), [clarabel.SecondOrderConeT(3)] * n


def fixed_point(w, q, mu, iterations, damping, error, report=print, tolerance=0.0, start=None):
    """Runs the damped fixed point; returns (best λ, best error, errors per iteration).
    `error(λ)` judges an iterate; the run stops early where it is at most `tolerance`. `start`:
    λ to begin from (3n values; s from its ‖w_T‖), else λ = 0 and s = 0."""
    import clarabel

    w_sym, w_anti = 0.5 * (w + w.T), 0.5 * (w - w.T)
    p, a, b, cones = cone_subproblem(w_sym, mu)
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.tol_gap_abs = settings.tol_gap_rel = settings.tol_feas = 1e-12
    settings.max_iter = 200
    n = len(mu)
    lam = np.zeros(3 * n) if start is None else np.asarray(start, dtype=float).ravel().copy()
    vel = w @ lam + q
    s = np.zeros(n) if start is None else np.hypot(vel[1::3], vel[2::3])
    best, best_error, errors = lam, math.inf, []
    for k in range(iterations):
        c = q + w_anti @ lam
        c[0::3] += mu * s
        solution = clarabel.DefaultSolver(p, c, a, b, cones, settings).solve()
        if str(solution.status) not in ("Solved", "AlmostSolved"):
            report(f"iteration {k}: the cone program ended {solution.status}; stopping")
            break
        lam = np.array(solution.x)
        vel = w @ lam + q
        s = (1.0 - damping) * s + damping * np.hypot(vel[1::3], vel[2::3])
        e = error(lam)
        errors.append(e)
        if e < best_error:
            best, best_error = lam, e
        if k % 10 == 9 or k == iterations - 1:
            report(f"iteration {k + 1}: Siconos' error {e:.3e} (best {best_error:.3e})")
        if best_error <= tolerance:
            break
    return best, best_error, errors


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("problem", help="a 3D contact problem file (.dat, .hdf5 or rigidref JSON)")
    ap.add_argument("--iterations", type=int, default=150,
                    help="fixed-point iterations (one cone program each; default 150); 0: "
                         "none, the polish starts from λ = 0")
    ap.add_argument("--damping", type=float, default=0.5,
                    help="α in s ← (1 − α) s + α ‖w_T‖, in (0, 1] (default 0.5)")
    ap.add_argument("--tolerance", type=float, default=1e-8,
                    help="stop the fixed point at this Siconos error (default 1e-8)")
    ap.add_argument("--polish", type=int, default=0,
                    help="Newton runs warm-started from the best answer (default 0)")
    ap.add_argument("--out", help="write λ, the errors and the settings as JSON")
    args = ap.parse_args()
    if not 0.0 < args.damping <= 1.0:
        sys.exit(f"--damping {args.damping}: must be in (0, 1]")
    if args.iterations < 0:
        sys.exit(f"--iterations {args.iterations}: must be at least 0")
    if args.iterations == 0 and args.polish == 0:
        sys.exit("--iterations 0 needs --polish (Newton from λ = 0, restarted from its best)")
    if args.polish < 0:
        sys.exit(f"--polish {args.polish}: must be at least 0")
    try:
        import clarabel  # noqa: F401
        import rigidref
        import scipy  # noqa: F401
    except ImportError as e:
        sys.exit(f"cadoux_fixed_point.py: {e} (pip install clarabel scipy ./bindings/python)")

    problem, w, q, mu = local_form(Path(args.problem))
    n = len(mu)

    def error(lam):
        return rigidref.siconos_error(problem, lam.reshape(n, 3))

    print(f"{args.problem}: {n} contacts, max |W − Wᵀ| = {np.abs(w - w.T).max():.3g}")
    start = time.perf_counter()
    lam, best, errors = fixed_point(w, q, mu, args.iterations, args.damping, error,
                                    tolerance=args.tolerance)
    fp_seconds = time.perf_counter() - start
    if errors:
        print(f"fixed point: {len(errors)} iterations, {fp_seconds:.1f} s, best error {best:.3e}")
    else:
        best = error(lam)
        print(f"no fixed point: the polish starts from λ = 0 (error {best:.3e})")
    polished = []
    for k in range(args.polish):
        t = time.perf_counter()
        answer = rigidref.solve_newton(problem, max_iterations=200, tolerance=1e-13,
                                       proximal_iterations=60, warm_start=lam.reshape(n, 3))
        cand = np.asarray(answer.lam, dtype=float).ravel()
        e = error(cand)
        polished.append({"error": e, "iterations": answer.iterations, "method": answer.method,
                         "seconds": time.perf_counter() - t})
        print(f"Newton polish {k + 1}: {answer.method}, {answer.iterations} iterations, "
              f"{polished[-1]['seconds']:.1f} s, error {e:.3e}")
        if e < best:
            lam, best = cand, e
    print(f"best: Siconos' error {best:.3e} ({'≤' if best <= args.tolerance else '>'} "
          f"{args.tolerance:g})")
    if args.out:
        Path(args.out).write_text(json.dumps({
            "problem": str(args.problem), "iterations": args.iterations,
            "damping": args.damping, "fixed_point_errors": errors,
            "fixed_point_seconds": fp_seconds, "polish": polished, "error": best,
            "lambda": lam.reshape(n, 3).tolist()}))


if __name__ == "__main__":
    main()
