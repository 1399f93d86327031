//! `rigidref plot TRACE.jsonl… [--out FILE.svg] [--quantities …]`: the viewer's plots as a
//! file, for one trace or several overlaid. docs/viewing.md §"Plots".

use anyhow::bail;
use clap::Args;
use rigidref::tools::viewing::plot::{PlottedRun, TIME_UNIT_2D, TIME_UNIT_3D, plot_runs};
use rigidref::tools::viewing::series::{QUANTITIES, plots_2d, plots_3d};
use rigidref::tools::viewing::view::RunTrace;
use std::path::PathBuf;

/// Arguments of `rigidref plot`.
#[derive(Args)]
#[command(after_long_help = "\
Draws quantities over time from traces written by `rigidref run` (or any trace in that format,
docs/trace-format.md), one panel per quantity:
  energy            kinetic (3D: linear and angular), potential, total
  momentum          linear momentum p
  angular_momentum  3D: L about the system's centre of mass; 2D: L about the origin
  omega             angular velocity of the bodies chosen by --bodies (default: the first four
                    that are not pinned)
  contacts          number of contacts in the record
  sweeps            solver iterations in the recorded frame: PGS sweeps or Newton iterations
  residual          solver residual, and the exact Coulomb residual with cone friction (log scale)
  criteria          the physical criteria, largest over the frame's contacts: primal, dual,
                    complementarity, signorini, cone boundary, max dissipation (log scale;
                    docs/contact.md §\"Physical criteria\"; traces that record them)
  penetration       3D: the penetration measure; 2D: the deepest disc overlap
Several traces are overlaid, each series named with its trace's file name: rigidref against
another simulator's trace of the same scene, or two integrators. A trace cut off in its last
line is plotted up to its last complete record, with a warning.")]
pub struct PlotArgs {
    /// One or more traces (.jsonl) of the same system (all 3D or all 2D).
    #[arg(required = true)]
    pub traces: Vec<PathBuf>,
    /// The file to write: SVG (.svg) or PNG (.png), by its extension.
    #[arg(long, short, default_value = "plot.svg")]
    pub out: PathBuf,
    /// The quantities to plot, comma-separated, in this order [default: all of them].
    #[arg(long, value_delimiter = ',', value_name = "Q,…")]
    pub quantities: Vec<String>,
    /// Bodies whose angular velocity is plotted, by index, comma-separated.
    #[arg(long, value_delimiter = ',', value_name = "I,J,…")]
    pub bodies: Vec<usize>,
    /// Print nothing but errors.
    #[arg(long, short)]
    pub quiet: bool,
}

/// Writes the plot.
pub fn plot(args: PlotArgs) -> anyhow::Result<()> {
    for q in &args.quantities {
        if !QUANTITIES.contains(&q.as_str()) {
            bail!(
                "--quantities: unknown quantity {q:?}; known: {}",
                QUANTITIES.join(", ")
            );
        }
    }
    let ext = args
        .out
        .extension()
        .map(|e| e.to_string_lossy().to_lowercase());
    if !matches!(ext.as_deref(), Some("svg" | "png")) {
        bail!(
            "{}: plots are written as SVG or PNG: name the file .svg or .png",
            args.out.display()
        );
    }
    let mut runs = Vec::new();
    let mut dimension = None;
    for path in &args.traces {
        let name = path.display().to_string();
        let (trace, _) = super::common::read_trace_file(path, &args.bodies)?;
        let omega = trace.omega_bodies(&args.bodies);
        let label = path
            .file_name()
            .map_or(name.clone(), |f| f.to_string_lossy().into_owned());
        let (dim, run) = match &trace {
            RunTrace::Three { header, records } => {
                let t = records.iter().map(|r| r.t).collect();
                (
                    3,
                    PlottedRun {
                        label,
                        t,
                        time_unit: TIME_UNIT_3D,
                        plots: plots_3d(header, records, &omega),
                    },
                )
            }
            RunTrace::Two { records, .. } => {
                let t = records.iter().map(|r| r.t).collect();
                (
                    2,
                    PlottedRun {
                        label,
                        t,
                        time_unit: TIME_UNIT_2D,
                        plots: plots_2d(records, &omega),
                    },
                )
            }
        };
        if dimension.is_some_and(|d| d != dim) {
            bail!(
                "{name}: a {dim}D trace; the traces before it are {}D: overlay traces of one system",
                5 - dim
            );
        }
        dimension = Some(dim);
        runs.push(run);
    }
    let keys: Vec<&str> = args.quantities.iter().map(String::as_str).collect();
    let title = runs
        .iter()
        .map(|r| r.label.as_str())
        .collect::<Vec<_>>()
        .join(" vs ");
    plot_runs(&runs, &keys, &args.out, &title).map_err(anyhow::Error::msg)?;
    if !args.quiet {
        eprintln!("plot           {}", args.out.display());
    }
    Ok(())
}
