//! Files written by `EaTree::save`: readable by everyone like xtask's outputs (issue 14,
//! item 11), and no temporary file left behind.

use ea_tree::{EaTree, EaTreeConfig, Sample};

fn small_tree() -> EaTree {
    let mut tree = EaTree::new(EaTreeConfig::new(0.3, 0.5).unwrap()).unwrap();
    for (state, action, q1, q2) in [([0_u32, 0], 0, 1.0, 2.0), ([2, 2], 1, -1.5, 0.0)] {
        tree.insert(Sample {
            state: &state,
            action,
            q1,
            q2,
        })
        .unwrap();
    }
    tree
}

/// A saved tree has mode 0644 (it had the temporary file's 0600 before), whatever the umask
/// gives new files.
#[cfg(unix)]
#[test]
fn saved_trees_are_readable_by_everyone() {
    use std::os::unix::fs::PermissionsExt as _;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("tree.json");
    small_tree().save(&path).unwrap();
    let mode = std::fs::metadata(&path).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode, ea_tree::persist::SAVED_FILE_MODE);
    assert_eq!(mode, 0o644);
    // Saving over an existing file keeps the same permissions and leaves one file.
    small_tree().save(&path).unwrap();
    let mode = std::fs::metadata(&path).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode, 0o644);
    let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert_eq!(names.len(), 1);
    let back: EaTree = EaTree::load(&path).unwrap();
    assert!(back == small_tree());
}
