"""The local (Delassus) form from Python: a problem from A, b, mu alone (docs/python.md
§"The local form"), read from Siconos' files, solved by every solver, and the same answers as
the body form it came from."""

import numpy as np
import pytest

import rigidref


@pytest.fixture(scope="module")
def stack(root):
    world = rigidref.World.load(root / "scenes" / "box_stack.json")
    world.step(60)
    return world.last_solves()[-1]


def test_from_arrays_with_a_alone_is_the_same_problem_as_the_body_form(stack):
    body = stack.problem
    W = body.W if isinstance(body.W, np.ndarray) else body.W.to_dense()
    local = rigidref.ContactProblem.from_arrays(W, body.b, body.mu, friction_model=body.friction_model,
                                                lambda0=body.lambda0)
    assert local.form == "local" and body.form == "body"
    assert local.num_contacts == body.num_contacts and local.num_bodies == 0
    np.testing.assert_array_equal(local.W, W)
    np.testing.assert_array_equal(local.b, body.b)
    # By keyword too; and to_local() gives the same operator.
    by_name = rigidref.ContactProblem.from_arrays(A=W, b=body.b, mu=body.mu, friction_model=body.friction_model)
    # The local form has no default friction law (FCLIB's is the cone, the assignment's the box).
    with pytest.raises(rigidref.ProblemError, match="give friction_model"):
        rigidref.ContactProblem.from_arrays(W, body.b, body.mu)
    np.testing.assert_array_equal(by_name.A, W)
    np.testing.assert_array_equal(body.to_local().W, W)
    # Every solver answers it, with the body form's answer: Newton to 1e-10 m/s (w to 1e-8),
    # PGS in order to round-off (its visits are the same, w read through W instead of the bodies).
    exact_body, exact_local = rigidref.solve_newton(body), rigidref.solve_newton(local)
    assert exact_local.converged and exact_local.residual <= 1e-10
    np.testing.assert_allclose(local.w(exact_local.lam), body.w(exact_body.lam), atol=1e-8)
    pgs_body = rigidref.solve_pgs(body, iterations=50)
    pgs_local = rigidref.solve_pgs(local, iterations=50, warm_start=body.lambda0)
    np.testing.assert_allclose(pgs_local.lam, pgs_body.lam, rtol=0, atol=1e-9 * np.abs(pgs_body.lam).max())
    qp = rigidref.solve_clarabel(local, formulation="cone_fixed", fixed_normal=exact_local.lam[:, 0])
    assert qp.converged
    assert rigidref.criteria(local, exact_local.lam)["max"]["signorini"] <= 1e-8


def test_the_local_form_says_what_it_does_not_have(stack):
    W = stack.problem.W
    local = rigidref.ContactProblem.from_arrays(A=W, b=stack.problem.b, mu=0.5, friction_model="cone")
    for name in ("J", "Minv", "velocity", "bodies", "compliance"):
        with pytest.raises(rigidref.ProblemError, match=f"{name}: a local-form problem"):
            getattr(local, name)
    with pytest.raises(rigidref.ProblemError, match="no compliance or velocity"):
        rigidref.ContactProblem.from_arrays(A=W, b=stack.problem.b, mu=0.5, compliance=0.1, friction_model="cone")
    with pytest.raises(rigidref.ProblemError, match="expected \\(3·contacts, 3·contacts\\)"):
        rigidref.ContactProblem.from_arrays(A=np.eye(4), b=np.zeros(4), mu=0.5, friction_model="cone")
    with pytest.raises(rigidref.ProblemError, match="mu must be ≥ 0"):
        rigidref.ContactProblem.from_arrays(np.eye(3), np.zeros(3), -1.0, friction_model="cone")
    with pytest.raises(rigidref.ProblemError, match="give J, Minv, b and mu"):
        rigidref.ContactProblem.from_arrays(np.eye(3), np.eye(3))
    # A NaN in A itself (not only through J or Minv) never reaches a solver.
    bad = np.eye(3)
    bad[1, 2] = np.nan
    with pytest.raises(rigidref.ProblemError, match="non-finite"):
        rigidref.ContactProblem.from_arrays(A=bad, b=np.zeros(3), mu=0.5, friction_model="cone")
    with pytest.raises(rigidref.ProblemError, match="non-finite"):
        rigidref.ContactProblem.from_arrays(A=np.eye(3), b=[0.0, np.nan, 0.0], mu=0.5, friction_model="cone")


def test_siconos_problems_read_and_solve_to_siconos_tolerance(root, tmp_path):
    # Rover11035: one sliding contact, W not symmetric; Siconos' Newton answer (tests/data/siconos).
    p = rigidref.ContactProblem.read(root / "tests" / "data" / "siconos" / "Rover11035.dat")
    assert p.form == "local" and p.friction_model == "cone" and p.num_contacts == 1
    assert p.W[0, 1] == -1.438285701497408206397943e-04 and p.W[1, 0] == -1.426574206813656375825161e-04
    s = rigidref.solve_newton(p, tolerance=1e-12)
    np.testing.assert_allclose(s.lam[0], [3.855527686824136, 1.0750356386021485, 2.4755189982088317], rtol=1e-7)
    assert rigidref.siconos_error(p, s.lam) <= 1e-8
    # A local problem writes and reads back as it was.
    p.write(tmp_path / "p.json")
    back = rigidref.ContactProblem.read(tmp_path / "p.json")
    assert back.form == "local"
    np.testing.assert_array_equal(back.W, p.W)
    np.testing.assert_array_equal(back.b, p.b)


def test_regularised_newton_solves_boxes_stack_by_plain_newton_in_fewer_iterations(root):
    # docs/contact.md §"Newton solver", **Regularisation following ‖F‖**: on BoxesStack1 (Siconos'
    # test data, redundant contacts) the unregularised solver needs its proximal loop; the
    # regularised one converges by plain Newton (the Rust test
    # regularised_newton_solves_boxes_stack_without_the_proximal_loop: 12 iterations to
    # Siconos' 1e-8). Both answers are exact to the default 1e-10 m/s.
    p = rigidref.ContactProblem.read(root / "tests" / "data" / "siconos_hard"
                                     / "BoxesStack1-i100000-32.hdf5.dat")
    plain = rigidref.solve_newton(p, max_iterations=200)
    regularised = rigidref.solve_newton(p, max_iterations=200, regularised=True)
    assert plain.converged and regularised.converged
    assert regularised.method == "newton" and plain.method != "newton"
    assert regularised.iterations < plain.iterations
    assert regularised.residual <= 1e-10 and rigidref.siconos_error(p, regularised.lam) <= 1e-8


def _twin_point(rows=3):
    # One point mass touched twice at the same point (docs/contact.md §"Near-duplicate contacts
    # left out"; the Rust tests' twin point): W = [[I, I], [I, I]], singular; contact 1
    # approaches δ = 1e-6 m/s slower than contact 0. The one exact answer loads contact 0
    # (λ = (1, −0.2[, 0]) N·s, sticking at μ = 1) and leaves contact 1 moving apart at δ.
    eye = np.eye(rows)
    W = np.block([[eye, eye], [eye, eye]])
    q = np.array(([-1.0, 0.2, 0.0] if rows == 3 else [-1.0, 0.2]) * 2)
    q[rows] += 1e-6
    return rigidref.ContactProblem.from_arrays(A=W, b=q, mu=[1.0, 1.0], friction_model="cone",
                                               dof_per_body=6 if rows == 3 else 3)


def test_newton_twins_leaves_out_the_twin_moving_apart_where_newton_stalls():
    # solve_newton_twins is `rigidref solve-problems --solver newton-twins` (src/solve/twins.rs).
    # Newton held to one iteration without its proximal fallback stalls on the twin point; the
    # reduction finds the pair, leaves out contact 1 (the one moving apart faster at the stalled
    # answer) and solves the rest: exact on the whole problem, contact 1 with λ = 0 exactly and
    # w_n = δ > 0. In 3D and 2D.
    for rows in (3, 2):
        p = _twin_point(rows)
        held = dict(max_iterations=1, proximal_iterations=0, restarts=0)
        alone = rigidref.solve_newton(p, max_iterations=1, proximal_iterations=0)
        assert rigidref.siconos_error(p, alone.lam) > 1e-8, "Newton alone stalls here"
        s = rigidref.solve_newton_twins(p, **held)
        assert (s.method, s.left_out, s.pairs) == ("twins", [1], [(0, 1)]), s
        assert s.converged and not alone.converged
        assert rigidref.siconos_error(p, s.lam) <= 1e-8
        np.testing.assert_array_equal(s.lam[1], np.zeros(rows))
        np.testing.assert_allclose(s.lam[0], [1.0, -0.2, 0.0][:rows], atol=1e-7)
        w = p.w(s.lam)
        assert 0.0 < w[1, 0] <= 2e-6 and abs(w[0, 0]) <= 1e-7
        # The same bits again.
        again = rigidref.solve_newton_twins(p, **held)
        np.testing.assert_array_equal(again.lam, s.lam)
        assert again.iterations == s.iterations
        # With its defaults Newton solves the point on the whole problem: nothing left out.
        whole = rigidref.solve_newton_twins(p)
        assert (whole.method, whole.left_out, whole.pairs) == ("newton", [], [])
        assert rigidref.siconos_error(p, whole.lam) <= 1e-8
        # .converged is the stop rule's, not Newton's own 1e-10 m/s: a tolerance that λ = 0
        # already meets (its error is 0.81) is met at once, with a residual of 1 m/s.
        loose = rigidref.solve_newton_twins(p, tolerance=0.9)
        assert loose.converged and loose.iterations == 0 and loose.residual == 1.0
        assert rigidref.siconos_error(p, loose.lam) <= 0.9
        # The other solvers leave the two fields empty.
        assert (alone.left_out, alone.pairs) == ([], [])


def test_newton_twins_on_a_body_problem_solves_its_local_form():
    # The twin point as a body: one 1 kg body with a unit inverse inertia, touched twice at its
    # centre (J = [I 0] per contact), so W = J M⁻¹ Jᵀ = [[I, I], [I, I]]: the same bits as on
    # its local form.
    J = np.zeros((6, 6))
    J[0:3, 0:3] = np.eye(3)
    J[3:6, 0:3] = np.eye(3)
    q = np.array([-1.0, 0.2, 0.0, -1.0 + 1e-6, 0.2, 0.0])
    body = rigidref.ContactProblem.from_arrays(J, np.eye(6), q, [1.0, 1.0], friction_model="cone")
    held = dict(max_iterations=1, proximal_iterations=0, restarts=0)
    s = rigidref.solve_newton_twins(body, **held)
    local = rigidref.solve_newton_twins(body.to_local(), **held)
    np.testing.assert_array_equal(s.lam, local.lam)
    assert s.left_out == local.left_out == [1]
    # A warm start replaces λ0, as for the other solvers; bad settings are refused.
    start = rigidref.solve_newton_twins(body, warm_start=s.lam)
    assert start.iterations <= 1 and rigidref.siconos_error(body.to_local(), start.lam) <= 1e-8
    for bad in (0.0, -1.0, float("nan")):
        with pytest.raises(rigidref.ProblemError, match="tolerance"):
            rigidref.solve_newton_twins(body, tolerance=bad)
    with pytest.raises(rigidref.ProblemError, match="warm_start"):
        rigidref.solve_newton_twins(body, warm_start=np.zeros((3, 3)))
