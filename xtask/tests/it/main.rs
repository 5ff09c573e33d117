//! Integration tests of the `xtask` binary, one module per subject.

mod kill_resume;
mod slurm;
