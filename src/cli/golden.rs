//! `rigidref golden`: compare fresh runs of the canonical scenes with golden/, or regenerate it.

use anyhow::bail;
use clap::Args;
use rigidref::verify::golden::{
    Tolerances, canonical_scenes, compare, golden_path, read_golden, record, write_golden,
};
use std::path::PathBuf;

/// Arguments of `rigidref golden`.
#[derive(Args)]
#[command(after_long_help = "\
Each canonical scene (every scenes/*.json) is run for 5 s, recording every 5th frame, and
compared quantity by quantity with golden/NAME.jsonl: |fresh − golden| ≤ tol · (1 + |golden|),
tol = 1e-8 for states, energies and momenta and 1e-6 for contacts and the penetration measure; the number of records and of
contacts must match exactly. Exit status 1 when any scene differs or has no golden trace.

--update rewrites golden/ from the current code. That is legitimate only when a change of the
method or of a canonical scene was intended and reviewed (docs/verification.md §\"Golden
traces\"): say in the commit what changed in the physics and why.")]
pub struct GoldenArgs {
    /// Rewrite golden/ from fresh runs instead of comparing.
    #[arg(long)]
    pub update: bool,
    /// The project root (holding scenes/ and golden/).
    #[arg(long, default_value = ".")]
    pub root: PathBuf,
}

/// Compares or regenerates.
pub fn golden(args: GoldenArgs) -> anyhow::Result<()> {
    let scenes_dir = args.root.join("scenes");
    let golden_dir = args.root.join("golden");
    let scenes = canonical_scenes(&scenes_dir).map_err(|e| anyhow::anyhow!(e))?;
    if scenes.is_empty() {
        bail!("{}: no canonical scenes (*.json)", scenes_dir.display());
    }
    let mut failed = Vec::new();
    for path in &scenes {
        let source = format!(
            "scenes/{}",
            path.file_name().unwrap_or_default().to_string_lossy()
        );
        let out = golden_path(&golden_dir, path);
        if args.update {
            std::fs::create_dir_all(&golden_dir)?;
            write_golden(path, &source, &out).map_err(|e| anyhow::anyhow!(e))?;
            println!("wrote {}", out.display());
            continue;
        }
        let golden = match read_golden(&out) {
            Ok(g) => g,
            Err(e) => {
                println!("{source}: {e}");
                failed.push(source);
                continue;
            }
        };
        let scene = rigidref::rigid3d::scene::load_scene(path)?;
        let fresh = record(&scene, &source).map_err(|e| anyhow::anyhow!(e))?;
        let mismatches = compare(&golden, &fresh, &Tolerances::default());
        if mismatches.is_empty() {
            println!(
                "{source}: matches {} ({} records)",
                out.display(),
                golden.records.len()
            );
        } else {
            println!(
                "{source}: {} values differ from {}; first: {}",
                mismatches.len(),
                out.display(),
                mismatches[0]
            );
            failed.push(source);
        }
    }
    if !failed.is_empty() {
        bail!(
            "{} of {} canonical scenes differ from golden/: {}",
            failed.len(),
            scenes.len(),
            failed.join(", ")
        );
    }
    Ok(())
}
