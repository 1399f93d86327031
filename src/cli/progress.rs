//! Progress on long runs, and why a run stopped early.

/// Why a run stopped early: the simulation reached a non-finite state, or writing failed.
pub(crate) enum Stopped {
    /// The step failed; what was written before stays written.
    Failed(rigidref::sim::NonFinite),
    /// Anything else (an output that cannot be written).
    Error(anyhow::Error),
}

impl Stopped {
    /// The outcome of a run: the steps run, or the error, a failed step explained by `failed`
    /// (which names the scene and what was kept).
    pub(crate) fn outcome(
        ran: Result<u64, Stopped>,
        failed: impl FnOnce(rigidref::sim::NonFinite) -> String,
    ) -> anyhow::Result<u64> {
        match ran {
            Ok(steps) => Ok(steps),
            Err(Stopped::Failed(e)) => Err(anyhow::Error::msg(failed(e))),
            Err(Stopped::Error(e)) => Err(e),
        }
    }
}

impl From<rigidref::sim::NonFinite> for Stopped {
    fn from(e: rigidref::sim::NonFinite) -> Stopped {
        Stopped::Failed(e)
    }
}

impl From<anyhow::Error> for Stopped {
    fn from(e: anyhow::Error) -> Stopped {
        Stopped::Error(e)
    }
}

impl From<std::io::Error> for Stopped {
    fn from(e: std::io::Error) -> Stopped {
        Stopped::Error(e.into())
    }
}

/// The progress template of a run.
pub(crate) const STEPS_TEMPLATE: &str =
    "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} steps (eta {eta})";

/// A progress bar over a run's steps, shown only once the run has taken more than a second
/// (unless quiet; indicatif hides it when stderr is not a terminal).
pub(crate) struct Progress {
    bar: indicatif::ProgressBar,
    started: std::time::Instant,
    quiet: bool,
    shown: bool,
}

impl Progress {
    /// A hidden bar over `steps` steps with `template`.
    pub(crate) fn new(steps: u64, template: &str, quiet: bool) -> Progress {
        let bar = indicatif::ProgressBar::with_draw_target(
            Some(steps),
            indicatif::ProgressDrawTarget::hidden(),
        );
        bar.set_style(
            indicatif::ProgressStyle::with_template(template)
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        Progress {
            bar,
            started: std::time::Instant::now(),
            quiet,
            shown: false,
        }
    }

    /// A bar over `steps` steps with the run template.
    pub(crate) fn steps(steps: u64, quiet: bool) -> Progress {
        Progress::new(steps, STEPS_TEMPLATE, quiet)
    }

    /// Step `k` is done; reveals the bar after a second.
    pub(crate) fn tick(&mut self, k: u64) {
        if !self.quiet && !self.shown && self.started.elapsed() > std::time::Duration::from_secs(1)
        {
            self.bar
                .set_draw_target(indicatif::ProgressDrawTarget::stderr());
            self.shown = true;
        }
        if self.shown && k.is_multiple_of(16) {
            self.bar.set_position(k);
        }
    }

    /// The underlying bar (to set a message or a new length).
    pub(crate) fn bar(&self) -> &indicatif::ProgressBar {
        &self.bar
    }

    /// Prints a line to stderr above the bar (shown or not).
    pub(crate) fn println(&self, line: &str) {
        self.bar.suspend(|| eprintln!("{line}"));
    }

    /// Seconds since the bar was made.
    pub(crate) fn elapsed(&self) -> f64 {
        self.started.elapsed().as_secs_f64()
    }

    /// Removes the bar.
    pub(crate) fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
