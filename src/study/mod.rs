//! Work-precision studies: how far each run of a scene is from a reference
//! run, against what the run cost.
//!
//! Every run and the reference write the same output frames `k = 0 .. K-1`
//! (times `t_k = k / fps`). For a run with positions `x_i^k` and total
//! energy `E^k` (kinetic plus every potential term), against the
//! reference's `x̂_i^k` and `Ê^k`:
//!
//! - **trajectory error**, when the run and the reference share the mesh
//!   (the same rest positions): `e_x = max_k max_i ‖x_i^k − x̂_i^k‖`, the
//!   largest vertex distance over all output frames;
//! - **centre-of-mass error**, when the meshes differ (a study over
//!   `mesh.cells`): `e_x = max_k ‖c^k − ĉ^k‖` with `c = Σ m_i x_i / Σ m_i`;
//! - **energy error**: `e_E = max_k |E^k − Ê^k| / |Ê^0|`, relative to the
//!   reference's initial energy (or, when that is zero, to `max_k |Ê^k|`).
//!
//! The **observed order of convergence** in `dt` of a series of runs that
//! differ only in their time step is the least-squares slope `p` of
//! `log e_x` against `log dt` ([`observed_order`]): a scheme of order `p`
//! has `e_x ≈ C dt^p` once `dt` is small enough.
//!
//! [`StudyTable`] writes the rows as `study.csv` and `study.md`, and
//! [`work_precision_plot`] draws `study.png`: error against wall time on
//! log-log axes, one series per solver and integrator.

mod convergence;
mod error_tracker;
mod plot;
mod study_table;

pub use convergence::observed_order;
pub use error_tracker::{ErrorKind, ErrorTracker, Reference, RunErrors};
pub use plot::{PlotPoint, work_precision_plot};
pub use study_table::{RunStatus, STUDY_COLUMNS, StudyRow, StudyTable};
