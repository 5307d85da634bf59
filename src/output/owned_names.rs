//! Which names in an output folder are elasto's: the files and folders a
//! run writes, their hidden partial and temporary files, the staging folder
//! of a re-run. Everything else there is the user's, never written or
//! removed (`output_dir.rs` checks a folder with these rules, `run_folder.rs`
//! clears an earlier run's outputs with them).

/// The hidden folder inside the output folder where a run that replaces an
/// earlier one writes until it is complete.
pub const STAGING_FOLDER: &str = ".elasto-rerun";

/// Names of the files and folders a run writes at the top of its folder.
pub(super) const OWNED_FILES: &[&str] = &[
    "scene.toml",
    "stats.csv",
    "video.png",
    "video.mp4",
    "video.gif",
];
/// Sub-folders whose `frame_*` files and `frames.pvd` a run writes.
pub(super) const OWNED_FOLDERS: &[&str] = &["frames", "meshes", "surfaces"];

/// Whether elasto writes or clears an entry of this name at the top of its folder
/// (its files, its sub-folders, the hidden partial videos, and the staging
/// folder of a run that replaces an earlier one).
pub(super) fn ours_at_top(name: &str) -> bool {
    OWNED_FILES.contains(&name)
        || name == STAGING_FOLDER
        || OWNED_FOLDERS.contains(&name)
        || (name.starts_with(".video.") && name.ends_with(".partial"))
        || partial_of(name).is_some_and(|file| OWNED_FILES.contains(&file))
}

/// The name a hidden partial file stands for (`.scene.toml.partial`: the
/// file being written, left by a killed run).
fn partial_of(name: &str) -> Option<&str> {
    name.strip_prefix('.')?.strip_suffix(".partial")
}

/// Whether elasto writes or clears an entry of this name inside `frames/`,
/// `meshes/` or `surfaces/` (frames, surfaces, their hidden partial and
/// temporary files, the ParaView collection).
pub(super) fn ours_inside(name: &str) -> bool {
    numbered(name, "frame_", &[".png", ".vtu"])
        || name == "frames.pvd"
        || (name.starts_with(".frame_") && name.ends_with(".partial"))
        || numbered(name, "surface_", &[".obj", ".ply"])
        || numbered(name, "obstacles_", &[".obj", ".ply"])
        || (name.starts_with(".surface_") && name.ends_with(".tmp"))
        || (name.starts_with(".obstacles_") && name.ends_with(".tmp"))
        || partial_of(name).is_some_and(ours_inside)
        || spare_of(name).is_some_and(ours_inside)
}

/// Whether `name` is `PREFIX` + a frame number + one of `extensions`, as
/// elasto names frames and surfaces (`frame_0042.png`; at least 4 digits,
/// more in runs of 10 000 frames or more): `frame_abc.png` or
/// `frame_0042-notes.png` are the user's.
fn numbered(name: &str, prefix: &str, extensions: &[&str]) -> bool {
    let Some(rest) = name.strip_prefix(prefix) else {
        return false;
    };
    extensions.iter().any(|extension| {
        rest.strip_suffix(extension)
            .is_some_and(|digits| digits.len() >= 4 && digits.bytes().all(|b| b.is_ascii_digit()))
    })
}

/// The name a spare file stands for (`.frame_0042.png.spare`: the frame
/// `frame_0042.png` hidden by an earlier version of elasto for reuse, left
/// by a killed run; removed like the frames).
fn spare_of(name: &str) -> Option<&str> {
    name.strip_prefix('.')?.strip_suffix(".spare")
}
