//! The `elasto` binary: parse the command line, run, map errors to exit codes.

use clap::Parser;
use elasto::app::{Cli, run};

fn main() {
    let cli = Cli::parse();
    if let Err(error) = run(cli) {
        let code = error.exit_code();
        eprintln!("error: {}", chain(&anyhow::Error::new(error)));
        std::process::exit(code);
    }
}

/// The error and its causes on one line, as `{:#}` prints them, leaving out
/// a cause whose text the message before it already includes.
fn chain(error: &anyhow::Error) -> String {
    let mut text = String::new();
    for cause in error.chain() {
        let part = cause.to_string();
        if !text.contains(&part) {
            if !text.is_empty() {
                text.push_str(": ");
            }
            text.push_str(&part);
        }
    }
    text
}
