#!/usr/bin/env python3
"""What makes a contact problem hard: its strict feasibility, and variants to solve beside it
(issue 48 item 2, RockPile_tob1; docs/problem-library.md §"RockPile_tob1").

    rigidref convert-problem PROBLEM x.json
    python3 python/problem_structure.py x.json [--variants DIR] [--mu 0.3,0.5,0.7,0.9]

Reads a 3D problem in rigidref's local JSON form (W, q, μ per contact; `rigidref
convert-problem` writes it from a Siconos `.dat` or FCLIB `.hdf5` file) and prints:

- its size, the asymmetry max |W − Wᵀ| and the extreme eigenvalues of W's symmetric part;
- **Cadoux's strict-feasibility margin** t* = max over y of min over contacts k of
  (w_n,k − μ_k ‖w_T,k‖), w = W y + q, capped at 1 m/s: whether some impulse makes every contact
  velocity lie strictly inside the dual cone K* = {w_n ≥ μ‖w_T‖}. Cadoux (2009) proves that
  where W = H M⁻¹ Hᵀ (symmetric) and t* > 0, the problem has a solution; t* ≤ 0 means no impulse
  separates every contact strictly. It is a second-order-cone program solved by Clarabel
  (`pip install clarabel`); without Clarabel this part is skipped with a note.

With --variants DIR it writes the same problem with W replaced by its symmetric part
(`sym.json`) and with every μ replaced by each value of --mu (`mu0.3.json`, ...), to be solved
beside the original (`rigidref solve-problems DIR --solver newton`, or converted to `.dat` for
python/siconos_side_by_side.py): which change makes the problem solvable says what makes it hard.
"""
import argparse
import copy
import json
import sys
from pathlib import Path

import numpy as np


def read_local(path):
    """W (dense), q, μ and the JSON document of a rigidref local problem file."""
    try:
        doc = json.loads(Path(path).read_text())
    except (OSError, ValueError) as e:
        sys.exit(f"{path}: cannot read a problem: {getattr(e, 'strerror', None) or e}")
    if not isinstance(doc, dict) or doc.get("form") != "local":
        form = doc.get("form") if isinstance(doc, dict) else None
        sys.exit(f"{path}: not a local-form problem (form = {form!r}); `rigidref convert-problem`"
                 " writes one")
    r = doc["rows_per_contact"]
    if r != 3:
        sys.exit(f"{path}: {r} rows per contact; this study is written for 3D problems (3)")
    try:
        n = len(doc["contacts"])
        w = np.zeros((n * r, n * r))
        for b in doc["W"]:
            i, j = b["row"], b["col"]
            w[i * r:(i + 1) * r, j * r:(j + 1) * r] = np.array(b["block"], dtype=float)
        q = np.concatenate([np.array(c["q"], dtype=float) for c in doc["contacts"]])
        mu = np.array([c["mu"] for c in doc["contacts"]], dtype=float)
    except (KeyError, TypeError, ValueError, IndexError) as e:
        sys.exit(f"{path}: not a well-formed local problem ({type(e).__name__}: {e})")
    return w, q, mu, doc


def strict_feasibility_margin(w, q, mu, cap=1.0):
    """Cadoux's margin t* = max_y min_k (w_n,k − μ_k‖w_T,k‖), w = W y + q, capped at `cap` (m/s),
    by Clarabel; None (with a note) where Clarabel is not installed."""
    try:
        import clarabel
        from scipy import sparse
    except ImportError as e:
        print(f"strict feasibility: skipped ({e}; pip install clarabel scipy)")
        return None
    n = len(mu)
    big_n = 3 * n
    # Variables x = (y, t); minimise −t. Cones: 1 − t ≥ 0, and per contact
    # s_k = (w_n − t, μ w_1, μ w_2) ∈ SOC with w = W y + q, written as s = b − A x.
    scale = np.repeat(mu, 3)
    scale[0::3] = 1.0
    a = np.zeros((big_n + 1, big_n + 1))
    b = np.zeros(big_n + 1)
    a[0, big_n], b[0] = 1.0, cap
    a[1:, :big_n] = -(scale[:, None] * w)
    b[1:] = scale * q
    a[1 + 3 * np.arange(n), big_n] = 1.0
    c = np.zeros(big_n + 1)
    c[big_n] = -1.0
    cones = [clarabel.NonnegativeConeT(1)] + [clarabel.SecondOrderConeT(3)] * n
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    solution = clarabel.DefaultSolver(
        sparse.csc_matrix((big_n + 1, big_n + 1)), c, sparse.csc_matrix(a), b, cones, settings
    ).solve()
    if str(solution.status) != "Solved":
        print(f"strict feasibility: Clarabel ended with {solution.status}")
        return None
    y = np.array(solution.x[:big_n])
    v = w @ y + q
    margin = v[0::3] - mu * np.hypot(v[1::3], v[2::3])
    return min(float(margin.min()), cap)


def write_variants(doc, out, mus):
    out.mkdir(parents=True, exist_ok=True)
    r = doc["rows_per_contact"]
    blocks = {(b["row"], b["col"]): np.array(b["block"]) for b in doc["W"]}
    sym = copy.deepcopy(doc)
    sym["W"] = []
    for (i, j) in sorted(set(blocks) | {(j, i) for (i, j) in blocks}):
        here = blocks.get((i, j), np.zeros((r, r)))
        there = blocks.get((j, i), np.zeros((r, r)))
        sym["W"].append({"row": i, "col": j, "block": (0.5 * (here + there.T)).tolist()})
    sym["source"] = f"{doc.get('source', '')}; W replaced by its symmetric part"
    (out / "sym.json").write_text(json.dumps(sym))
    for m in mus:
        v = copy.deepcopy(doc)
        for c in v["contacts"]:
            c["mu"] = m
        v["source"] = f"{doc.get('source', '')}; every μ set to {m}"
        (out / f"mu{m:g}.json").write_text(json.dumps(v))
    print(f"wrote {out}/sym.json and {len(mus)} μ variants")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("problem", help="a 3D problem in rigidref's local JSON form")
    p.add_argument("--variants", type=Path, help="write the symmetrised and μ variants here")
    p.add_argument("--mu", default="0.3,0.5,0.7,0.9", help="μ values of the variants")
    a = p.parse_args()
    w, q, mu, doc = read_local(a.problem)
    eig = np.linalg.eigvalsh(0.5 * (w + w.T))
    print(f"{a.problem}: {len(mu)} contacts, ‖q‖ = {np.linalg.norm(q):.4g}, "
          f"μ in [{mu.min():g}, {mu.max():g}], max |W − Wᵀ| = {np.abs(w - w.T).max():.3g}, "
          f"eigenvalues of (W + Wᵀ)/2 in [{eig.min():.3g}, {eig.max():.4g}]")
    t = strict_feasibility_margin(w, q, mu)
    if t is not None:
        print(f"strict feasibility margin t* = {t:.6g} m/s (capped at 1): "
              + ("strictly feasible" if t > 0 else "not strictly feasible"))
    if a.variants:
        write_variants(doc, a.variants, [float(x) for x in a.mu.split(",")])


if __name__ == "__main__":
    main()
