//! Project tooling. Run `cargo xtask --help` for the list of commands.

// The experiment runner (crate `eamadm`) has not landed yet, so outside the tests nothing calls
// these modules. `expect` (not `allow`) makes the compiler say when the wiring is done and the
// attribute must go.
mod atomic;
#[cfg_attr(
    not(test),
    expect(dead_code, reason = "used once the eamadm runner lands")
)]
mod figures;
#[cfg_attr(
    not(test),
    expect(dead_code, reason = "used once the eamadm runner lands")
)]
mod progress;
#[cfg_attr(
    not(test),
    expect(dead_code, reason = "used once the eamadm runner lands")
)]
mod report;
#[cfg_attr(
    not(test),
    expect(dead_code, reason = "used once the eamadm runner lands")
)]
mod resume;
#[cfg_attr(
    not(test),
    expect(dead_code, reason = "used once the eamadm runner lands")
)]
mod stats;

fn main() {}
