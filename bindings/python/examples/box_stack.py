"""A notebook-style walk through rigidref from Python (run it as a script, or cell by cell).

    python bindings/python/examples/box_stack.py [SCENE] [--plot energy.png]

Loads the box stack (or SCENE), steps it for two seconds, records the energy (and plots it when
matplotlib is installed and --plot is given), takes the last contact problem, solves it with
projected Gauss–Seidel, the exact Newton solver and clarabel, and compares the answers.
"""

import argparse
from pathlib import Path

import numpy as np

import rigidref

ROOT = Path(__file__).resolve().parents[3]

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("scene", nargs="?", default=str(ROOT / "scenes" / "box_stack.json"))
parser.add_argument("--plot", help="write the energy plot to this PNG (needs matplotlib)")
parser.add_argument("--time", type=float, default=2.0, help="simulated seconds (default 2)")
args = parser.parse_args()

# %% Load and step, recording the energy after every step.
world = rigidref.World.load(args.scene)
print(world)
steps = int(round(args.time / world.dt))
times, energy = [], []
for _ in range(steps):
    world.step()
    s = world.state()
    times.append(s["time"])
    energy.append(s["energy"]["total"])
print(f"energy: {energy[0]:.6g} J after the first step, {energy[-1]:.6g} J at t = {times[-1]:.3g} s")

if args.plot:
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(6, 3))
        ax.plot(times, energy)
        ax.set_xlabel("t (s)")
        ax.set_ylabel("total energy (J)")
        ax.set_title(Path(args.scene).stem)
        fig.tight_layout()
        fig.savefig(args.plot, dpi=100)
        print(f"plot: {args.plot}")
    except ImportError:
        print("plot: matplotlib is not installed; skipped")

# %% The last contact problem of the last step, as arrays.
solves = world.last_solves()
if not solves:
    raise SystemExit("the last step had no contact: nothing to solve")
solve = solves[-1]
p = solve.problem
print(p)
print(f"J {p.J.shape}, Minv {p.Minv.shape}, A {p.A.shape}, b {p.b.shape}, mu {p.mu[:3]}...")
print(f"A = J Minv J^T to {np.abs(p.A - p.J @ p.Minv @ p.J.T).max():.1e}")

# %% Solve it again: PGS with the step's own settings gives the step's impulses to the bit;
# the exact solver and clarabel answer the same problem.
pgs = rigidref.solve_pgs(p, **world.solver_settings()["pgs"])
newton = rigidref.solve_newton(p)
check = rigidref.solve_clarabel(p, formulation="box_fixed" if p.friction_model == "box" else "cone_fixed",
                                fixed_normal=newton.lam[:, 0])
print(f"PGS      {pgs.iterations:4d} sweeps      residual {pgs.residual:.2e} m/s"
      f"   same lambda as the step: {np.array_equal(pgs.lam, solve.lam)}")
print(f"Newton   {newton.iterations:4d} iterations  residual {newton.residual:.2e} m/s ({newton.method})")
print(f"clarabel {check.iterations:4d} iterations  residual {check.residual:.2e} m/s ({check.status})")
# A resting stack's impulses are not unique (four contacts carry each face: statically
# indeterminate), so compare what is: the contacts' velocities after the impulses, w = A lam + b.
print(f"|w_PGS - w_Newton|      = {np.abs(p.w(pgs.lam) - p.w(newton.lam)).max():.2e} m/s")
print(f"|w_clarabel - w_Newton| = {np.abs(p.w(check.lam) - p.w(newton.lam)).max():.2e} m/s")
c = rigidref.criteria(p, pgs.lam)["max"]
print("PGS's criteria: " + ", ".join(f"{k} {v:.1e}" for k, v in c.items()))
if p.friction_model == "box":
    print("(the criteria are against Coulomb's cone: box friction's corners lie outside it, so "
          "'primal' measures the box's excess over the disk, not an error of the solve)")
