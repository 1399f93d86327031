"""Type stubs of rigidref's native part (bindings/python/src). Arrays are float64 in C order
unless said; R is the rows per contact (3 in 3D, 2 in 2D), D the degrees of freedom per body (6
in 3D, 3 in 2D)."""

from os import PathLike
from typing import Any, Dict, List, Literal, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

_Path = Union[str, PathLike]
_F64 = npt.NDArray[np.float64]
_I64 = npt.NDArray[np.int64]
_Matrix = Union[_F64, "CooMatrix"]

DENSE_LIMIT: int
"""A matrix with more entries than this is returned as a CooMatrix instead of a dense array."""

class Error(Exception):
    """Any error rigidref reports, with the CLI's one-line message."""

class SceneError(Error):
    """A scene that cannot be loaded, or a world whose state became non-finite."""

class ProblemError(Error):
    """A malformed contact problem: shapes, non-finite numbers, negative mu, a bad file."""

class TraceError(Error):
    """A trace that cannot be read, or a comparison or grading that cannot be made."""

class CooMatrix:
    """A sparse matrix as coordinate triplets."""
    @property
    def data(self) -> _F64: ...
    @property
    def row(self) -> _I64: ...
    @property
    def col(self) -> _I64: ...
    @property
    def shape(self) -> Tuple[int, int]: ...
    @property
    def nnz(self) -> int: ...
    def to_scipy(self) -> Any:
        """scipy.sparse.coo_matrix (needs scipy)."""
    def to_dense(self) -> _F64: ...

class ContactProblem:
    """One contact problem: w = (A + C) lam + b, A = J Minv J^T, with each contact's
    complementarity and friction conditions (docs/contact.md)."""
    @staticmethod
    def read(path: _Path) -> "ContactProblem":
        """Reads a contact-problem file (3D or 2D, body or local form) or a Siconos .dat file."""
    def write(self, path: _Path) -> None:
        """Writes a contact-problem file (no provenance, no solution), in the problem's form."""
    @staticmethod
    def from_arrays(
        J: Optional[npt.ArrayLike] = None,
        Minv: Optional[npt.ArrayLike] = None,
        b: Optional[npt.ArrayLike] = None,
        mu: Optional[npt.ArrayLike] = None,
        *,
        A: Optional[npt.ArrayLike] = None,
        friction_model: Optional[Literal["box", "cone"]] = None,
        compliance: Optional[npt.ArrayLike] = None,
        lambda0: Optional[npt.ArrayLike] = None,
        velocity: Optional[npt.ArrayLike] = None,
        bounds: Optional[Sequence[Literal["contact", "free"]]] = None,
        dof_per_body: Literal[6, 3] = 6,
    ) -> "ContactProblem":
        """The body form from J (R*contacts x D*bodies), Minv (block diagonal, or (bodies, D, D)),
        b (R*contacts), mu (number or per contact); or the local form from A (the Delassus
        operator W, R*contacts square, compliance included), b and mu: from_arrays(A, b, mu,
        friction_model=...) or from_arrays(A=..., b=..., mu=..., friction_model=...). The body
        form's friction_model defaults to "box" (the assignment's); the local form has no
        default."""
    @property
    def form(self) -> Literal["body", "local"]:
        """"body" (bodies, J, Minv) or "local" (W, b, mu only)."""
    def to_local(self) -> "ContactProblem":
        """The local form: W = J Minv J^T + C, b unchanged."""
    @property
    def W(self) -> _Matrix:
        """W = A + C (R*contacts square), kg^-1, in either form."""
    @property
    def dof_per_body(self) -> int: ...
    @property
    def rows_per_contact(self) -> int: ...
    @property
    def num_contacts(self) -> int: ...
    @property
    def num_bodies(self) -> int: ...
    @property
    def friction_model(self) -> Literal["box", "cone"]: ...
    @property
    def J(self) -> _Matrix:
        """The Jacobian (R*contacts x D*bodies); ProblemError in the local form."""
    @property
    def Minv(self) -> _Matrix:
        """The inverse mass (D*bodies square, block diagonal)."""
    @property
    def A(self) -> _Matrix:
        """The Delassus operator J Minv J^T (R*contacts square), kg^-1; W in the local form."""
    @property
    def b(self) -> _F64:
        """b = J u - bias (R*contacts), m/s."""
    @property
    def mu(self) -> _F64: ...
    @property
    def compliance(self) -> _F64: ...
    @property
    def lambda0(self) -> _F64:
        """The warm start (contacts x R), N s."""
    @property
    def velocity(self) -> _F64:
        """The bodies' velocities u before contact (D*bodies)."""
    @property
    def bodies(self) -> _I64:
        """Each contact's two bodies (contacts x 2; -1 the static world)."""
    @property
    def bounds(self) -> List[Literal["contact", "free"]]:
        """Each constraint's row bounds."""
    def sparse(self, name: Literal["J", "Minv", "A", "W"]) -> CooMatrix:
        """The matrix as coordinate triplets, whatever its size."""
    def w(self, lam: npt.ArrayLike) -> _F64:
        """w = (A + C) lam + b (contacts x R), m/s."""

class Solution:
    """A solver's answer."""
    @property
    def lam(self) -> _F64:
        """lambda per contact (contacts x R), N s."""
    @property
    def iterations(self) -> int: ...
    @property
    def residual(self) -> float:
        """The natural-map residual, m/s."""
    @property
    def converged(self) -> bool: ...
    @property
    def coulomb_residual(self) -> Optional[float]: ...
    @property
    def method(self) -> str: ...
    @property
    def status(self) -> Optional[str]:
        """clarabel's status; None for the other solvers."""
    @property
    def left_out(self) -> List[int]:
        """solve_newton_twins: the contacts left out (lambda = 0 there); empty otherwise."""
    @property
    def pairs(self) -> List[Tuple[int, int]]:
        """solve_newton_twins: the near-duplicate pairs found; empty otherwise."""

class Solve:
    """One contact solve of a step."""
    @property
    def substep(self) -> int: ...
    @property
    def problem(self) -> ContactProblem: ...
    @property
    def lam(self) -> _F64:
        """The impulses the step applied (contacts x R), N s."""
    @property
    def iterations(self) -> int: ...
    @property
    def residual(self) -> float: ...
    @property
    def converged(self) -> bool: ...
    @property
    def coulomb_residual(self) -> Optional[float]: ...
    @property
    def method(self) -> str: ...
    @property
    def criteria(self) -> Dict[str, Any]:
        """Per-contact arrays of the physical criteria, and their "max"."""
    @property
    def solve_seconds(self) -> float: ...

class World:
    """A scene loaded as `rigidref run` loads it: a 3D scene file, a PNG image or a 2D scene file."""
    @staticmethod
    def load(path: _Path, overrides: Optional[Dict[str, Any]] = None) -> "World":
        """Loads a scene; overrides are the CLI's --set pairs."""
    def step(self, n: int = 1) -> None:
        """Steps n times, the interpreter's lock released."""
    @property
    def dimension(self) -> Literal[2, 3]: ...
    @property
    def time(self) -> float: ...
    @property
    def dt(self) -> float: ...
    @property
    def steps(self) -> int: ...
    @property
    def source(self) -> str: ...
    @property
    def warnings(self) -> List[str]: ...
    @property
    def body_names(self) -> List[str]: ...
    def state(self) -> Dict[str, Any]:
        """3D: x, R, v, omega; 2D: x, q, v, omega; time, step, energy, momentum."""
    def contacts(self) -> Dict[str, Any]:
        """bodies, point, normal, depth, lam of the last solve of the last step."""
    def last_solves(self) -> List[Solve]: ...
    def solver_settings(self) -> Dict[str, Any]:
        """{"solver", "pgs": solve_pgs keywords, "newton": solve_newton keywords}."""

def solve_pgs(
    problem: ContactProblem,
    iterations: int = 100,
    tolerance: Optional[float] = None,
    warm_start: Optional[npt.ArrayLike] = None,
    order: Literal["sequential", "random"] = "sequential",
    local: Literal["rows", "exact"] = "rows",
    seed: int = 0,
) -> Solution: ...
def solve_newton(
    problem: ContactProblem,
    max_iterations: int = 50,
    tolerance: float = 1e-10,
    proximal_iterations: int = 60,
    warm_start: Optional[npt.ArrayLike] = None,
    regularised: bool = False,
) -> Solution: ...
def solve_newton_twins(
    problem: ContactProblem,
    tolerance: float = 1e-8,
    max_iterations: int = 200,
    proximal_iterations: int = 60,
    restarts: int = 1,
    rounds: int = 8,
    warm_start: Optional[npt.ArrayLike] = None,
) -> Solution:
    """Newton with near-duplicate contacts left out (docs/contact.md), stopped on Siconos' error."""
def solve_clarabel(
    problem: ContactProblem,
    formulation: Literal["cone", "frictionless", "box_fixed", "cone_fixed"] = "cone",
    fixed_normal: Optional[npt.ArrayLike] = None,
    tolerance: float = 1e-10,
    max_iterations: int = 200,
) -> Solution: ...
def residual(problem: ContactProblem, lam: npt.ArrayLike) -> float: ...
def coulomb_residual(problem: ContactProblem, lam: npt.ArrayLike) -> float: ...
def criteria(problem: ContactProblem, lam: npt.ArrayLike) -> Dict[str, Any]: ...
def siconos_error(problem: ContactProblem, lam: npt.ArrayLike) -> float:
    """Siconos' error measure of lam (docs/problem-library.md), relative."""
def compare_traces(
    reference: _Path,
    candidate: _Path,
    mode: Literal["trajectory", "outcome"] = "trajectory",
    tolerance: float = 1e-3,
    scene: Optional[_Path] = None,
) -> Dict[str, Any]: ...
def grade(
    submissions_dir: _Path,
    scenes: Sequence[_Path],
    time: float = 5.0,
    mode: Literal["trajectory", "outcome"] = "trajectory",
    overrides: Optional[Dict[str, Any]] = None,
    max_file_mb: int = 512,
    jobs: Optional[int] = None,
) -> Dict[str, Any]: ...

def validate(
    out: _Path,
    engines: Optional[Sequence[str]] = None,
    scenes: Optional[Sequence[str]] = None,
    scene_dir: _Path = "scenes",
    python: Optional[_Path] = None,
) -> Dict[str, Any]: ...
