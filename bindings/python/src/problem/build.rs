//! Problems from arrays: the body form from J, M⁻¹, b, μ and the local form from W, b, μ, each
//! checked as a problem file is; and the matrices of a problem as triplets.

use super::*;

/// λ (N·s) per contact from an array of shape (contacts, R).
pub(super) fn lambdas<const R: usize>(
    obj: &Bound<'_, PyAny>,
    contacts: usize,
    what: &str,
) -> PyResult<Vec<SVector<f64, R>>> {
    let (data, _) = arrays::shaped(obj, what, &[Some(contacts), Some(R)])?;
    if let Some(x) = data.iter().find(|x| !x.is_finite()) {
        return Err(errors::problem(format!("{what}: not finite ({x})")));
    }
    Ok(data
        .chunks(R)
        .map(SVector::<f64, R>::from_column_slice)
        .collect())
}

/// λ per contact as an array of shape (contacts, R).
pub fn lambda_array<'py, const R: usize>(
    py: Python<'py>,
    lambda: &[SVector<f64, R>],
) -> Bound<'py, PyArray2<f64>> {
    let data = lambda.iter().flat_map(|l| l.iter().copied()).collect();
    arrays::matrix(py, lambda.len(), R, data)
}

/// The Jacobian J (R·contacts × D·bodies) as triplets.
pub(super) fn jacobian_triplets<const D: usize, const R: usize>(
    p: &Problem<D, R>,
) -> Vec<(usize, usize, f64)> {
    let mut t = Vec::new();
    for (k, c) in p.contacts.iter().enumerate() {
        for side in 0..2 {
            if let Some(body) = c.bodies[side] {
                for r in 0..R {
                    for d in 0..D {
                        t.push((R * k + r, D * body + d, c.jacobian[side][(r, d)]));
                    }
                }
            }
        }
    }
    t
}

/// The Delassus operator A = J M⁻¹ Jᵀ (R·contacts square) as triplets: block (k, l) is the sum,
/// over the bodies contacts k and l share, of J_k,b M_b⁻¹ J_l,bᵀ.
pub(super) fn delassus_triplets<const D: usize, const R: usize>(
    p: &Problem<D, R>,
) -> Vec<(usize, usize, f64)> {
    let mut touching: Vec<Vec<(usize, usize)>> = vec![Vec::new(); p.bodies.len()];
    for (k, c) in p.contacts.iter().enumerate() {
        for side in 0..2 {
            if let Some(body) = c.bodies[side] {
                touching[body].push((k, side));
            }
        }
    }
    let mut blocks: BTreeMap<(usize, usize), SMatrix<f64, R, R>> = BTreeMap::new();
    for (body, list) in touching.iter().enumerate() {
        let m = &p.bodies[body].inverse_mass;
        for &(k, sk) in list {
            let left = p.contacts[k].jacobian[sk] * m;
            for &(l, sl) in list {
                *blocks.entry((k, l)).or_insert_with(SMatrix::zeros) +=
                    left * p.contacts[l].jacobian[sl].transpose();
            }
        }
    }
    let mut t = Vec::new();
    for ((k, l), block) in blocks {
        for i in 0..R {
            for j in 0..R {
                t.push((R * k + i, R * l + j, block[(i, j)]));
            }
        }
    }
    t
}

/// The inverse mass M⁻¹ (D·bodies square, block diagonal) as triplets.
pub(super) fn inverse_mass_triplets<const D: usize, const R: usize>(
    p: &Problem<D, R>,
) -> Vec<(usize, usize, f64)> {
    let mut t = Vec::new();
    for (b, body) in p.bodies.iter().enumerate() {
        for i in 0..D {
            for j in 0..D {
                t.push((D * b + i, D * b + j, body.inverse_mass[(i, j)]));
            }
        }
    }
    t
}

/// Builds a problem of D dof per body and R rows per contact from dense arrays.
#[allow(clippy::too_many_arguments)]
pub(super) fn build<const D: usize, const R: usize>(
    jacobian: &Bound<'_, PyAny>,
    inverse_mass: &Bound<'_, PyAny>,
    b: &Bound<'_, PyAny>,
    mu: &Bound<'_, PyAny>,
    friction: FrictionModel,
    compliance: Option<&Bound<'_, PyAny>>,
    lambda0: Option<&Bound<'_, PyAny>>,
    velocity: Option<&Bound<'_, PyAny>>,
    bounds: Option<Vec<RowBounds>>,
) -> PyResult<Problem<D, R>> {
    let (j, shape) = arrays::numbers(jacobian, "J")?;
    if shape.len() != 2 || shape[0] % R != 0 || shape[1] % D != 0 || shape[1] == 0 {
        return Err(errors::problem(format!(
            "J: shape {shape:?}, expected ({R}·contacts, {D}·bodies) with at least one body"
        )));
    }
    let (rows, cols) = (shape[0], shape[1]);
    let (m, n) = (rows / R, cols / D);
    let (minv, mshape) = arrays::numbers(inverse_mass, "Minv")?;
    // Minv: the block-diagonal matrix (D·bodies square) or its blocks (bodies, D, D).
    let block = |b: usize, i: usize, jj: usize| -> f64 {
        if mshape.len() == 3 {
            minv[(b * D + i) * D + jj]
        } else {
            minv[(D * b + i) * cols + D * b + jj]
        }
    };
    if mshape == [cols, cols] {
        for r in 0..cols {
            for c in 0..cols {
                if r / D != c / D && minv[r * cols + c] != 0.0 {
                    return Err(errors::problem(format!(
                        "Minv: entry ({r}, {c}) is {} outside the bodies' {D} × {D} diagonal blocks; a body's inverse mass couples only its own velocities",
                        minv[r * cols + c]
                    )));
                }
            }
        }
    } else if mshape != [n, D, D] {
        return Err(errors::problem(format!(
            "Minv: shape {mshape:?}, expected ({cols}, {cols}) or ({n}, {D}, {D}) for the {n} bodies of J"
        )));
    }
    let (b, _) = arrays::numbers(b, "b")?;
    if b.len() != rows {
        return Err(errors::problem(format!(
            "b: {} entries, expected {rows} (J's rows)",
            b.len()
        )));
    }
    let per_contact =
        |obj: Option<&Bound<'_, PyAny>>, what: &str, default: f64| -> PyResult<Vec<f64>> {
            let Some(obj) = obj else {
                return Ok(vec![default; m]);
            };
            let (v, s) = arrays::numbers(obj, what)?;
            match s.len() {
                0 => Ok(vec![v[0]; m]),
                1 if v.len() == m => Ok(v),
                _ => Err(errors::problem(format!(
                    "{what}: shape {s:?}, expected a number or ({m},), one per contact"
                ))),
            }
        };
    let mu = per_contact(Some(mu), "mu", 0.0)?;
    let compliance = per_contact(compliance, "compliance", 0.0)?;
    let lambda0 = match lambda0 {
        Some(l) => arrays::shaped(l, "lambda0", &[Some(m), Some(R)])?.0,
        None => vec![0.0; rows],
    };
    let velocity = match velocity {
        Some(u) => {
            let (u, _) = arrays::numbers(u, "velocity")?;
            if u.len() != cols {
                return Err(errors::problem(format!(
                    "velocity: {} entries, expected {cols} (J's columns)",
                    u.len()
                )));
            }
            u
        }
        None => vec![0.0; cols],
    };
    if let Some(b) = &bounds
        && b.len() != m
    {
        return Err(errors::problem(format!(
            "bounds: {} entries, expected {m}, one per contact",
            b.len()
        )));
    }
    let bodies = (0..n)
        .map(|i| ProblemBody {
            inverse_mass: SMatrix::<f64, D, D>::from_fn(|r, c| block(i, r, c)),
            velocity: SVector::<f64, D>::from_column_slice(&velocity[D * i..D * i + D]),
        })
        .collect();
    let mut contacts = Vec::with_capacity(m);
    for k in 0..m {
        let entry = |r: usize, c: usize| j[(R * k + r) * cols + c];
        let touched: Vec<usize> = (0..n)
            .filter(|&body| (0..R).any(|r| (0..D).any(|d| entry(r, D * body + d) != 0.0)))
            .collect();
        if touched.len() > 2 {
            return Err(errors::problem(format!(
                "J: contact {k}'s rows act on bodies {touched:?}; a contact acts on at most two bodies"
            )));
        }
        let side = |s: usize| -> (Option<usize>, SMatrix<f64, R, D>) {
            match touched.get(s) {
                Some(&body) => (Some(body), SMatrix::from_fn(|r, d| entry(r, D * body + d))),
                None => (None, SMatrix::zeros()),
            }
        };
        let ((b1, j1), (b2, j2)) = (side(0), side(1));
        contacts.push(ProblemContact {
            bodies: [b1, b2],
            jacobian: [j1, j2],
            b: SVector::from_column_slice(&b[R * k..R * k + R]),
            mu: mu[k],
            compliance: compliance[k],
            lambda0: SVector::from_column_slice(&lambda0[R * k..R * k + R]),
            bounds: bounds.as_ref().map_or(RowBounds::Contact, |b| b[k]),
        });
    }
    let problem = Problem {
        friction,
        bodies,
        contacts,
    };
    problem.validate().map_err(errors::problem)?;
    Ok(problem)
}

pub(super) fn row_bounds(name: &str) -> PyResult<RowBounds> {
    match name {
        "contact" => Ok(RowBounds::Contact),
        "free" => Ok(RowBounds::Free),
        other => Err(errors::problem(format!(
            "bounds {other:?}: expected \"contact\" or \"free\""
        ))),
    }
}

pub(super) fn friction_model(name: &str) -> PyResult<FrictionModel> {
    match name {
        "box" => Ok(FrictionModel::Box),
        "cone" => Ok(FrictionModel::Cone),
        other => Err(errors::problem(format!(
            "friction_model {other:?}: expected \"box\" or \"cone\""
        ))),
    }
}

/// W (R·contacts square) of a local problem as triplets, block by block.
pub(super) fn local_triplets<const R: usize>(p: &LocalProblem<R>) -> Vec<(usize, usize, f64)> {
    let mut t = Vec::new();
    for (k, c) in p.contacts.iter().enumerate() {
        for (j, block) in &c.row {
            for a in 0..R {
                for b in 0..R {
                    t.push((R * k + a, R * j + b, block[(a, b)]));
                }
            }
        }
    }
    t
}

/// A local problem of R rows per contact from a dense W (A), b and μ, with the optional warm
/// start and bounds.
pub(super) fn build_local<const R: usize>(
    a: &Bound<'_, PyAny>,
    b: &Bound<'_, PyAny>,
    mu: &Bound<'_, PyAny>,
    friction: FrictionModel,
    lambda0: Option<&Bound<'_, PyAny>>,
    bounds: Option<Vec<RowBounds>>,
) -> PyResult<LocalProblem<R>> {
    let (w, shape) = arrays::numbers(a, "A")?;
    if shape.len() != 2 || shape[0] != shape[1] || shape[0] % R != 0 {
        return Err(errors::problem(format!(
            "A: shape {shape:?}, expected ({R}·contacts, {R}·contacts)"
        )));
    }
    let n = shape[0];
    let m = n / R;
    let (q, _) = arrays::numbers(b, "b")?;
    if q.len() != n {
        return Err(errors::problem(format!(
            "b: {} entries, expected {n} (A's rows)",
            q.len()
        )));
    }
    let (mu_values, mu_shape) = arrays::numbers(mu, "mu")?;
    let mu = match mu_shape.len() {
        0 => vec![mu_values[0]; m],
        1 if mu_values.len() == m => mu_values,
        _ => {
            return Err(errors::problem(format!(
                "mu: shape {mu_shape:?}, expected a number or ({m},), one per contact"
            )));
        }
    };
    let entries = (0..n)
        .flat_map(|i| (0..n).map(move |j| (i, j)))
        .filter_map(|(i, j)| {
            let v = w[i * n + j];
            (v != 0.0 || i / R == j / R).then_some((i, j, v))
        });
    let mut problem =
        LocalProblem::<R>::from_entries(friction, entries, &q, &mu).map_err(errors::problem)?;
    if let Some(l) = lambda0 {
        for (c, l) in problem
            .contacts
            .iter_mut()
            .zip(lambdas::<R>(l, m, "lambda0")?)
        {
            c.lambda0 = l;
        }
    }
    if let Some(bounds) = bounds {
        if bounds.len() != m {
            return Err(errors::problem(format!(
                "bounds: {} entries, expected {m}, one per contact",
                bounds.len()
            )));
        }
        for (c, b) in problem.contacts.iter_mut().zip(bounds) {
            c.bounds = b;
        }
    }
    problem.validate().map_err(errors::problem)?;
    Ok(problem)
}
