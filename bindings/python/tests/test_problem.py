"""ContactProblem and the solvers: the arrays are the problem's, the solvers the library's."""

import numpy as np
import pytest

import rigidref


@pytest.fixture(scope="module")
def stack(root):
    """The box stack after 60 steps (resting on the ground and on each other): its world and
    its last solve."""
    world = rigidref.World.load(root / "scenes" / "box_stack.json")
    world.step(60)
    return world, world.last_solves()[-1]


def test_the_delassus_operator_is_j_minv_jt(stack):
    _, solve = stack
    p = solve.problem
    J, Minv, A = p.J, p.Minv, p.A
    assert J.shape == (3 * p.num_contacts, 6 * p.num_bodies)
    # Round-off: A's entries are sums of a few products of J (≤ 1 m lever arms) and M⁻¹
    # (≤ 1/kg); 1e-12 of the largest entry is far above double round-off and far below any
    # mistake of a block or a sign.
    np.testing.assert_allclose(A, J @ Minv @ J.T, rtol=0, atol=1e-12 * np.abs(A).max())
    assert np.array_equal(A, A.T) or np.abs(A - A.T).max() <= 1e-15 * np.abs(A).max()


def test_the_velocities_after_the_impulses_are_a_lambda_plus_b(stack):
    _, solve = stack
    p = solve.problem
    w = p.w(solve.lam).ravel()
    np.testing.assert_allclose(w, p.A @ solve.lam.ravel() + p.b, rtol=0, atol=1e-12)


def test_solve_pgs_on_the_steps_problem_reproduces_the_steps_lambda(stack):
    world, solve = stack
    again = rigidref.solve_pgs(solve.problem, **world.solver_settings()["pgs"])
    assert again.lam.tolist() == solve.lam.tolist()  # to the bit
    assert again.iterations == solve.iterations and again.residual == solve.residual


def test_a_cold_start_changes_pgs_answer_but_not_its_problem(stack):
    world, solve = stack
    p = solve.problem
    before = p.lambda0.copy()
    cold = rigidref.solve_pgs(p, warm_start=np.zeros_like(solve.lam), **world.solver_settings()["pgs"])
    assert cold.lam.shape == solve.lam.shape
    assert cold.lam.tolist() != solve.lam.tolist()
    assert np.array_equal(p.lambda0, before)  # the warm start replaced a copy's, not the problem's
    assert rigidref.solve_pgs(p, **world.solver_settings()["pgs"]).lam.tolist() == solve.lam.tolist()


def test_newton_and_clarabel_answer_the_same_problem(stack):
    _, solve = stack
    p = solve.problem
    exact = rigidref.solve_newton(p)
    assert exact.converged and exact.residual <= 1e-10
    assert rigidref.residual(p, exact.lam) == pytest.approx(exact.residual, abs=1e-15)
    # clarabel with the friction bounds frozen at Newton's normal impulses must find a minimiser
    # of the same convex program. The stack's four contacts per face make λ non-unique
    # (statically indeterminate), but the velocities after the impulses, w = A λ + b, are the
    # same for every minimiser (w is the gradient of the convex quadratic ½λᵀAλ + bᵀλ, which is
    # the same at all its minimisers over a convex set; Newton's λ is one of them once the
    # bounds are frozen at its own λn). 1e-6 m/s is clarabel's accuracy at tolerance 1e-10 here.
    check = rigidref.solve_clarabel(p, formulation="box_fixed", fixed_normal=exact.lam[:, 0])
    assert check.converged and check.status in ("Solved", "AlmostSolved")
    np.testing.assert_allclose(p.w(check.lam), p.w(exact.lam), atol=1e-6)
    assert check.residual <= 1e-6
    c = rigidref.criteria(p, exact.lam)
    assert c["signorini"].shape == (p.num_contacts,)


@pytest.mark.parametrize("friction_model", ["box", "cone"])
def test_from_arrays_round_trips_through_a_file(tmp_path, stack, friction_model):
    _, solve = stack
    p = solve.problem
    compliance = np.linspace(0.0, 1e-6, p.num_contacts)
    q = rigidref.ContactProblem.from_arrays(p.J, p.Minv, p.b, p.mu, lambda0=p.lambda0,
                                            velocity=p.velocity, compliance=compliance,
                                            friction_model=friction_model)
    path = tmp_path / "p.json"
    q.write(path)
    r = rigidref.ContactProblem.read(path)
    for name in ("J", "Minv", "A", "b", "mu", "lambda0", "velocity"):
        assert np.array_equal(getattr(r, name), getattr(p, name)), name
    # from_arrays reads each contact's bodies off J's columns, in ascending order (the static
    # world last): the same pairs as the step's, and the same after the file.
    assert np.array_equal(r.bodies, q.bodies)
    assert [sorted(b) for b in q.bodies.tolist()] == [sorted(b) for b in p.bodies.tolist()]
    assert np.array_equal(r.compliance, compliance)
    assert r.friction_model == friction_model and r.bounds == ["contact"] * p.num_contacts
    assert rigidref.solve_pgs(r, iterations=50).lam.tolist() == rigidref.solve_pgs(q, iterations=50).lam.tolist()


def test_a_dumped_problem_file_reads_as_the_steps_problem(root, cli, tmp_path):
    from conftest import run_cli
    run_cli(cli, "run", root / "scenes" / "box_stack.json", "--steps", 3, "--quiet",
            "--out", tmp_path / "t.jsonl", "--dump-problems", tmp_path / "p")
    files = sorted((tmp_path / "p").glob("*.json"))
    assert files
    p = rigidref.ContactProblem.read(files[-1])
    world = rigidref.World.load(root / "scenes" / "box_stack.json")
    world.step(3)
    assert np.array_equal(p.A, world.last_solves()[-1].problem.A)


def test_a_two_dimensional_problem_has_three_dofs_and_two_rows(root):
    world = rigidref.World.load(root / "scenes" / "blocks" / "stack.png")
    world.step(60)
    p = world.last_solves()[-1].problem
    assert (p.dof_per_body, p.rows_per_contact) == (3, 2)
    np.testing.assert_allclose(p.A, p.J @ p.Minv @ p.J.T, atol=1e-12 * np.abs(p.A).max())


def test_sparse_matrices_are_coo_triplets_of_the_dense_ones(stack):
    _, solve = stack
    p = solve.problem
    coo = p.sparse("A")
    assert isinstance(coo, rigidref.CooMatrix)
    assert np.array_equal(coo.to_dense(), p.A)
    scipy = pytest.importorskip("scipy.sparse")
    assert np.array_equal(coo.to_scipy().toarray(), p.A)


def box_on_ground(**changes):
    """One contact of a body on the ground: the 3 × 6 Jacobian of a point 0.5 m below the centre."""
    J = np.zeros((3, 6))
    J[0, 1] = 1.0                     # normal: y
    J[1, 0], J[2, 2] = 1.0, 1.0       # tangents: x, z
    J[1, 5], J[2, 3] = 0.5, -0.5      # lever arm r = (0, -0.5, 0): ω × r
    Minv = np.diag([1.0, 1.0, 1.0, 6.0, 6.0, 6.0])
    args = dict(J=J, Minv=Minv, b=[-1.0, 0.2, 0.0], mu=0.5)
    args.update(changes)
    return args


def test_a_hand_made_problem_is_solved_by_every_solver():
    p = rigidref.ContactProblem.from_arrays(**box_on_ground())
    assert (p.num_contacts, p.num_bodies) == (1, 1)
    assert p.bodies.tolist() == [[0, -1]]
    for s in (rigidref.solve_pgs(p, iterations=200, tolerance=1e-12), rigidref.solve_newton(p)):
        assert s.residual <= 1e-10
        assert s.lam[0, 0] > 0 and abs(s.lam[0, 1]) <= 0.5 * s.lam[0, 0] + 1e-12


@pytest.mark.parametrize("changes,message", [
    (dict(J=np.zeros((4, 6))), "J: shape [4, 6], expected (3·contacts, 6·bodies)"),
    (dict(b=[1.0, 2.0]), "b: 2 entries, expected 3"),
    (dict(Minv=np.eye(5)), "Minv: shape [5, 5], expected (6, 6) or (1, 6, 6)"),
    (dict(mu=-0.5), "contact 0: mu must be ≥ 0, got -0.5"),
    (dict(J=np.full((3, 6), np.nan)), "contact 0: non-finite"),
    (dict(Minv=np.diag([np.nan, 1, 1, 6, 6, 6])), "body 0: non-finite inverse mass"),
    (dict(J="not numbers"), "J: not an array of numbers"),
])
def test_bad_arrays_are_a_problem_error_with_the_readers_message(changes, message):
    with pytest.raises(rigidref.ProblemError, match=None) as e:
        rigidref.ContactProblem.from_arrays(**box_on_ground(**changes))
    assert message in str(e.value)
    assert isinstance(e.value, rigidref.Error)


def test_a_negative_friction_coefficient_is_refused_as_a_problem_file_is(tmp_path):
    p = rigidref.ContactProblem.from_arrays(**box_on_ground())
    path = tmp_path / "p.json"
    p.write(path)
    text = path.read_text().replace('"mu":0.5', '"mu":-0.5')
    assert '"mu":-0.5' in text
    path.write_text(text)
    with pytest.raises(rigidref.ProblemError) as from_file:
        rigidref.ContactProblem.read(path)
    with pytest.raises(rigidref.ProblemError) as from_arrays:
        rigidref.ContactProblem.from_arrays(**box_on_ground(mu=-0.5))
    assert str(from_file.value) == f"{path}: {from_arrays.value}"


def test_a_nan_in_j_or_minv_and_so_in_a_cannot_reach_a_solver():
    # A is J M⁻¹ Jᵀ: a NaN in it comes from J or M⁻¹, and both are refused when the problem is
    # made (the J case is in the table above), so a solver never sees one.
    with pytest.raises(rigidref.ProblemError):
        rigidref.ContactProblem.from_arrays(**box_on_ground(Minv=np.diag([1, 1, 1, np.nan, 6, 6])))
    p = rigidref.ContactProblem.from_arrays(**box_on_ground())
    with pytest.raises(rigidref.ProblemError, match="lam: not finite"):
        rigidref.residual(p, [[np.nan, 0, 0]])
    with pytest.raises(rigidref.ProblemError, match="warm_start: shape"):
        rigidref.solve_pgs(p, warm_start=np.zeros((2, 3)))


def test_a_missing_or_malformed_problem_file_is_a_problem_error_with_the_clis_message(tmp_path, cli):
    from conftest import cli_error
    good = tmp_path / "good.json"
    rigidref.ContactProblem.from_arrays(**box_on_ground()).write(good)
    missing = tmp_path / "none.json"
    bad = tmp_path / "bad.json"
    bad.write_text('{"format": "rigidref-contact-problem", "version": 1,')
    for path in (missing, bad):
        with pytest.raises(rigidref.ProblemError) as e:
            rigidref.ContactProblem.read(path)
        assert str(e.value) == cli_error(cli, "compare-problem", path, good)
    odd = tmp_path / "odd.json"
    odd.write_text(good.read_text().replace('"dof_per_body":6', '"dof_per_body":4'))
    with pytest.raises(rigidref.ProblemError) as e:
        rigidref.ContactProblem.read(odd)
    assert "dof_per_body 4 with rows_per_contact 3 is not a problem rigidref knows" in str(e.value)
    assert str(e.value) == cli_error(cli, "crosscheck", odd)


def test_joint_rows_round_trip_and_are_not_bounded():
    J = np.zeros((2, 3)); J[0, 0] = 1.0; J[1, 1] = 1.0
    p = rigidref.ContactProblem.from_arrays(J, np.eye(3), [-1.0, 0.5], 0.0, bounds=["free"], dof_per_body=3)
    assert p.bounds == ["free"] and (p.dof_per_body, p.rows_per_contact) == (3, 2)
    s = rigidref.solve_pgs(p, iterations=50, tolerance=1e-14)
    assert s.lam.tolist() == [[1.0, -0.5]]  # w = λ + b = 0 on both rows, any sign
    with pytest.raises(rigidref.ProblemError, match="mu has no meaning on free rows"):
        rigidref.ContactProblem.from_arrays(J, np.eye(3), [-1.0, 0.5], 0.3, bounds=["free"], dof_per_body=3)
