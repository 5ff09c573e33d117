//! `docs/ARCHITECTURE.md` tied to the code (issue 36 item 5, as rust-analyzer's tidy ties docs to
//! code): each crate's `Modules:` line lists exactly the modules its `lib.rs` (xtask: `main.rs`)
//! declares, each crate states an `Architecture Invariant:` naming the test or tidy rule that
//! checks it, and that test or rule exists. Also the one atomic write: only `eamadm-runs`
//! renames a temporary file into place and syncs it.
//!
//! Each check is a function over in-memory text, so the unit tests below prove it catches a
//! deliberate mismatch; the workspace tests apply them to the repository.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// One crate's entry of ARCHITECTURE's code map.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Entry {
    /// The crate's folder, relative to the workspace root (`crates/dql`, `xtask`).
    folder: String,
    /// The modules its `Modules:` line lists, if it has one.
    modules: Option<BTreeSet<String>>,
    /// The text of its `Architecture Invariant:` line(s), if any.
    invariant: Option<String>,
}

/// The code map's entries of crates: bullets `` - `crates/<name>` — `` and `` - `xtask` — ``,
/// each running to the next bullet, blank line or heading.
fn entries(architecture: &str) -> Vec<Entry> {
    let mut found: Vec<(String, String)> = Vec::new();
    let mut open = false;
    for line in architecture.lines() {
        let starts = line.starts_with("- `crates/") || line.starts_with("- `xtask` —");
        if starts {
            let folder = line[3..].split('`').next().unwrap_or_default().to_owned();
            found.push((folder, String::new()));
            open = true;
            continue;
        }
        if line.starts_with("- ") || line.trim().is_empty() || line.starts_with('#') {
            open = false;
        }
        if open && let Some((_, body)) = found.last_mut() {
            body.push_str(line.trim());
            body.push(' ');
        }
    }
    found
        .into_iter()
        .map(|(folder, body)| Entry {
            folder,
            modules: labelled(&body, "Modules:").map(|list| {
                list.split(',')
                    .map(|m| m.trim().trim_end_matches('.').trim_matches('`').to_owned())
                    .filter(|m| !m.is_empty())
                    .collect()
            }),
            invariant: labelled(&body, "Architecture Invariant:").map(str::to_owned),
        })
        .collect()
}

/// The text after `label` up to the next label of an entry or its end.
fn labelled<'a>(body: &'a str, label: &str) -> Option<&'a str> {
    let start = body.find(label)? + label.len();
    let rest = &body[start..];
    let end = ["Modules:", "Architecture Invariant:"]
        .iter()
        .filter_map(|other| rest.find(other))
        .min()
        .unwrap_or(rest.len());
    Some(rest[..end].trim())
}

/// The modules a crate root declares (`mod x;`, `pub mod x;`, `pub(crate) mod x;`), not inline
/// ones (`mod tests { … }`).
fn declared_modules(root_source: &str) -> BTreeSet<String> {
    root_source
        .lines()
        .filter_map(|line| {
            let line = line.trim();
            let rest = line
                .strip_prefix("pub mod ")
                .or_else(|| line.strip_prefix("pub(crate) mod "))
                .or_else(|| line.strip_prefix("mod "))?;
            let name = rest.strip_suffix(';')?;
            name.chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_')
                .then(|| name.to_owned())
        })
        .collect()
}

/// What is wrong with one entry's module list against its crate root's source.
fn module_mismatch(entry: &Entry, root_source: &str) -> Option<String> {
    let Some(listed) = &entry.modules else {
        return Some(format!(
            "{}: no `Modules:` line in its ARCHITECTURE entry",
            entry.folder
        ));
    };
    let declared = declared_modules(root_source);
    if &declared == listed {
        return None;
    }
    let missing: Vec<&String> = declared.difference(listed).collect();
    let extra: Vec<&String> = listed.difference(&declared).collect();
    Some(format!(
        "{}: ARCHITECTURE's `Modules:` line lacks {missing:?} and lists {extra:?} that the code \
         does not declare; make the line list exactly the modules of the crate root",
        entry.folder
    ))
}

/// The checks an invariant line names: `` test `name` `` and `` tidy `rule` ``.
fn named_checks(invariant: &str) -> Vec<(&'static str, String)> {
    let mut checks = Vec::new();
    for kind in ["test", "tidy"] {
        let marker = format!("{kind} `");
        let mut rest = invariant;
        while let Some(at) = rest.find(&marker) {
            let after = &rest[at + marker.len()..];
            let Some(end) = after.find('`') else { break };
            checks.push((kind, after[..end].to_owned()));
            rest = &after[end..];
        }
    }
    checks
}

/// What is wrong with one entry's invariant, given the workspace's source text (every `.rs` and
/// `.py` file, concatenated) and tidy's source.
fn invariant_mismatch(entry: &Entry, sources: &str, tidy: &str) -> Vec<String> {
    let Some(invariant) = &entry.invariant else {
        return vec![format!(
            "{}: no `Architecture Invariant:` line in its ARCHITECTURE entry",
            entry.folder
        )];
    };
    let checks = named_checks(invariant);
    if checks.is_empty() {
        return vec![format!(
            "{}: its invariant names no check; end it with (test `name`) or (tidy `rule`)",
            entry.folder
        )];
    }
    checks
        .into_iter()
        .filter(|(kind, name)| match *kind {
            "test" => {
                !sources.contains(&format!("fn {name}("))
                    && !sources.contains(&format!("def {name}("))
            }
            _ => !tidy.contains(&format!("\"{name}\"")),
        })
        .map(|(kind, name)| {
            format!(
                "{}: its invariant names {kind} `{name}`, which does not exist",
                entry.folder
            )
        })
        .collect()
}

/// Lines of non-test Rust code that make a file appear by renaming a synced temporary file:
/// outside `eamadm-runs` (the one atomic write) there must be none.
fn own_atomic_writes(path: &str, text: &str) -> Vec<String> {
    const PATTERNS: [&str; 4] = ["sync_all", "fs::rename", ".persist(", "NamedTempFile"];
    let code = text.split("#[cfg(test)]").next().unwrap_or(text);
    code.lines()
        .enumerate()
        .filter(|(_, line)| !line.trim_start().starts_with("//"))
        .filter(|(_, line)| PATTERNS.iter().any(|p| line.contains(p)))
        .map(|(i, line)| {
            format!(
                "{path}:{}: `{}` writes a file atomically outside eamadm-runs; use \
                 eamadm_runs::atomic::write_atomic (or AtomicFile)",
                i + 1,
                line.trim()
            )
        })
        .collect()
}

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map_or_else(|| PathBuf::from("."), Path::to_path_buf)
}

/// Every file under `dir` (hidden folders, `target` and `snapshots` skipped) ending in one of
/// `suffixes`.
fn files_under(dir: &Path, suffixes: &[&str]) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(current) = stack.pop() {
        let Ok(read) = std::fs::read_dir(&current) else {
            continue;
        };
        for entry in read.flatten() {
            let path = entry.path();
            let name = entry.file_name().to_string_lossy().into_owned();
            if name.starts_with('.') || name == "target" || name == "snapshots" {
                continue;
            }
            if path.is_dir() {
                stack.push(path);
            } else if suffixes.iter().any(|s| name.ends_with(s)) {
                out.push(path);
            }
        }
    }
    out.sort();
    out
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn architectures_module_lists_are_the_crates_modules() {
    let root = workspace_root();
    let entries = entries(&read(&root.join("docs/ARCHITECTURE.md")));
    let mut problems = Vec::new();
    let mut folders = BTreeSet::new();
    for entry in &entries {
        let src = root.join(&entry.folder).join("src");
        let crate_root = [src.join("lib.rs"), src.join("main.rs")]
            .into_iter()
            .find(|p| p.is_file());
        let Some(crate_root) = crate_root else {
            problems.push(format!("{}: no crate root under src/", entry.folder));
            continue;
        };
        folders.insert(entry.folder.clone());
        problems.extend(module_mismatch(entry, &read(&crate_root)));
    }
    // Every crate of the workspace has an entry.
    for manifest in files_under(&root.join("crates"), &["Cargo.toml"]) {
        let folder = manifest
            .parent()
            .and_then(|p| p.strip_prefix(&root).ok())
            .map(|p| p.display().to_string())
            .unwrap_or_default();
        if folder.matches('/').count() == 1 && !folders.contains(&folder) {
            problems.push(format!("{folder}: no entry in ARCHITECTURE's code map"));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn every_crates_architecture_invariant_names_a_check_that_exists() {
    let root = workspace_root();
    let entries = entries(&read(&root.join("docs/ARCHITECTURE.md")));
    let mut sources = String::new();
    for folder in ["crates", "xtask", "benches"] {
        for file in files_under(&root.join(folder), &[".rs", ".py"]) {
            sources.push_str(&read(&file));
            sources.push('\n');
        }
    }
    let tidy = read(&root.join("xtask/tests/it/tidy.rs"));
    let problems: Vec<String> = entries
        .iter()
        .flat_map(|entry| invariant_mismatch(entry, &sources, &tidy))
        .collect();
    assert!(entries.len() >= 12, "{entries:?}");
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn only_eamadm_runs_writes_files_atomically() {
    let root = workspace_root();
    let mut problems = Vec::new();
    for folder in ["crates", "xtask/src"] {
        for file in files_under(&root.join(folder), &[".rs"]) {
            let path = file
                .strip_prefix(&root)
                .map(|p| p.display().to_string())
                .unwrap_or_default();
            if path.starts_with("crates/eamadm-runs/") || path.contains("/tests/") {
                continue;
            }
            problems.extend(own_atomic_writes(&path, &read(&file)));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

const SAMPLE: &str = "# Architecture\n\n## Code map\n\n\
- `crates/dql` — Q-tables and\n  more.\n  Modules: `env`, `table`.\n  Architecture \
Invariant: schedules (test `a_test`).\n\
- `xtask` — the command line.\n  Modules: `cli`.\n  Architecture Invariant: thin (tidy \
`thin-xtask`).\n\n## Invariants\n";

#[test]
fn the_entries_are_read_with_their_modules_and_invariants() {
    let found = entries(SAMPLE);
    assert_eq!(found.len(), 2);
    assert_eq!(found[0].folder, "crates/dql");
    assert_eq!(
        found[0].modules,
        Some(["env".to_owned(), "table".to_owned()].into())
    );
    assert_eq!(
        found[0].invariant.as_deref(),
        Some("schedules (test `a_test`).")
    );
    assert_eq!(found[1].folder, "xtask");
    assert_eq!(
        named_checks(found[1].invariant.as_deref().unwrap()),
        vec![("tidy", "thin-xtask".to_owned())]
    );
}

#[test]
fn a_module_missing_or_extra_in_the_list_is_named() {
    let entry = &entries(SAMPLE)[0];
    assert_eq!(
        module_mismatch(entry, "//! Doc.\npub mod env;\nmod table;\n"),
        None
    );
    // A declared module not listed, and an inline test module ignored.
    let problem = module_mismatch(
        entry,
        "pub mod env;\npub mod table;\npub mod policy;\n#[cfg(test)]\nmod tests {\n}\n",
    )
    .unwrap();
    assert!(problem.contains("lacks [\"policy\"]"), "{problem}");
    let problem = module_mismatch(entry, "pub mod env;\n").unwrap();
    assert!(problem.contains("lists [\"table\"]"), "{problem}");
    let unlisted = Entry {
        modules: None,
        ..entry.clone()
    };
    assert!(
        module_mismatch(&unlisted, "")
            .unwrap()
            .contains("no `Modules:`")
    );
}

#[test]
fn an_invariant_naming_no_check_or_a_missing_one_is_named() {
    let found = entries(SAMPLE);
    let sources = "fn a_test() {}\n";
    let tidy = "rule: \"thin-xtask\",";
    assert!(invariant_mismatch(&found[0], sources, tidy).is_empty());
    assert!(invariant_mismatch(&found[1], sources, tidy).is_empty());
    let problems = invariant_mismatch(&found[0], "fn another() {}\n", tidy);
    assert_eq!(problems.len(), 1);
    assert!(problems[0].contains("test `a_test`"), "{problems:?}");
    let unchecked = Entry {
        invariant: Some("it is good.".to_owned()),
        ..found[0].clone()
    };
    assert!(invariant_mismatch(&unchecked, sources, tidy)[0].contains("names no check"));
    let absent = Entry {
        invariant: None,
        ..found[0].clone()
    };
    assert!(invariant_mismatch(&absent, sources, tidy)[0].contains("no `Architecture Invariant:`"));
}

#[test]
fn an_atomic_write_outside_the_store_is_flagged_but_not_in_tests() {
    let code = "//! Doc.\nfn save() {\n    file.sync_all()?;\n    std::fs::rename(a, b)?;\n}\n\
                #[cfg(test)]\nmod tests {\n    fn t() { f.sync_all().unwrap(); }\n}\n";
    let found = own_atomic_writes("crates/ea-tree/src/persist.rs", code);
    assert_eq!(found.len(), 2, "{found:?}");
    assert!(found[0].starts_with("crates/ea-tree/src/persist.rs:3:"));
    assert!(own_atomic_writes("x.rs", "// sync_all is mentioned in a comment\n").is_empty());
}
