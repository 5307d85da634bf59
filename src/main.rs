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
    if std::env::var_os("LP_NUM_THREADS").is_none()
        && let Some(threads) = elasto::render::llvmpipe_threads()
    {
        // Mesa's llvmpipe reads this when it opens a device: each of the
        // two devices that draw frames side by side rasterises on fewer
        // threads (see `render::llvmpipe_threads`). An explicit setting
        // wins; a GPU ignores it.
        // SAFETY: no other thread exists yet.
        unsafe { std::env::set_var("LP_NUM_THREADS", threads.to_string()) };
    }
    #[cfg(unix)]
    exit_on_interrupt();
    let cli = Cli::parse();
    if let Err(error) = run(cli) {
        let code = error.exit_code();
        eprintln!("error: {}", chain(&anyhow::Error::new(error)));
        std::process::exit(code);
    }
}

/// On SIGINT or SIGTERM: stop the encoders, remove the partial frames and
/// videos (frames already complete stay), say so, and exit with 128 + the
/// signal number (130, 143), the code a shell shows for a process the signal
/// killed.
#[cfg(unix)]
fn exit_on_interrupt() {
    use signal_hook::consts::{SIGINT, SIGTERM};
    use std::io::IsTerminal;
    // Without a handler the signals keep their default action.
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM]) else {
        return;
    };
    std::thread::spawn(move || {
        if let Some(signal) = signals.forever().next() {
            elasto::render::remove_partial_files();
            let name = if signal == SIGINT {
                "SIGINT"
            } else {
                "SIGTERM"
            };
            // A progress bar may hold the terminal's last line.
            let newline = if std::io::stderr().is_terminal() {
                "\n"
            } else {
                ""
            };
            eprintln!(
                "{newline}error: interrupted by {name}; frames already written are kept, \
                 partial frames and videos removed"
            );
            // _exit, not exit: atexit handlers (the graphics driver's) must
            // not run while other threads may still be drawing.
            // SAFETY: _exit has no preconditions; it ends the process at once.
            unsafe { libc::_exit(128 + signal) };
        }
    });
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
