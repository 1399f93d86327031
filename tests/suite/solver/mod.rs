//! The shared core: the contact problem and PGS.

mod coulomb;
mod derivations;
mod local_solve;
mod pgs;
mod problem;

/// One contact whose Delassus block is `a` (kg⁻¹): one body with inverse mass `a` and J₁ = I.
fn local_solve_problem(
    a: nalgebra::SMatrix<f64, 3, 3>,
    b: nalgebra::SVector<f64, 3>,
    mu: f64,
    friction: rigidref::problem::FrictionModel,
) -> rigidref::problem::ContactProblem<3, 3> {
    use rigidref::problem::{ContactProblem, ProblemBody, ProblemContact};
    ContactProblem {
        friction,
        bodies: vec![ProblemBody {
            inverse_mass: a,
            velocity: nalgebra::SVector::zeros(),
        }],
        contacts: vec![ProblemContact {
            bodies: [Some(0), None],
            jacobian: [nalgebra::SMatrix::identity(), nalgebra::SMatrix::zeros()],
            b,
            mu,
            compliance: 0.0,
            lambda0: nalgebra::SVector::zeros(),
        }],
    }
}
