//! The `rigidref` command-line program: one file per subcommand under src/cli/.

mod cli;

use clap::Parser;

fn main() {
    let args = cli::Cli::parse();
    if let Err(err) = cli::dispatch(args) {
        // One line, naming the file and what is wrong; the cause chain is joined with ": ".
        eprintln!("error: {err:#}");
        std::process::exit(1);
    }
}
