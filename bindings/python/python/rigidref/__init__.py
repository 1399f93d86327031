"""rigidref from Python: load a scene, step it, look at its contact problems as numpy arrays,
solve them with the reference's solvers, and compare or grade traces (docs/python.md).

    import rigidref
    world = rigidref.World.load("scenes/box_stack.json")
    world.step(100)
    solve = world.last_solves()[-1]
    p = solve.problem                      # p.J, p.Minv, p.A, p.b, p.mu as float64 arrays
    again = rigidref.solve_pgs(p, **world.solver_settings()["pgs"])
    assert (again.lam == solve.lam).all()  # the step's λ, to the bit

Everything runs the library the `rigidref` command runs: the same scene reader, the same step,
the same solvers, the same comparison; errors are rigidref.Error (SceneError, ProblemError,
TraceError) with the command's one-line messages. TraceWriter and write_problem (pure Python)
write traces and problem files from another simulator, for `rigidref compare`.
"""

from ._rigidref import (
    DENSE_LIMIT,
    ContactProblem,
    CooMatrix,
    Error,
    ProblemError,
    SceneError,
    Solution,
    Solve,
    TraceError,
    World,
    compare_traces,
    coulomb_residual,
    criteria,
    grade,
    residual,
    siconos_error,
    solve_clarabel,
    solve_newton,
    solve_newton_twins,
    solve_pgs,
    validate,
)
from .trace import TraceWriter, write_problem

__all__ = [
    "DENSE_LIMIT",
    "ContactProblem",
    "CooMatrix",
    "Error",
    "ProblemError",
    "SceneError",
    "Solution",
    "Solve",
    "TraceError",
    "TraceWriter",
    "World",
    "compare_traces",
    "coulomb_residual",
    "criteria",
    "grade",
    "residual",
    "siconos_error",
    "solve_clarabel",
    "solve_newton",
    "solve_newton_twins",
    "solve_pgs",
    "validate",
    "write_problem",
]
