//! The snapshot regression test of `fixtures/`: every fixture [`eamadm::fixtures::generate`]
//! makes equals the committed file (what each file's header promises of `cargo test -p xtask`,
//! besides `cargo xtask regen-fixtures --check`).

use std::fmt::Write as _;
use std::path::Path;

#[test]
fn committed_fixtures_match_the_code() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures");
    let mut failures = String::new();
    for file in &eamadm::fixtures::generate().unwrap() {
        let committed = std::fs::read_to_string(root.join(&file.path)).unwrap_or_default();
        let diff = eamadm_present::generated::first_difference(&committed, &file.content);
        if let Some(diff) = diff {
            let _ = writeln!(failures, "fixtures/{}:\n{diff}", file.path);
        }
    }
    assert!(
        failures.is_empty(),
        "fixtures differ from the code's output; if the change is intended, run \
         `cargo xtask regen-fixtures` and review the diff:\n{failures}"
    );
}
