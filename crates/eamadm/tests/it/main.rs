//! The `eamadm` integration tests gathered into one test binary (one module per topic).

mod robot_refusals;
