//! Data outputs of a run: stats.csv, resolved scene, meshes (filled in by the CLI work).
