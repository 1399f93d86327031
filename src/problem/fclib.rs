//! FCLIB's HDF5 problem files (Acary, Brémond, Dubois, Huber; the format of the FCLIB
//! collection and of Siconos' `frictionContact_fclib_read`): docs/problem-library.md §"FCLIB".
//! Compiled with the feature `fclib` (the HDF5 C library, Debian's libhdf5-dev).
//!
//! A local problem is the group `/fclib_local`: `spacedim` (2 or 3), the matrix `W`, and
//! `vectors/q`, `vectors/mu`; optionally `info/{title, description, math_info}`,
//! `/solution/{r, u}` and `/guesses/{number_of_guesses, 1/{r, u}, …}`. A global problem is
//! `/fclib_global`: `M`, `H` (and `G`, equality constraints), `vectors/{f, w, mu}` (and `b`),
//! with M v = H r + f and u = Hᵀ v + w. A matrix group holds `m`, `n`, `nz`, `nzmax` (int) and
//! `p`, `i` (int), `x` (double): nz ≥ 0 triplets (i rows, p columns), nz = −1 compressed columns
//! (p column pointers, i rows), nz = −2 compressed rows (p row pointers, i columns); 0-based.

use super::siconos::AnyLocalProblem;
use super::{ContactProblem, FrictionModel, LocalProblem, ProblemBody, ProblemContact, RowBounds};
use nalgebra::{SMatrix, SVector};
use std::path::Path;

/// What an FCLIB file holds.
#[derive(Clone, Debug)]
pub enum FclibProblem {
    /// `/fclib_local`, with the solution's r when the file has one.
    Local {
        /// The problem (its warm start from the first guess, when the file has guesses).
        problem: AnyLocalProblem,
        /// `/solution/r`, stacked per contact (normal first).
        solution: Option<Vec<f64>>,
    },
    /// `/fclib_global` in 3D with M block-diagonal in 6 × 6 blocks: rigid bodies.
    Global(ContactProblem<6, 3>),
}

fn h5(path: &Path, what: &str) -> impl Fn(hdf5::Error) -> String {
    let name = path.display().to_string();
    let what = what.to_string();
    move |e| format!("{name}: {what}: {e}")
}

/// A dataset read whole, after its declared size is checked against `most` elements: a file's
/// declarations are untrusted (a chunked dataset with no stored chunks can declare 2⁴⁰
/// elements of a file of a few bytes), so nothing is allocated for more than the input limit.
fn dataset<T: hdf5::H5Type>(
    group: &hdf5::Group,
    name: &str,
    path: &Path,
    most: usize,
) -> Result<Vec<T>, String> {
    let err = h5(path, name);
    let d = group.dataset(name).map_err(&err)?;
    let declared = d.size();
    if declared > most {
        return Err(format!(
            "{}: {name} declares {declared} entries, more than the {most} that fit the input \
             limit (--max-input-mb)",
            path.display()
        ));
    }
    d.read_raw::<T>().map_err(&err)
}

/// Elements of 8 bytes that fit the input limit.
fn most_elements() -> usize {
    usize::try_from(crate::common::input::max_input_bytes() / 8).unwrap_or(usize::MAX)
}

/// The first value of a one-element integer dataset (FCLIB writes sizes and `spacedim` so).
fn scalar(group: &hdf5::Group, name: &str, path: &Path) -> Result<i64, String> {
    dataset::<i64>(group, name, path, 1)?
        .first()
        .copied()
        .ok_or_else(|| format!("{}: {name} is empty", path.display()))
}

/// A matrix's entries: (row, column, value).
type Entries = Vec<(usize, usize, f64)>;

/// A matrix group as (m, n, its entries).
fn read_matrix(
    group: &hdf5::Group,
    path: &Path,
    what: &str,
) -> Result<(usize, usize, Entries), String> {
    let int = |name: &str| scalar(group, name, path).map_err(|e| format!("{e} (in {what})"));
    let (m, n, nz) = (int("m")?, int("n")?, int("nz")?);
    if m < 0 || n < 0 {
        return Err(format!("{}: {what}: size {m}×{n}", path.display()));
    }
    let (m, n) = (m as usize, n as usize);
    let most = most_elements();
    let p = dataset::<i64>(group, "p", path, most)?;
    let i = dataset::<i64>(group, "i", path, most)?;
    let x = dataset::<f64>(group, "x", path, most)?;
    let bad = |msg: &str| format!("{}: {what}: {msg}", path.display());
    let index = |v: i64, bound: usize| -> Result<usize, String> {
        usize::try_from(v)
            .ok()
            .filter(|&v| v < bound)
            .ok_or_else(|| bad(&format!("index {v} outside 0..{bound}")))
    };
    let mut entries = Vec::new();
    match nz {
        nz if nz >= 0 => {
            let nz = nz as usize;
            if p.len() < nz || i.len() < nz || x.len() < nz {
                return Err(bad("fewer triplets stored than nz says"));
            }
            for k in 0..nz {
                entries.push((index(i[k], m)?, index(p[k], n)?, x[k]));
            }
        }
        -1 | -2 => {
            // Compressed columns (p over n columns, i rows) or rows (p over m rows, i columns).
            let (outer, inner) = if nz == -1 { (n, m) } else { (m, n) };
            if p.len() != outer + 1 {
                return Err(bad(&format!(
                    "p has {} entries, expected {}",
                    p.len(),
                    outer + 1
                )));
            }
            for o in 0..outer {
                let (start, end) = (p[o], p[o + 1]);
                if start < 0 || end < start || end as usize > i.len().min(x.len()) {
                    return Err(bad("p is not a valid pointer array"));
                }
                for k in start as usize..end as usize {
                    let other = index(i[k], inner)?;
                    entries.push(if nz == -1 {
                        (other, o, x[k])
                    } else {
                        (o, other, x[k])
                    });
                }
            }
        }
        nz => {
            return Err(bad(&format!(
                "nz {nz}: not a triplet (≥ 0), CSC (−1) or CSR (−2) matrix"
            )));
        }
    }
    Ok((m, n, entries))
}

fn read_vector(group: &hdf5::Group, name: &str, path: &Path) -> Result<Vec<f64>, String> {
    dataset::<f64>(group, name, path, most_elements())
}

/// Without HDF5's file locks: rigidref only reads a file or writes a new one, and a lock is
/// inherited by any process started while the file is open (HDF5 opens files without
/// close-on-exec), which would then keep another open of the file failing.
fn unlocked() -> hdf5::FileBuilder {
    let mut builder = hdf5::File::with_options();
    builder.with_fapl(|p| p.file_locking(false));
    builder
}

/// Reads an FCLIB file: its local problem, or its global one where M is rigid bodies' (6 × 6
/// blocks, 3D). Errors name the file and the group or dataset.
pub fn read_fclib(path: &Path) -> Result<FclibProblem, String> {
    let name = path.display().to_string();
    let file = unlocked()
        .open(path)
        .map_err(|e| format!("{name}: not an HDF5 file: {e}"))?;
    if file.link_exists("fclib_local") {
        read_local(&file, path)
    } else if file.link_exists("fclib_global") {
        read_global(&file, path).map(FclibProblem::Global)
    } else {
        Err(format!(
            "{name}: neither /fclib_local nor /fclib_global: not an FCLIB problem"
        ))
    }
}

fn read_local(file: &hdf5::File, path: &Path) -> Result<FclibProblem, String> {
    let name = path.display().to_string();
    let group = file.group("fclib_local").map_err(h5(path, "fclib_local"))?;
    let spacedim = scalar(&group, "spacedim", path)?;
    if group.link_exists("R") || group.link_exists("V") {
        return Err(format!(
            "{name}: a local problem with equality constraints (R, V) is not supported"
        ));
    }
    let w = group.group("W").map_err(h5(path, "fclib_local/W"))?;
    let (m, n, entries) = read_matrix(&w, path, "fclib_local/W")?;
    let vectors = group
        .group("vectors")
        .map_err(h5(path, "fclib_local/vectors"))?;
    let q = read_vector(&vectors, "q", path)?;
    let mu = read_vector(&vectors, "mu", path)?;
    let d = spacedim as usize;
    if !(spacedim == 2 || spacedim == 3) || m != n || m != d * mu.len() {
        return Err(format!(
            "{name}: W is {m}×{n} with spacedim {spacedim} and {} values of mu",
            mu.len()
        ));
    }
    // A vector of the wrong length is an error, not dropped: the file says something else than
    // its problem.
    let of_length = |v: Vec<f64>, what: &str| -> Result<Vec<f64>, String> {
        if v.len() == m {
            Ok(v)
        } else {
            Err(format!(
                "{name}: {what} has {} entries, W has {m} rows",
                v.len()
            ))
        }
    };
    let solution = if file.link_exists("solution") {
        let s = file.group("solution").map_err(h5(path, "solution"))?;
        Some(of_length(read_vector(&s, "r", path)?, "solution/r")?)
    } else {
        None
    };
    let guess = if file.link_exists("guesses/1") {
        let g = file.group("guesses/1").map_err(h5(path, "guesses/1"))?;
        Some(of_length(read_vector(&g, "r", path)?, "guesses/1/r")?)
    } else {
        None
    };
    // Triplets may repeat an entry; CSparse (FCLIB's library) sums them, and so does this.
    let mut summed: std::collections::BTreeMap<(usize, usize), f64> = Default::default();
    for (i, j, v) in entries {
        *summed.entry((i, j)).or_insert(0.0) += v;
    }
    let entries: Vec<(usize, usize, f64)> =
        summed.into_iter().map(|((i, j), v)| (i, j, v)).collect();
    let named = |e: String| format!("{name}: {e}");
    let problem = match d {
        3 => AnyLocalProblem::Three(
            with_guess(
                LocalProblem::from_entries(FrictionModel::Cone, entries, &q, &mu).map_err(named)?,
                guess.as_deref(),
            )
            .map_err(named)?,
        ),
        _ => AnyLocalProblem::Two(
            with_guess(
                LocalProblem::from_entries(FrictionModel::Cone, entries, &q, &mu).map_err(named)?,
                guess.as_deref(),
            )
            .map_err(named)?,
        ),
    };
    Ok(FclibProblem::Local { problem, solution })
}

/// The problem with the first guess as its warm start, checked again (a guess may hold a NaN).
fn with_guess<const R: usize>(
    mut problem: LocalProblem<R>,
    guess: Option<&[f64]>,
) -> Result<LocalProblem<R>, String> {
    if let Some(r) = guess {
        for (k, c) in problem.contacts.iter_mut().enumerate() {
            c.lambda0 = SVector::from_column_slice(&r[R * k..R * k + R]);
        }
    }
    problem.validate()?;
    Ok(problem)
}

/// `/fclib_global` as the body form: M v = H r + f, u = Hᵀ v + w, so J = Hᵀ, the free velocity
/// M⁻¹ f, and b = Hᵀ M⁻¹ f + w. Only rigid bodies: M block-diagonal in 6 × 6 blocks (3D).
fn read_global(file: &hdf5::File, path: &Path) -> Result<ContactProblem<6, 3>, String> {
    let name = path.display().to_string();
    let group = file
        .group("fclib_global")
        .map_err(h5(path, "fclib_global"))?;
    if group.link_exists("G") {
        return Err(format!(
            "{name}: a global problem with equality constraints (G) is not supported"
        ));
    }
    let spacedim = scalar(&group, "spacedim", path)?;
    if spacedim != 3 {
        return Err(format!(
            "{name}: a global problem of spacedim {spacedim}: rigidref reads 3D ones"
        ));
    }
    let (nm, nm2, m_entries) = read_matrix(
        &group.group("M").map_err(h5(path, "M"))?,
        path,
        "fclib_global/M",
    )?;
    let (hn, hm, h_entries) = read_matrix(
        &group.group("H").map_err(h5(path, "H"))?,
        path,
        "fclib_global/H",
    )?;
    let vectors = group
        .group("vectors")
        .map_err(h5(path, "fclib_global/vectors"))?;
    let f = read_vector(&vectors, "f", path)?;
    let w = read_vector(&vectors, "w", path)?;
    let mu = read_vector(&vectors, "mu", path)?;
    const D: usize = 6;
    if nm != nm2 || nm % D != 0 || hn != nm || hm != 3 * mu.len() || f.len() != nm || w.len() != hm
    {
        return Err(format!(
            "{name}: sizes do not fit: M {nm}×{nm2}, H {hn}×{hm}, f {}, w {}, mu {} (M must be \
             rigid bodies' 6 × 6 blocks)",
            f.len(),
            w.len(),
            mu.len()
        ));
    }
    let bodies_count = nm / D;
    let mut blocks = vec![SMatrix::<f64, D, D>::zeros(); bodies_count];
    for (i, j, v) in m_entries {
        if i / D != j / D {
            if v != 0.0 {
                return Err(format!(
                    "{name}: M has entry ({i}, {j}) outside the 6 × 6 diagonal blocks: not rigid \
                     bodies (rigidref's body form); its local form is not read from a global file"
                ));
            }
            continue;
        }
        blocks[i / D][(i % D, j % D)] += v;
    }
    let mut bodies = Vec::with_capacity(bodies_count);
    for (b, block) in blocks.iter().enumerate() {
        // A mass matrix is symmetric; one that is not (beyond its printed digits) is refused
        // rather than symmetrised, which would change the problem.
        if (block - block.transpose()).amax() > 1e-9 * block.amax() {
            return Err(format!("{name}: body {b}'s mass block is not symmetric"));
        }
        let inverse = block
            .try_inverse()
            .ok_or_else(|| format!("{name}: body {b}'s mass block is singular"))?;
        let inverse = (inverse + inverse.transpose()) * 0.5;
        let velocity = inverse * SVector::<f64, D>::from_column_slice(&f[D * b..D * b + D]);
        bodies.push(ProblemBody {
            inverse_mass: inverse,
            velocity,
        });
    }
    // J = Hᵀ, contact by contact (3 rows), each acting on at most two bodies: H's entries
    // sorted by contact, each contact's row blocks built for the bodies it touches (sparse: a
    // dense 3 × nm row block per contact would be nm · contacts numbers).
    let contacts_count = mu.len();
    let mut per_contact: Vec<Vec<(usize, usize, f64)>> = vec![Vec::new(); contacts_count];
    for (i, j, v) in h_entries {
        per_contact[j / 3].push((j % 3, i, v));
    }
    let mut contacts = Vec::with_capacity(contacts_count);
    for (k, entries) in per_contact.iter().enumerate() {
        let mut touched: Vec<usize> = entries
            .iter()
            .filter(|(_, _, v)| *v != 0.0)
            .map(|(_, col, _)| col / D)
            .collect();
        touched.sort_unstable();
        touched.dedup();
        if touched.is_empty() || touched.len() > 2 {
            return Err(format!(
                "{name}: contact {k} acts on {} bodies; a contact acts on one or two",
                touched.len()
            ));
        }
        let side = |s: usize| -> (Option<usize>, SMatrix<f64, 3, D>) {
            match touched.get(s) {
                Some(&b) => {
                    let mut block = SMatrix::<f64, 3, D>::zeros();
                    for &(r, col, v) in entries {
                        if col / D == b {
                            block[(r, col % D)] += v;
                        }
                    }
                    (Some(b), block)
                }
                None => (None, SMatrix::zeros()),
            }
        };
        let ((b1, j1), (b2, j2)) = (side(0), side(1));
        let mut b = SVector::<f64, 3>::from_column_slice(&w[3 * k..3 * k + 3]);
        b += j1 * bodies[b1.unwrap_or(0)].velocity;
        if let Some(b2) = b2 {
            b += j2 * bodies[b2].velocity;
        }
        contacts.push(ProblemContact {
            bodies: [b1, b2],
            jacobian: [j1, j2],
            b,
            mu: mu[k],
            compliance: 0.0,
            lambda0: SVector::zeros(),
            bounds: RowBounds::Contact,
        });
    }
    let problem = ContactProblem {
        friction: FrictionModel::Cone,
        bodies,
        contacts,
    };
    problem.validate().map_err(|e| format!("{name}: {e}"))?;
    Ok(problem)
}

/// Writes `problem` as an FCLIB local problem: W in triplets (every entry of every stored block,
/// zeros included, so that the block structure reads back), q, μ, `info/title`, the warm start
/// as the first guess when it is not zero, and `solution` (r = λ, u = W λ + q) when given.
/// FCLIB's law is the Coulomb cone: a box-friction problem is written as it is and would be
/// solved as a cone problem there.
pub fn write_fclib<const R: usize>(
    problem: &LocalProblem<R>,
    title: &str,
    solution: Option<&[SVector<f64, R>]>,
    path: &Path,
) -> Result<(), String> {
    let err = h5(path, "writing");
    let file = unlocked().create(path).map_err(&err)?;
    let local = file.create_group("fclib_local").map_err(&err)?;
    let int = |g: &hdf5::Group, name: &str, v: i32| -> Result<(), String> {
        g.new_dataset_builder()
            .with_data(&[v][..])
            .create(name)
            .map(|_| ())
            .map_err(h5(path, name))
    };
    let doubles = |g: &hdf5::Group, name: &str, v: &[f64]| -> Result<(), String> {
        g.new_dataset_builder()
            .with_data(v)
            .create(name)
            .map(|_| ())
            .map_err(h5(path, name))
    };
    let ints = |g: &hdf5::Group, name: &str, v: &[i32]| -> Result<(), String> {
        g.new_dataset_builder()
            .with_data(v)
            .create(name)
            .map(|_| ())
            .map_err(h5(path, name))
    };
    int(&local, "spacedim", R as i32)?;
    let n = R * problem.contacts.len();
    let (mut rows, mut cols, mut values) = (Vec::new(), Vec::new(), Vec::new());
    for (k, c) in problem.contacts.iter().enumerate() {
        for (j, block) in &c.row {
            for b in 0..R {
                for a in 0..R {
                    rows.push((R * k + a) as i32);
                    cols.push((R * j + b) as i32);
                    values.push(block[(a, b)]);
                }
            }
        }
    }
    let w = local.create_group("W").map_err(&err)?;
    int(&w, "m", n as i32)?;
    int(&w, "n", n as i32)?;
    int(&w, "nz", values.len() as i32)?;
    int(&w, "nzmax", values.len() as i32)?;
    ints(&w, "i", &rows)?;
    ints(&w, "p", &cols)?;
    doubles(&w, "x", &values)?;
    let vectors = local.create_group("vectors").map_err(&err)?;
    doubles(&vectors, "q", problem.dense_q().as_slice())?;
    let mu: Vec<f64> = problem.contacts.iter().map(|c| c.mu).collect();
    doubles(&vectors, "mu", &mu)?;
    let info = local.create_group("info").map_err(&err)?;
    // A fixed-length ASCII string, as FCLIB's H5LTmake_dataset_string writes (its reader reads
    // no variable-length strings); other characters become '?', and it is cut at 255.
    let ascii: String = title
        .chars()
        .map(|c| {
            if c.is_ascii() && !c.is_ascii_control() {
                c
            } else {
                '?'
            }
        })
        .take(255)
        .collect();
    let title = hdf5::types::FixedAscii::<256>::from_ascii(ascii.as_bytes())
        .map_err(|e| format!("{}: title: {e:?}", path.display()))?;
    info.new_dataset_builder()
        .with_data(&[title][..])
        .create("title")
        .map_err(h5(path, "info/title"))?;
    let write_solution = |g: &hdf5::Group, lambda: &[SVector<f64, R>]| -> Result<(), String> {
        let r: Vec<f64> = lambda.iter().flat_map(|l| l.iter().copied()).collect();
        let u: Vec<f64> = problem
            .velocity(lambda)
            .iter()
            .flat_map(|w| w.iter().copied())
            .collect();
        doubles(g, "r", &r)?;
        doubles(g, "u", &u)
    };
    if problem
        .contacts
        .iter()
        .any(|c| c.lambda0.iter().any(|x| *x != 0.0))
    {
        let guesses = file.create_group("guesses").map_err(&err)?;
        int(&guesses, "number_of_guesses", 1)?;
        let first = guesses.create_group("1").map_err(&err)?;
        let lambda0: Vec<SVector<f64, R>> = problem.contacts.iter().map(|c| c.lambda0).collect();
        write_solution(&first, &lambda0)?;
    }
    if let Some(lambda) = solution {
        let g = file.create_group("solution").map_err(&err)?;
        write_solution(&g, lambda)?;
    }
    // Closed here, every handle with it, so that the file is complete and unlocked on return.
    drop((local, w, vectors, info));
    file.close().map_err(&err)
}
