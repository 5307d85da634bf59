//! Scene files: TOML description of a simulation, validated into typed settings (filled in by the scene work).
