//! Energy terms of the incremental potential.
