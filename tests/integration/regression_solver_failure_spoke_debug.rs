//! Issue 33, item 5 (in part): valid-looking extreme parameters that fail
//! at step 0 printed a Rust debug string (`sparse Cholesky factorisation
//! failed: NonPositivePivot { index: 70 }`). The failure now says in words
//! what went wrong and what may help; no Debug-formatted internals.

use crate::cli_common as common;
use common::*;

#[test]
fn a_factorisation_that_fails_says_why_in_words() {
    let tmp = tempfile::tempdir().unwrap();
    let o = elasto(
        tmp.path(),
        &[
            "run",
            "--no-render",
            "-q",
            "--frames",
            "3",
            "-o",
            "o",
            "--set",
            "material.density=1e-20",
        ],
    );
    assert_code(&o, 1);
    let err = stderr(&o);
    assert!(
        err.contains("the system matrix is not positive definite in floating point")
            && err.contains("material.density")
            && !err.contains("NonPositivePivot")
            && !err.contains("{ index"),
        "{err}"
    );
}
