//! A command's report on standard output, written so that a failure (a full
//! disk, a closed pipe) is an [`AppError::Stdout`] the command returns, not
//! the panic of `print!`.

use super::AppError;
use std::io::Write;

/// Writes `text` to standard output and flushes it.
pub(crate) fn print(text: &str) -> Result<(), AppError> {
    let mut out = std::io::stdout().lock();
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .map_err(|source| AppError::Stdout { source })
}
