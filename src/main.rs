//! The `elasto` binary: parse the command line, run, map errors to exit codes.

use clap::Parser;
use elasto::app::{Cli, run};
use std::io::Write;

fn main() {
    if std::env::var_os("NODEVICE_SELECT").is_none() {
        // Mesa's Vulkan device-select layer (installed with lavapipe) prints a
        // spurious "XDG_RUNTIME_DIR is invalid" error when adapters are listed
        // on a headless machine; it selects nothing elasto needs.
        // SAFETY: no other thread exists yet.
        unsafe { std::env::set_var("NODEVICE_SELECT", "1") };
    }
    #[cfg(unix)]
    exit_on_interrupt();
    let cli = parse_command_line();
    if let Err(error) = run(cli) {
        if error.is_broken_pipe() {
            // The reader of the pipe has gone (`elasto scenes | head -1`):
            // nothing is left to say, and no one to say it to.
            std::process::exit(0);
        }
        let code = error.exit_code();
        // Not eprintln!: it panics when stderr cannot be written either.
        let _ = writeln!(
            std::io::stderr(),
            "error: {}",
            chain(&anyhow::Error::new(error))
        );
        std::process::exit(code);
    }
}

/// On SIGINT, SIGTERM or SIGHUP (a closed terminal, a dropped ssh session):
/// stop the encoders, remove the partial frames and videos (frames already
/// complete stay; a run replacing an earlier one removes all of its
/// outputs, and the earlier run stays as it was), say so, and exit with 128 + the signal number (130, 143,
/// 129), the code a shell shows for a process the signal killed.
#[cfg(unix)]
fn exit_on_interrupt() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    use std::io::IsTerminal;
    // Without a handler the signals keep their default action.
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) else {
        return;
    };
    std::thread::spawn(move || {
        if let Some(signal) = signals.forever().next() {
            elasto::encode::remove_partial_files();
            let kept = elasto::output::abandon_staged_runs();
            let name = match signal {
                SIGINT => "SIGINT",
                SIGHUP => "SIGHUP",
                _ => "SIGTERM",
            };
            // A progress bar may hold the terminal's last line.
            let newline = if std::io::stderr().is_terminal() {
                "\n"
            } else {
                ""
            };
            // Not eprintln!: after SIGHUP the terminal may be gone, and a
            // panic here would leave the process running.
            let _ = match kept.first() {
                // A --force run over an earlier one: nothing of it was kept.
                Some(folder) => writeln!(
                    std::io::stderr(),
                    "{newline}error: interrupted by {name}; the earlier run in {} is kept as \
                     it was, this run's outputs removed",
                    folder.display()
                ),
                None => writeln!(
                    std::io::stderr(),
                    "{newline}error: interrupted by {name}; frames already written are kept, \
                     partial frames and videos removed"
                ),
            };
            // _exit, not exit: atexit handlers (the graphics driver's) must
            // not run while other threads may still be drawing.
            // SAFETY: _exit has no preconditions; it ends the process at once.
            unsafe { libc::_exit(128 + signal) };
        }
    });
}

/// The command line, or the end of the process: `--help` and `--version`
/// print and exit 0 (exit 1 with a message when standard output cannot be
/// written, as every command does), a bad command line exits 2.
fn parse_command_line() -> Cli {
    let error = match Cli::try_parse() {
        Ok(cli) => return cli,
        Err(error) => error,
    };
    use clap::error::ErrorKind;
    if !matches!(
        error.kind(),
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion
    ) {
        error.exit();
    }
    let printed = error.print().and_then(|()| std::io::stdout().flush());
    match printed {
        Ok(()) => std::process::exit(0),
        Err(cause) if cause.kind() == std::io::ErrorKind::BrokenPipe => std::process::exit(0),
        Err(cause) => {
            let _ = writeln!(
                std::io::stderr(),
                "error: cannot write to standard output: {cause}"
            );
            std::process::exit(1);
        }
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
