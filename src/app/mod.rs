//! The `run`, `check` and `scenes` commands: scene → simulation → outputs (filled in by the CLI work).
