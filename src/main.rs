//! The `elasto` binary: parse the command line, run, map errors to exit codes.

use clap::Parser;
use elasto::app::{Cli, run};

fn main() {
    let cli = Cli::parse();
    if let Err(error) = run(cli) {
        let code = error.exit_code();
        eprintln!("error: {:#}", anyhow::Error::new(error));
        std::process::exit(code);
    }
}
