//! The `rigidref` command-line program: one file per subcommand under src/cli/.

mod cli;

use clap::Parser;

fn main() {
    // `rigidref contacts scene.json | head` closes the pipe early: end quietly, as Unix tools do,
    // instead of panicking on the failed write (Rust ignores SIGPIPE by default).
    #[cfg(unix)]
    // SAFETY: restoring the default action of one signal at start-up, before any thread exists.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    let args = cli::Cli::parse();
    if let Err(err) = cli::dispatch(args) {
        // One line, naming the file and what is wrong; the cause chain is joined with ": ".
        eprintln!("error: {err:#}");
        // `compare` and `compare-problem`: 1 means the inputs differ, 2 that one is unreadable.
        // `crosscheck`: 3 means some problems could not be checked (none disagrees).
        let status = if err.downcast_ref::<cli::Unreadable>().is_some() {
            2
        } else if err.downcast_ref::<cli::Unverified>().is_some() {
            3
        } else {
            1
        };
        std::process::exit(status);
    }
}
