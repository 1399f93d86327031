"""Solve a 3D friction-contact problem whose Newton iteration stalls on near-duplicate contacts
("twins"), by leaving one contact of each stalled pair out (docs/problem-library.md
§"RockPile_tob1").

A contact left out with zero impulse satisfies de Saxcé's form of the law exactly where its
normal velocity w_n ≥ 0, whatever μ; so an exact answer of the problem without it, extended by
zeros, is an exact answer of the whole problem wherever the left-out contacts end with w_n ≥ 0.
Every candidate is judged on the whole problem by Siconos' error (`rigidref.siconos_error`).

The steps: Newton (rigidref's, through the Python bindings) from λ = 0 or `--start`, then from
its own answer `--polish` times; then the reductions, each reduced problem solved by Newton
warm-started from the best answer so far (by the whole problem's error), until one is at or
below `--tolerance`. The reductions are those `--leave-out` names, in turn, or else every choice
of one contact per twin pair, in order: the contacts that carry 99 % of the squared error at the
best point, each paired with the contact whose normal row of W is most nearly parallel (cosine
above 1 − `--cosine`). On RockPile_tob1 that search finds 7 pairs at Newton's 7.5e-8 point (128
choices, each a Newton run of up to minutes); the answer stored in the repository came from two
reductions named by hand (docs/problem-library.md). `rigidref solve-problems --solver
newton-twins` does this in Rust from λ = 0, with a first choice this script lacks (of each pair,
leave out the contact moving apart faster) and swaps in place of the search (docs/contact.md
§"Near-duplicate contacts left out"); this script is kept to reproduce the sixth session's route.

    target/venv/bin/python python/twin_reduction.py PROBLEM.dat [--start λ.npy] [--polish N]
        [--leave-out K,K,... ...] [--out answer.json]
"""

import argparse
import itertools
import json
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from cadoux_fixed_point import local_form  # noqa: E402


def per_contact_error(w, q, mu, lam):
    """Each contact's share of Siconos' error numerator, ‖λ − P_K(λ − ŵ)‖."""
    n = len(mu)
    u = (w @ lam.ravel() + q).reshape(n, 3)
    out = np.zeros(n)
    for k in range(n):
        wt = np.linalg.norm(u[k, 1:])
        x = lam[k] - np.r_[u[k, 0] + mu[k] * wt, u[k, 1:]]
        xn, xt = x[0], x[1:]
        nt = np.linalg.norm(xt)
        if nt <= mu[k] * xn:
            p = x
        elif mu[k] * nt <= -xn:
            p = np.zeros(3)
        else:
            a = (xn + mu[k] * nt) / (1 + mu[k] ** 2)
            p = np.r_[a, mu[k] * a * xt / nt]
        out[k] = np.linalg.norm(lam[k] - p)
    return out


def twins(w, e, cosine):
    """Pairs (k, twin) for the contacts carrying 99 % of Σ e²; twin's normal row of W is the
    most nearly parallel to k's, within 1 − cosine."""
    order = np.argsort(-e)
    total, acc, pairs = (e ** 2).sum(), 0.0, []
    rows = w[0::3] / np.linalg.norm(w[0::3], axis=1)[:, None]
    for k in order:
        if acc >= 0.99 * total:
            break
        acc += e[k] ** 2
        c = rows @ rows[k]
        c[k] = -2.0
        j = int(np.argmax(c))
        pair = tuple(sorted((int(k), j)))
        if c[j] > 1.0 - cosine and not any(set(pair) & set(p) for p in pairs):
            pairs.append(pair)
    return pairs


def main():
    import rigidref

    parser = argparse.ArgumentParser(
        description="Newton on a 3D cone problem, then the same problem with contacts left out "
                    "(one of each near-duplicate pair), each answer judged on the whole problem "
                    "by Siconos' error (docs/problem-library.md §\"RockPile_tob1\"). Exits 0 "
                    "where an answer is at or below the tolerance, 1 otherwise.")
    parser.add_argument("problem", help="a 3D local problem file (.dat, .json, .hdf5)")
    parser.add_argument("--start", help="λ to start from (.npy, contacts × 3)")
    parser.add_argument("--polish", type=int, default=1,
                        help="further Newton runs, each from the best answer so far (default 1)")
    parser.add_argument("--cosine", type=float, default=1e-8,
                        help="twins: normal rows of W with cosine above 1 − this (default 1e-8)")
    parser.add_argument("--tolerance", type=float, default=1e-8,
                        help="Siconos' error to accept (default 1e-8)")
    parser.add_argument("--leave-out", action="append", default=[], metavar="K,K,...",
                        help="contacts to leave out, in place of the search over twin pairs; "
                             "repeat for several reductions in turn")
    parser.add_argument("--out", help="write the answer as JSON")
    args = parser.parse_args()
    if args.polish < 0 or not 0 < args.cosine < 1 or not args.tolerance > 0:
        sys.exit("--polish must be ≥ 0, --cosine in (0, 1), --tolerance > 0")
    problem, w, q, mu = local_form(Path(args.problem))
    n = len(mu)
    if args.start:
        try:
            lam = np.load(args.start).reshape(n, 3)
        except (OSError, ValueError) as e:
            sys.exit(f"{args.start}: {e}")
    else:
        lam = np.zeros((n, 3))

    def error(x):
        return rigidref.siconos_error(problem, x.reshape(n, 3))

    def newton(p, start):
        a = rigidref.solve_newton(p, max_iterations=200, tolerance=1e-13,
                                  proximal_iterations=60, warm_start=start)
        return np.asarray(a.lam, dtype=float).reshape(-1, 3), a.iterations

    best, best_e = lam, error(lam)
    for k in range(1 + args.polish):
        t = time.perf_counter()
        cand, it = newton(problem, best)
        e = error(cand)
        print(f"Newton {k + 1}: {it} iterations, {time.perf_counter() - t:.1f} s, error {e:.3e}",
              flush=True)
        if e < best_e:
            best, best_e = cand, e
        if best_e <= args.tolerance:
            break
    try:
        given = [tuple(int(k) for k in item.split(",")) for item in args.leave_out]
    except ValueError:
        sys.exit(f"--leave-out takes contact numbers separated by commas: {args.leave_out}")
    if any(not 0 <= k < n for drop in given for k in drop):
        sys.exit(f"--leave-out: contacts are numbered 0 to {n - 1}")
    if best_e <= args.tolerance:
        choices = []
    elif given:
        choices = given
    else:
        pairs = twins(w, per_contact_error(w, q, mu, best), args.cosine)
        print(f"twin pairs carrying the error: {pairs}", flush=True)
        choices = itertools.product(*pairs) if pairs else []
    left_out = []
    for drop in choices:
        keep = [k for k in range(n) if k not in drop]
        idx = np.array([[3 * k, 3 * k + 1, 3 * k + 2] for k in keep]).ravel()
        sub = rigidref.ContactProblem.from_arrays(A=w[np.ix_(idx, idx)], b=q[idx], mu=mu[keep],
                                                  friction_model="cone")
        t = time.perf_counter()
        part, it = newton(sub, best[keep])
        cand = np.zeros((n, 3))
        cand[keep] = part
        e = error(cand)
        print(f"without {drop}: {it} iterations, {time.perf_counter() - t:.1f} s, "
              f"whole problem's error {e:.3e}", flush=True)
        if e < best_e:
            best, best_e, left_out = cand, e, list(drop)
        if best_e <= args.tolerance:
            break
    print(f"best: Siconos' error {best_e:.3e} ({'≤' if best_e <= args.tolerance else '>'} "
          f"{args.tolerance:g}), contacts left out {left_out}")
    if args.out:
        Path(args.out).write_text(json.dumps({"problem": str(args.problem), "error": best_e,
                                              "left_out": left_out, "lambda": best.tolist()}))
    sys.exit(0 if best_e <= args.tolerance else 1)


if __name__ == "__main__":
    main()
