//! The `elasto` binary: parse the command line, run, map errors to exit codes.

use clap::Parser;
use elasto::app::{Cli, run};

fn main() {
    if std::env::var_os("NODEVICE_SELECT").is_none() {
        // Mesa's Vulkan device-select layer (installed with lavapipe) prints a
        // spurious "XDG_RUNTIME_DIR is invalid" error when adapters are listed
        // on a headless machine; it selects nothing elasto needs.
        // SAFETY: no other thread exists yet.
        unsafe { std::env::set_var("NODEVICE_SELECT", "1") };
    }
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
