//! A tree as JSON text and back (validated load, index rebuilt on load).
//!
//! This crate writes no file: [`EaTree::to_json`] is the saved form, and whoever stores it
//! writes it (in this workspace atomically, through `eamadm_runs::atomic::write_atomic`, the one
//! atomic-write implementation: docs/paper-notes.md §25). [`EaTree::load`] reads a file back.
//!
//! The file is one JSON object, one cluster per line:
//!
//! ```text
//! {
//!   "format": "ea-tree",
//!   "version": 1,
//!   "similarity": "weighted-jaccard",
//!   "config": {"state_threshold":1.0,"action_threshold":1.0},
//!   "samples_seen": 3,
//!   "clusters": [
//!     {"count":2,"state":[[0,1,2],[1,2,2]],"actions":[[0,2]],"q1":0.5,"q2":0.25,"state_differs":1,"action_differs":null},
//!     …
//!   ]
//! }
//! ```
//!
//! `state` lists `[feature, bin, members carrying it]`, `actions` lists `[action, members]`,
//! children are cluster indices. Floats are written in shortest round-trip form and read back
//! exactly, so a round trip is lossless. The lookup index is not saved: it is rebuilt.

use std::path::Path;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::cluster::{ActionCount, Cluster, ClusterId, TokenCount};
use crate::config::EaTreeConfig;
use crate::encoding::Token;
use crate::error::LoadError;
use crate::index::WalkIndex;
use crate::similarity::Similarity;
use crate::tree::{EaTree, index_kind};

const FORMAT: &str = "ea-tree";
const VERSION: u32 = 1;

/// Just enough of a file to tell whether it is ours and which version.
#[derive(Deserialize)]
struct Header {
    format: String,
    version: u32,
}

/// The saved form of a tree.
#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct TreeFile {
    format: String,
    version: u32,
    similarity: String,
    config: EaTreeConfig,
    samples_seen: u64,
    clusters: Vec<ClusterRecord>,
}

/// The saved form of a cluster.
#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ClusterRecord {
    count: u64,
    /// `(feature, bin, members carrying it)`, ascending.
    state: Vec<(u32, u32, u64)>,
    /// `(action, members)`, ascending.
    actions: Vec<(usize, u64)>,
    q1: f64,
    q2: f64,
    state_differs: Option<u32>,
    action_differs: Option<u32>,
}

impl From<&Cluster> for ClusterRecord {
    fn from(cluster: &Cluster) -> Self {
        Self {
            count: cluster.count,
            state: cluster
                .state_tokens
                .iter()
                .map(|t| (t.token.feature, t.token.bin, t.count))
                .collect(),
            actions: cluster
                .actions
                .iter()
                .map(|a| (a.action, a.count))
                .collect(),
            q1: cluster.q1,
            q2: cluster.q2,
            state_differs: cluster.state_differs.map(|c| c.0),
            action_differs: cluster.action_differs.map(|c| c.0),
        }
    }
}

impl<S: Similarity> EaTree<S> {
    fn to_file(&self) -> TreeFile {
        TreeFile {
            format: FORMAT.to_owned(),
            version: VERSION,
            similarity: self.similarity.name().to_owned(),
            config: self.config,
            samples_seen: self.samples_seen,
            clusters: self.clusters.iter().map(ClusterRecord::from).collect(),
        }
    }

    /// The tree as JSON text, one cluster per line (see [`crate::persist`]).
    #[must_use]
    pub fn to_json(&self) -> String {
        let file = self.to_file();
        let mut out = String::from("{\n");
        out += &format!("  \"format\": {},\n", json(&file.format));
        out += &format!("  \"version\": {},\n", file.version);
        out += &format!("  \"similarity\": {},\n", json(&file.similarity));
        out += &format!("  \"config\": {},\n", json(&file.config));
        out += &format!("  \"samples_seen\": {},\n", file.samples_seen);
        out += "  \"clusters\": [";
        for (i, record) in file.clusters.iter().enumerate() {
            out += if i == 0 { "\n    " } else { ",\n    " };
            out += &json(record);
        }
        out += if file.clusters.is_empty() {
            "]\n}\n"
        } else {
            "\n  ]\n}\n"
        };
        out
    }

    /// Reads a tree from JSON, checking that it is one this crate could have built, and
    /// rebuilds its index.
    ///
    /// # Errors
    /// [`LoadError::Truncated`], [`LoadError::Corrupt`], [`LoadError::UnsupportedFormat`],
    /// [`LoadError::SimilarityMismatch`], [`LoadError::InvalidConfig`] or
    /// [`LoadError::Inconsistent`].
    pub fn from_json_with(text: &str, similarity: S) -> Result<Self, LoadError> {
        let header: Header = serde_json::from_str(text).map_err(|e| parse_error(&e))?;
        if header.format != FORMAT || header.version != VERSION {
            return Err(LoadError::UnsupportedFormat {
                format: header.format,
                version: header.version,
            });
        }
        let file: TreeFile = serde_json::from_str(text).map_err(|e| parse_error(&e))?;
        Self::from_file(file, similarity)
    }

    /// Reads a tree from a file holding its [`to_json`](Self::to_json) text, built with
    /// `similarity`.
    ///
    /// # Errors
    /// [`LoadError::Io`] naming `path`, or an error of [`from_json_with`](Self::from_json_with).
    pub fn load_with(path: impl AsRef<Path>, similarity: S) -> Result<Self, LoadError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|source| LoadError::Io {
            path: path.to_owned(),
            source,
        })?;
        Self::from_json_with(&text, similarity)
    }

    fn from_file(file: TreeFile, similarity: S) -> Result<Self, LoadError> {
        if file.format != FORMAT || file.version != VERSION {
            return Err(LoadError::UnsupportedFormat {
                format: file.format,
                version: file.version,
            });
        }
        if file.similarity != similarity.name() {
            return Err(LoadError::SimilarityMismatch {
                expected: similarity.name().to_owned(),
                found: file.similarity,
            });
        }
        file.config.validate().map_err(LoadError::InvalidConfig)?;
        let clusters = validate_clusters(&file.clusters)?;
        let members = clusters
            .iter()
            .try_fold(0_u64, |sum, c| sum.checked_add(c.count));
        if members != Some(file.samples_seen) {
            return Err(inconsistent(
                "tree",
                format!(
                    "samples_seen is {} but the clusters hold {} members",
                    file.samples_seen,
                    members.map_or_else(|| "more than u64::MAX".to_owned(), |m| m.to_string())
                ),
            ));
        }
        let kind = index_kind(&file.config, &similarity);
        let mut tree = Self {
            config: file.config,
            similarity,
            index: WalkIndex::empty(kind),
            clusters,
            samples_seen: file.samples_seen,
        };
        tree.rebuild_index();
        tree.index.shrink_to_fit();
        Ok(tree)
    }
}

impl<S: Similarity + Default> EaTree<S> {
    /// [`from_json_with`](Self::from_json_with) the default similarity.
    ///
    /// # Errors
    /// As [`from_json_with`](Self::from_json_with).
    pub fn from_json(text: &str) -> Result<Self, LoadError> {
        Self::from_json_with(text, S::default())
    }

    /// [`load_with`](Self::load_with) the default similarity.
    ///
    /// # Errors
    /// As [`load_with`](Self::load_with).
    pub fn load(path: impl AsRef<Path>) -> Result<Self, LoadError> {
        Self::load_with(path, S::default())
    }
}

impl<S: Similarity> PartialEq for EaTree<S> {
    /// Same similarity name, thresholds, sample count and clusters (the index follows).
    fn eq(&self, other: &Self) -> bool {
        self.similarity.name() == other.similarity.name()
            && self.config == other.config
            && self.samples_seen == other.samples_seen
            && self.clusters == other.clusters
    }
}

impl<S: Similarity> Serialize for EaTree<S> {
    fn serialize<Ser: Serializer>(&self, serializer: Ser) -> Result<Ser::Ok, Ser::Error> {
        self.to_file().serialize(serializer)
    }
}

impl<'de, S: Similarity + Default> Deserialize<'de> for EaTree<S> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let file = TreeFile::deserialize(deserializer)?;
        Self::from_file(file, S::default()).map_err(serde::de::Error::custom)
    }
}

/// Compact JSON of a value that always serialises (plain data with finite floats).
fn json<T: Serialize>(value: &T) -> String {
    serde_json::to_string(value).expect("plain data with finite floats always serialises")
}

fn parse_error(error: &serde_json::Error) -> LoadError {
    let (line, column) = (error.line(), error.column());
    match error.classify() {
        serde_json::error::Category::Eof => LoadError::Truncated { line, column },
        _ => LoadError::Corrupt {
            line,
            column,
            message: error.to_string(),
        },
    }
}

fn inconsistent(location: impl Into<String>, problem: String) -> LoadError {
    LoadError::Inconsistent {
        location: location.into(),
        problem,
    }
}

/// Checks every invariant the tree keeps and turns the records into clusters.
fn validate_clusters(records: &[ClusterRecord]) -> Result<Vec<Cluster>, LoadError> {
    if u32::try_from(records.len()).is_err() {
        return Err(inconsistent(
            "tree",
            format!("{} clusters exceed the u32 index space", records.len()),
        ));
    }
    let mut has_parent = vec![false; records.len()];
    let mut clusters = Vec::with_capacity(records.len());
    for (i, record) in records.iter().enumerate() {
        let here = format!("cluster #{i}");
        let bad = |problem: String| inconsistent(here.clone(), problem);
        if record.count == 0 {
            return Err(bad("count is 0".to_owned()));
        }
        for (name, value) in [("q1", record.q1), ("q2", record.q2)] {
            if !value.is_finite() {
                return Err(bad(format!("{name} is {value}, not finite")));
            }
        }
        // State tokens: ascending, counts in 1..=count, at most `count` per feature,
        // at least one token per member.
        let mut state_tokens = Vec::with_capacity(record.state.len());
        let mut total: u64 = 0;
        let mut feature_members: u64 = 0;
        for (j, &(feature, bin, count)) in record.state.iter().enumerate() {
            let token = Token { feature, bin };
            if count == 0 || count > record.count {
                return Err(bad(format!(
                    "state token {feature}:{bin} has count {count}, outside 1..={}",
                    record.count
                )));
            }
            match j.checked_sub(1).map(|p| record.state[p]) {
                Some((f, b, _)) if (f, b) >= (feature, bin) => {
                    return Err(bad(format!(
                        "state tokens not strictly ascending at {feature}:{bin}"
                    )));
                }
                Some((f, _, _)) if f == feature => {
                    feature_members = feature_members.saturating_add(count);
                }
                _ => feature_members = count,
            }
            if feature_members > record.count {
                return Err(bad(format!(
                    "feature {feature} is carried {feature_members} times by {} members",
                    record.count
                )));
            }
            total = total
                .checked_add(count)
                .ok_or_else(|| bad("state token counts overflow u64".to_owned()))?;
            state_tokens.push(TokenCount { token, count });
        }
        if total < record.count {
            return Err(bad(format!(
                "{} members carry only {total} state tokens (each needs at least one)",
                record.count
            )));
        }
        let mut actions = Vec::with_capacity(record.actions.len());
        let mut action_members: u64 = 0;
        for (j, &(action, count)) in record.actions.iter().enumerate() {
            if count == 0 {
                return Err(bad(format!("action {action} has count 0")));
            }
            if j > 0 && record.actions[j - 1].0 >= action {
                return Err(bad(format!("actions not strictly ascending at {action}")));
            }
            action_members = action_members.saturating_add(count);
            actions.push(ActionCount { action, count });
        }
        if action_members != record.count {
            return Err(bad(format!(
                "action counts sum to {action_members}, not to count {}",
                record.count
            )));
        }
        let mut child = |name: &str, link: Option<u32>| -> Result<Option<ClusterId>, LoadError> {
            let Some(c) = link else { return Ok(None) };
            let c_index = c as usize;
            if c_index >= records.len() || c_index <= i {
                return Err(bad(format!(
                    "{name} is #{c}; a child must come after its parent and before #{}",
                    records.len()
                )));
            }
            if std::mem::replace(&mut has_parent[c_index], true) {
                return Err(bad(format!("{name} #{c} already has a parent")));
            }
            Ok(Some(ClusterId(c)))
        };
        let state_differs = child("state_differs", record.state_differs)?;
        let action_differs = child("action_differs", record.action_differs)?;
        clusters.push(Cluster {
            count: record.count,
            state_tokens,
            state_total: total,
            actions,
            q1: record.q1,
            q2: record.q2,
            state_differs,
            action_differs,
        });
    }
    // Children come after parents and have one parent each, so all but the root must have
    // a parent for the clusters to form one tree.
    if let Some(orphan) = has_parent.iter().skip(1).position(|&p| !p) {
        return Err(inconsistent(
            format!("cluster #{}", orphan + 1),
            "no cluster links to it".to_owned(),
        ));
    }
    Ok(clusters)
}
