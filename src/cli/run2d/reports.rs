//! What `rigidref run` reports of a 2D run besides its trace: the nut-bag report, the scaling
//! CSV, every contact's line, and the summary printed at the end (docs/blocks2d.md).

use super::*;

/// The reports a 2D run writes beside its trace: the scaling CSV (every step) and the nut
/// report (every recorded step).
pub(super) struct Reports2 {
    pub(super) scaling: Option<std::io::BufWriter<std::fs::File>>,
    pub(super) nuts: Option<std::io::BufWriter<std::fs::File>>,
    /// The nut report's path and its (t, fraction of the heaviest fifth in the upper half)
    /// points, for the plot beside it.
    pub(super) nut_points: Option<(std::path::PathBuf, Vec<(f64, f64)>)>,
    /// The first recorded time a nut was outside the bag and the most outside at once.
    pub(super) nuts_outside: Option<(f64, usize)>,
    /// The nut report's own path (the warning names it).
    pub(super) nut_csv: Option<std::path::PathBuf>,
}

impl Reports2 {
    /// Creates the files asked for, with their header lines.
    pub(super) fn open(asked: &crate::cli::run_args::Run2dReports) -> anyhow::Result<Reports2> {
        let mut reports = Reports2 {
            scaling: None,
            nuts: None,
            nut_points: None,
            nuts_outside: None,
            nut_csv: None,
        };
        if let Some(p) = &asked.scaling_csv {
            let mut f = crate::cli::common::create_file(p)?;
            writeln!(f, "step,bodies,contacts,pgs_seconds")?;
            reports.scaling = Some(f);
        }
        if let Some(p) = &asked.nut_report {
            let mut f = crate::cli::common::create_file(p)?;
            writeln!(
                f,
                "t,mean_height_heaviest_fifth,mean_height_others,heaviest_fraction_in_upper_half,outside_bag"
            )?;
            reports.nuts = Some(f);
            reports.nut_points = Some((p.with_extension("svg"), Vec::new()));
            reports.nut_csv = Some(p.clone());
        }
        Ok(reports)
    }

    /// Step `k`'s line of the scaling CSV: contacts detected and PGS seconds, summed over its
    /// substeps.
    pub(super) fn scaling(
        &mut self,
        w: &World2,
        k: u64,
        totals: &SolveTotals,
    ) -> std::io::Result<()> {
        match &mut self.scaling {
            Some(f) => writeln!(
                f,
                "{k},{},{},{:.9}",
                w.bodies.len(),
                w.contacts_in_step,
                totals.solve_seconds
            ),
            None => Ok(()),
        }
    }

    /// A line of the nut report: where the heaviest fifth of the moving bodies is now.
    pub(super) fn nuts(&mut self, w: &World2) -> std::io::Result<()> {
        let Some(f) = &mut self.nuts else {
            return Ok(());
        };
        let s = nut_statistics(w);
        if let Some((_, points)) = &mut self.nut_points {
            points.push((w.time(), s.heaviest_fraction_in_upper_half));
        }
        let outside = outside_bag(w);
        if outside > 0 {
            let (_, most) = self.nuts_outside.get_or_insert((w.time(), 0));
            *most = (*most).max(outside);
        }
        writeln!(
            f,
            "{},{},{},{},{}",
            w.time(),
            s.heaviest_mean_height,
            s.others_mean_height,
            s.heaviest_fraction_in_upper_half,
            outside
        )
    }

    /// Flushes the files and draws the nut report's plot (NAME.svg beside NAME.csv), with the
    /// time the largest nuts took to rise, if they did (first at [`RISEN`], and held for
    /// [`HOLD_CYCLES`] cycles of `world`'s first shake), and whether every nut stayed in the bag;
    /// returns that finding for the summary, and warns on stderr when a nut left the bag.
    pub(super) fn flush(&mut self, world: &World2) -> anyhow::Result<Option<String>> {
        for f in [&mut self.nuts, &mut self.scaling].into_iter().flatten() {
            f.flush()?;
        }
        if let Some((path, points)) = &self.nut_points {
            let frequency = world.shakes.iter().map(|s| s.frequency).find(|&f| f > 0.0);
            let mut risen = match time_to_rise(points) {
                Some(t) => format!("reached {RISEN} at t = {t}"),
                None => format!("did not reach {RISEN}"),
            };
            if let Some(f) = frequency {
                let hold = HOLD_CYCLES / f;
                risen += &match time_to_rise_held(points, hold) {
                    Some(t) => format!(
                        ", held from t = {t} ({:.0} cycles) for {HOLD_CYCLES} cycles",
                        t * f
                    ),
                    None => format!(", not held for {HOLD_CYCLES} cycles"),
                };
            }
            let outside = match self.nuts_outside {
                None => "every nut stayed in the bag".to_string(),
                Some((t, most)) => {
                    eprintln!(
                        "warning: {}: a nut left the bag at t = {t} (at most {most} outside at once): the step let it pass through the wall; `--max-travel 1` takes substeps so that no block moves more than a block per substep",
                        self.nut_csv.as_deref().unwrap_or(path).display()
                    );
                    format!("{most} nuts outside the bag at most, the first at t = {t}")
                }
            };
            let title = format!("heaviest fifth of the nuts in the upper half ({risen})");
            plot(points, path, &title).map_err(anyhow::Error::msg)?;
            let last = points.last().map_or(f64::NAN, |p| p.1);
            return Ok(Some(format!(
                "heaviest fifth in the upper half: {:.2} at the start, {last:.2} at the end; {risen}; {outside}; plot {}",
                points.first().map_or(f64::NAN, |p| p.1),
                path.display()
            )));
        }
        Ok(None)
    }
}

/// Writes `value` as one line of JSON.
pub(super) fn write_json_line(
    out: &mut impl Write,
    value: &impl serde::Serialize,
) -> std::io::Result<()> {
    serde_json::to_writer(&mut *out, value)?;
    out.write_all(b"\n")
}

/// What the 2D summary reports beside the world's own state.
pub(super) struct Summary2<'a> {
    pub(super) image: &'a Path,
    pub(super) steps: u64,
    pub(super) wall: f64,
    pub(super) rest_threshold: f64,
    pub(super) totals: RunTotals,
    pub(super) most_contacts: usize,
    pub(super) overrides: &'a [String],
    /// Total energy at the start (kinetic + potential + elastic), mass · blocks² / time².
    pub(super) start_energy: f64,
}

impl Summary2<'_> {
    pub(super) fn print(&self, world: &World2) {
        let e = world.energy();
        let p = &world.params;
        let moving = world.bodies.iter().filter(|b| !b.pinned).count();
        let resting = world
            .bodies
            .iter()
            .filter(|b| !b.pinned && b.kinetic_energy() < self.rest_threshold)
            .count();
        let mut joined = String::new();
        if !world.pins.is_empty() || !world.springs.is_empty() {
            joined = format!(
                "; {} pins, {} springs",
                world.pins.len(),
                world.springs.len()
            );
        }
        eprintln!(
            "image          {} ({} bodies, {} pinned{joined})",
            self.image.display(),
            world.bodies.len(),
            world.bodies.len() - moving
        );
        eprintln!(
            "steps          {} × {} substeps, h = {}, t = {}; gravity {} at {}°",
            self.steps,
            p.substeps,
            p.h(),
            world.time(),
            p.gravity,
            p.gravity_angle
        );
        if let Some(travel) = p.max_travel {
            eprintln!(
                "adaptive       at most {travel} blocks per substep: up to {} substeps in a step{}",
                world.most_substeps,
                match world.capped_steps {
                    0 => String::new(),
                    n => format!(
                        "; warning: {n} steps at the cap of {MAX_ADAPTIVE_SUBSTEPS} substeps moved further"
                    ),
                }
            );
        }
        let solver = match p.solver {
            rigidref::solve::Solver::Newton => "by newton (exact)".to_string(),
            rigidref::solve::Solver::Pgs => format!(
                "by pgs, {} iterations{}, order {:?} (seed {})",
                p.iterations,
                p.tolerance
                    .map_or(String::new(), |t| format!(" (tolerance {t})")),
                p.order,
                p.seed
            ),
        };
        eprintln!(
            "solver         {:?} contacts {solver}, μ {}, restitution {}, warm start {}, post-stabilisation {} (slop {}){}",
            p.contact_model,
            p.mu,
            p.restitution,
            p.warm_start,
            p.post_stabilization,
            p.slop,
            if p.shock_propagation {
                ", shock propagation"
            } else {
                ""
            }
        );
        eprintln!(
            "bodies         numbered by the {} image reader, inertia {}, disc tree {}",
            describe(p.image_reader),
            describe(p.inertia),
            describe(p.disc_tree)
        );
        if let Some(set) = rigidref::blocks2d::params::preset_summary(p.preset) {
            eprintln!("preset         {set}");
        }
        if !self.overrides.is_empty() {
            eprintln!("overrides      {}", self.overrides.join(", "));
        }
        eprintln!("wall time      {:.3} s", self.wall);
        // The total and its change first: in a pile the potential energy dominates and the
        // kinetic energy alone says little about what the run gained or lost.
        eprintln!(
            "energy         {:.6e} → {:.6e}, change {:+.3e} (now kinetic {:.6e}, potential {:.6e})",
            self.start_energy,
            e.total,
            e.total - self.start_energy,
            e.kinetic,
            e.potential
        );
        if p.post_stabilization {
            eprintln!(
                "post-stab.     worst residual {:.3e} blocks per time unit (the position solve's, {} iterations)",
                world.post_stabilization_residual, p.iterations
            );
        }
        eprintln!(
            "at rest        {resting} of {moving} bodies below kinetic energy {}",
            self.rest_threshold
        );
        eprintln!(
            "contacts       {} now, at most {}; solves: {}",
            world.contacts.len(),
            self.most_contacts,
            self.totals
                .describe("blocks per time unit", "blocks (disc overlap)")
        );
        if let Some(line) =
            self.totals
                .describe_criteria("mass·blocks/time", "blocks/time", "mass·blocks²/time²")
        {
            eprintln!("criteria       {line}");
        }
    }
}

/// A value as the scene key spells it (`block_centres`).
fn describe<T: serde::Serialize>(value: T) -> String {
    serde_json::to_value(value)
        .ok()
        .and_then(|v| v.as_str().map(str::to_string))
        .unwrap_or_default()
}
