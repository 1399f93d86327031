//! The quantities of a run over time, grouped into plots: what the viewer draws beside the
//! bodies and what `rigidref plot` writes to a file, from the same code so the two always agree.
//! docs/viewing.md §"Plots".

use crate::blocks2d::trace::Record2;
use crate::rigid3d::trace::{TraceHeader, TraceRecord};
use crate::sim::SolverRecord;

/// One plotted series: a name (unique within its plot) and one value per record (`None` where
/// the record has none, drawn as a gap).
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// Legend name, e.g. "kinetic (linear)" or "ω_x brick".
    pub name: String,
    /// One value per record, in record order.
    pub values: Vec<Option<f64>>,
}

/// A plot: a title, the unit of its y axis, whether the axis is logarithmic, its series.
#[derive(Clone, Debug, PartialEq)]
pub struct Plot {
    /// Which quantity this is (the `--quantities` name, e.g. "energy").
    pub key: &'static str,
    /// Title, e.g. "Energy".
    pub title: String,
    /// Unit of the y axis, e.g. "J" (empty for counts).
    pub unit: String,
    /// A logarithmic y axis (for residuals, which span many decades).
    pub log: bool,
    /// The series, drawn in order.
    pub series: Vec<Series>,
}

/// The quantity names `rigidref plot --quantities` accepts, in the order plots are drawn.
pub const QUANTITIES: [&str; 9] = [
    "energy",
    "momentum",
    "angular_momentum",
    "omega",
    "contacts",
    "sweeps",
    "residual",
    "criteria",
    "penetration",
];

/// At most this many bodies get their angular velocity plotted (three series each); the rest
/// are named in a note (`rigidref plot --bodies` chooses which).
pub const MAX_OMEGA_BODIES: usize = 4;

fn series(name: impl Into<String>, values: Vec<Option<f64>>) -> Series {
    Series {
        name: name.into(),
        values,
    }
}

fn plot(key: &'static str, title: &str, unit: &str, log: bool, series: Vec<Series>) -> Plot {
    Plot {
        key,
        title: title.into(),
        unit: unit.into(),
        log,
        series,
    }
}

/// The solver's plots (sweeps; residual and exact Coulomb residual; the physical criteria) from
/// each record's `solver` key, `velocity` naming the residual's unit and `criteria` the
/// criteria's (impulse, velocity, energy).
fn solver_plots(solver: &[Option<SolverRecord>], velocity: &str, criteria: &str) -> Vec<Plot> {
    let sweeps = solver.iter().map(|s| s.map(|s| s.sweeps as f64)).collect();
    let residual = solver.iter().map(|s| s.map(|s| s.residual)).collect();
    let mut residuals = vec![series("worst residual", residual)];
    if solver
        .iter()
        .any(|s| s.is_some_and(|s| s.coulomb_residual.is_some()))
    {
        let coulomb = solver
            .iter()
            .map(|s| s.and_then(|s| s.coulomb_residual))
            .collect();
        residuals.push(series("exact Coulomb residual", coulomb));
    }
    let mut plots = vec![
        plot(
            "sweeps",
            "solver iterations (PGS sweeps, Newton iterations)",
            "",
            false,
            vec![series("iterations per frame", sweeps)],
        ),
        plot("residual", "solver residual", velocity, true, residuals),
    ];
    if solver
        .iter()
        .any(|s| s.is_some_and(|s| s.criteria.is_some()))
    {
        let criterion = |name: &str, pick: fn(&crate::problem::ContactCriteria) -> f64| {
            let values = solver
                .iter()
                .map(|s| s.and_then(|s| s.criteria.as_ref().map(pick)))
                .collect();
            series(name, values)
        };
        plots.push(plot(
            "criteria",
            "physical criteria (largest over the contacts)",
            criteria,
            true,
            vec![
                criterion("primal", |c| c.primal),
                criterion("dual", |c| c.dual),
                criterion("complementarity", |c| c.complementarity),
                criterion("signorini", |c| c.signorini),
                criterion("cone boundary", |c| c.cone_boundary),
                criterion("max dissipation", |c| c.max_dissipation),
            ],
        ));
    }
    plots
}

/// The plots of a 3D trace: energy, linear and angular momentum, the angular velocity of the
/// bodies `omega_bodies` (indices), contacts, PGS sweeps and residuals, penetration.
pub fn plots_3d(
    header: &TraceHeader,
    records: &[TraceRecord],
    omega_bodies: &[usize],
) -> Vec<Plot> {
    let each = |f: &dyn Fn(&TraceRecord) -> Option<f64>| records.iter().map(f).collect::<Vec<_>>();
    let axes = ["x", "y", "z"];
    let mut plots = vec![plot(
        "energy",
        "Energy",
        "J",
        false,
        vec![
            series("kinetic (linear)", each(&|r| Some(r.energy.kinetic_linear))),
            series(
                "kinetic (angular)",
                each(&|r| Some(r.energy.kinetic_angular)),
            ),
            series("potential", each(&|r| Some(r.energy.potential))),
            series("total", each(&|r| Some(r.energy.total))),
        ],
    )];
    plots.push(plot(
        "momentum",
        "Linear momentum",
        "kg·m/s",
        false,
        (0..3)
            .map(|k| {
                series(
                    format!("p_{}", axes[k]),
                    each(&|r| Some(r.momentum.linear[k])),
                )
            })
            .collect(),
    ));
    plots.push(plot(
        "angular_momentum",
        "Angular momentum about the centre of mass",
        "kg·m²/s",
        false,
        (0..3)
            .map(|k| {
                series(
                    format!("L_{}", axes[k]),
                    each(&|r| Some(r.momentum.angular_com[k])),
                )
            })
            .collect(),
    ));
    let mut omega = Vec::new();
    for &b in omega_bodies {
        let name = header
            .bodies
            .get(b)
            .map_or(String::new(), |i| i.name.clone());
        for (k, axis) in axes.iter().enumerate() {
            omega.push(series(
                format!("ω_{axis} {name}"),
                each(&|r| r.bodies.get(b).map(|s| s.omega[k])),
            ));
        }
    }
    if !omega.is_empty() {
        plots.push(plot(
            "omega",
            "Angular velocity (world frame)",
            "rad/s",
            false,
            omega,
        ));
    }
    plots.push(plot(
        "contacts",
        "Contacts",
        "",
        false,
        vec![series("contacts", each(&|r| Some(r.contacts.len() as f64)))],
    ));
    let solver: Vec<_> = records.iter().map(|r| r.solver).collect();
    plots.extend(solver_plots(&solver, "m/s", "N·s, m/s, J"));
    plots.push(plot(
        "penetration",
        "Penetration",
        "m",
        false,
        vec![series("deepest interpenetration", each(&|r| r.penetration))],
    ));
    plots
}

/// The plots of a 2D trace: energy, momentum (p and L), angular velocity of `omega_bodies`,
/// contacts, PGS sweeps and residuals, the deepest overlap. Units are the 2D system's (block,
/// time unit, the mass of a black block).
pub fn plots_2d(records: &[Record2], omega_bodies: &[usize]) -> Vec<Plot> {
    let each = |f: &dyn Fn(&Record2) -> Option<f64>| records.iter().map(f).collect::<Vec<_>>();
    let mut plots = vec![plot(
        "energy",
        "Energy",
        "mass·block²/time²",
        false,
        vec![
            series("kinetic", each(&|r| Some(r.energy.kinetic))),
            series("potential", each(&|r| Some(r.energy.potential))),
            series("total", each(&|r| Some(r.energy.total))),
        ],
    )];
    plots.push(plot(
        "momentum",
        "Linear momentum",
        "mass·block/time",
        false,
        vec![
            series("p_x", each(&|r| Some(r.momentum.linear[0]))),
            series("p_y", each(&|r| Some(r.momentum.linear[1]))),
        ],
    ));
    plots.push(plot(
        "angular_momentum",
        "Angular momentum about the origin",
        "mass·block²/time",
        false,
        vec![series("L", each(&|r| Some(r.momentum.angular)))],
    ));
    let omega: Vec<_> = omega_bodies
        .iter()
        .map(|&b| {
            series(
                format!("ω body{b}"),
                each(&|r| r.bodies.get(b).map(|s| s.omega)),
            )
        })
        .collect();
    if !omega.is_empty() {
        plots.push(plot("omega", "Angular velocity", "rad/time", false, omega));
    }
    plots.push(plot(
        "contacts",
        "Contacts",
        "",
        false,
        vec![series("contacts", each(&|r| Some(r.contact_count as f64)))],
    ));
    let solver: Vec<_> = records.iter().map(|r| r.solver).collect();
    plots.extend(solver_plots(
        &solver,
        "block/time",
        "mass·block/time, block/time, mass·block²/time²",
    ));
    plots.push(plot(
        "penetration",
        "Deepest overlap",
        "block",
        false,
        vec![series(
            "deepest disc overlap",
            each(&|r| Some(r.deepest_overlap)),
        )],
    ));
    plots
}

/// The bodies whose angular velocity is plotted when none are chosen: the first
/// [`MAX_OMEGA_BODIES`] that are not pinned.
pub fn default_omega_bodies(pinned: &[bool]) -> Vec<usize> {
    (0..pinned.len())
        .filter(|&i| !pinned[i])
        .take(MAX_OMEGA_BODIES)
        .collect()
}
