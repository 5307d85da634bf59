//! Data outputs of a run: the output folder, `stats.csv`, VTK meshes, OBJ/PLY
//! surfaces, and the one way numbers are written as text ([`format_number`]).
//!
//! Every write that fails names its file. Nothing a user made is lost: an
//! existing non-empty output folder is refused unless the caller forces it,
//! and even then only the files elasto writes are replaced, and an earlier
//! run's stay whole until the new run is complete ([`RunFolder`]).

mod folder_lock;
mod mesh_series_writer;
mod number_text;
mod output_dir;
mod output_error;
mod owned_names;
mod run_folder;
mod stats_writer;
mod surface_writer;

pub use folder_lock::FolderLock;
pub use mesh_series_writer::MeshSeriesWriter;
pub use number_text::format_number;
pub use output_dir::OutputDir;
pub use output_error::OutputError;
pub use owned_names::STAGING_FOLDER;
pub use run_folder::{RunFolder, abandon_staged_runs};
pub use stats_writer::{StatsWriter, stats_columns};
pub use surface_writer::{
    Surface, SurfaceFormat, SurfaceSeriesWriter, obstacles_file_name, surface_file_name,
    write_surface,
};
