//! `RAYON_NUM_THREADS`, the threads that assemble the system: checked at
//! start-up like elasto's own variables, before any work.
//!
//! Rayon itself ignores a value that is not a number and starts as many
//! threads as a number asks for (100 000 threads made a 3-frame run take a
//! minute). Here a value that is not a whole number is an error (exit 2),
//! `0` means one thread per core (rayon's default), and a value above
//! [`thread_cap`] is lowered to it with a warning.

use super::AppError;
use super::process_clock::cores;
use std::ffi::OsStr;

/// The variable rayon reads.
pub const THREADS_VARIABLE: &str = "RAYON_NUM_THREADS";

/// The most threads elasto starts for assembly: 4 per core, at least 64.
pub fn thread_cap(cores: usize) -> usize {
    cores.saturating_mul(4).max(64)
}

/// What the variable asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum ThreadSetting {
    /// Unset or `0`: rayon's default, one thread per core.
    Default,
    /// A number of threads within the cap.
    Exactly(usize),
    /// A number above the cap (or beyond any integer): the cap is used.
    Capped(usize),
}

/// Checks [`THREADS_VARIABLE`] and, when it asks for more threads than
/// [`thread_cap`], starts rayon's pool with the cap and says so on stderr.
pub(super) fn configure_threads() -> Result<(), AppError> {
    let value = std::env::var_os(THREADS_VARIABLE);
    let shown = format!(
        "{THREADS_VARIABLE}={}",
        value.as_deref().unwrap_or_default().to_string_lossy()
    );
    let setting =
        thread_setting(value.as_deref(), cores()).map_err(|reason| AppError::Environment {
            variable: shown.clone(),
            reason,
        })?;
    if let ThreadSetting::Capped(cap) = setting {
        eprintln!(
            "warning: {shown} is more than the {cap} threads elasto starts \
             (4 per core, at least 64): using {cap}"
        );
        // Fails only when the pool already exists, which it does not yet.
        let _ = rayon::ThreadPoolBuilder::new()
            .num_threads(cap)
            .build_global();
    }
    Ok(())
}

/// The setting `value` stands for on a machine of `cores` cores, or why it
/// is refused.
fn thread_setting(value: Option<&OsStr>, cores: usize) -> Result<ThreadSetting, String> {
    let Some(value) = value else {
        return Ok(ThreadSetting::Default);
    };
    let text = value.to_str().map(str::trim).unwrap_or("");
    if text.is_empty() || !text.bytes().all(|b| b.is_ascii_digit()) {
        return Err(format!(
            "must be a whole number of threads (0: one per core), not `{}`",
            value.to_string_lossy()
        ));
    }
    let cap = thread_cap(cores);
    Ok(match text.parse::<usize>() {
        Ok(0) => ThreadSetting::Default,
        Ok(threads) if threads <= cap => ThreadSetting::Exactly(threads),
        _ => ThreadSetting::Capped(cap),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn setting(value: &str, cores: usize) -> Result<ThreadSetting, String> {
        thread_setting(Some(OsStr::new(value)), cores)
    }

    #[test]
    fn numbers_within_the_cap_are_kept_and_zero_is_the_default() {
        assert_eq!(thread_setting(None, 2), Ok(ThreadSetting::Default));
        assert_eq!(setting("0", 2), Ok(ThreadSetting::Default));
        assert_eq!(setting(" 8 ", 2), Ok(ThreadSetting::Exactly(8)));
        assert_eq!(setting("64", 2), Ok(ThreadSetting::Exactly(64)));
    }

    #[test]
    fn numbers_above_the_cap_are_lowered_to_it() {
        assert_eq!(thread_cap(2), 64);
        assert_eq!(thread_cap(32), 128);
        assert_eq!(setting("100000", 2), Ok(ThreadSetting::Capped(64)));
        assert_eq!(
            setting("99999999999999999999999", 32),
            Ok(ThreadSetting::Capped(128))
        );
    }

    #[test]
    fn anything_but_a_whole_number_is_refused() {
        for bad in ["abc", "", "-1", "2.5", "1e3", "four"] {
            let reason = setting(bad, 2).unwrap_err();
            assert!(
                reason.contains("must be a whole number of threads"),
                "{reason}"
            );
        }
    }
}
