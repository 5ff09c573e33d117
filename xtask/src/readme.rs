//! The generated parts of `README.md` and its figure, made from the default run by
//! `cargo xtask regen-fixtures` (and checked by `--check`):
//!
//! - between `<!-- generated:verdicts -->` and `<!-- /generated:verdicts -->`: the verdict table
//!   of the run's `REPORT.md`, then the claims C1–C4 in a line each ([`readme_verdicts`]);
//! - between `<!-- generated:answer -->` and `<!-- /generated:answer -->`: the answer, a
//!   paragraph per task, exactly as the run's `REPORT.md` opens ([`readme_answer`]);
//! - [`FIGURE`]: the run's `task1/steps.svg`, byte for byte.
//!
//! Both blocks are rendered by [`eamadm_present::report`] from the run's `findings.json`
//! (what the report states, as data), never cut out of its text; this module reads the run's
//! files and splices.
//!
//! The default run is made by this very binary (`reproduce-paper --out <temporary folder>`), so
//! the README always shows what the code computes now.

use std::path::Path;

use eamadm::findings::Findings;
use eamadm_present::generated::splice;
use eamadm_present::report::{readme_answer, readme_verdicts};

/// The README, relative to the workspace root.
pub(crate) const README: &str = "README.md";
/// The README's figure, relative to the workspace root.
pub(crate) const FIGURE: &str = "docs/figures/task1-steps.svg";
/// The run's file that becomes [`FIGURE`], relative to the run's output folder.
const FIGURE_SOURCE: &str = "task1/steps.svg";

/// What the README is made from: the default run's files.
#[derive(Debug, Clone)]
pub(crate) struct DefaultRun {
    /// `findings.json`.
    pub(crate) findings: Findings,
    /// `task1/steps.svg`.
    pub(crate) figure: Vec<u8>,
}

/// Reads the default run's files from its output folder.
pub(crate) fn read_run(out: &Path) -> Result<DefaultRun, String> {
    let read = |name: &str| {
        std::fs::read(out.join(name))
            .map_err(|error| format!("cannot read {}: {error}", out.join(name).display()))
    };
    let text = |name: &str| {
        read(name).and_then(|bytes| {
            String::from_utf8(bytes).map_err(|error| format!("{name} is not UTF-8: {error}"))
        })
    };
    let findings = eamadm::output_names::FINDINGS;
    Ok(DefaultRun {
        findings: Findings::from_json(&text(findings)?)
            .map_err(|error| format!("{findings} of {}: {error}", out.display()))?,
        figure: read(FIGURE_SOURCE)?,
    })
}

/// The README with its generated parts replaced by those of `run`.
pub(crate) fn generate(readme: &str, run: &DefaultRun) -> Result<String, String> {
    let readme = splice(readme, "verdicts", &readme_verdicts(&run.findings)?)?;
    splice(&readme, "answer", &readme_answer(&run.findings)?)
}
