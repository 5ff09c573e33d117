//! Statistics of a tree and its compact text dump.

use std::fmt::Write as _;

use serde::{Deserialize, Serialize};

use crate::cluster::Cluster;
use crate::index::IndexKind;
use crate::similarity::Similarity;
use crate::tree::EaTree;

/// Size and shape of a tree (see [`EaTree::stats`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct TreeStats {
    /// Samples inserted.
    pub samples_seen: u64,
    /// Clusters (nodes).
    pub clusters: usize,
    /// Clusters on the longest path from the root (0 for an empty tree): the most
    /// similarity tests a literal walk can take.
    pub depth: usize,
    /// Most clusters linked by consecutive "state differs" edges.
    pub longest_chain: usize,
    /// Which index lookups use.
    pub index: IndexKind,
    /// Estimated heap bytes of the clusters (arena and centres, by capacity).
    pub cluster_bytes: usize,
    /// Estimated heap bytes of the lookup index.
    pub index_bytes: usize,
}

impl TreeStats {
    /// All heap bytes (clusters and index).
    #[must_use]
    pub fn bytes(&self) -> usize {
        self.cluster_bytes + self.index_bytes
    }

    /// Heap bytes per cluster (0 for an empty tree).
    #[must_use]
    pub fn bytes_per_cluster(&self) -> f64 {
        if self.clusters == 0 {
            0.0
        } else {
            self.bytes() as f64 / self.clusters as f64
        }
    }
}

impl<S: Similarity> EaTree<S> {
    /// Samples, clusters, depth, longest chain and estimated heap bytes.
    ///
    /// Bytes are estimated from capacities: the cluster arena, each centre's two vectors,
    /// and the index's maps (with `std`'s hash-table layout: buckets of key and value plus a
    /// control byte, at most 7/8 full). Allocator overhead is not counted.
    #[must_use]
    pub fn stats(&self) -> TreeStats {
        // Parents precede children, so one forward pass sees every parent first.
        let n = self.clusters.len();
        let mut depth = vec![0_usize; n];
        let mut chain = vec![0_usize; n];
        if n > 0 {
            depth[0] = 1;
            chain[0] = 1;
        }
        for (i, cluster) in self.clusters.iter().enumerate() {
            if let Some(child) = cluster.state_differs {
                depth[child.index()] = depth[i] + 1;
                chain[child.index()] = chain[i] + 1;
            }
            if let Some(child) = cluster.action_differs {
                depth[child.index()] = depth[i] + 1;
                chain[child.index()] = 1;
            }
        }
        TreeStats {
            samples_seen: self.samples_seen,
            clusters: n,
            depth: depth.iter().copied().max().unwrap_or(0),
            longest_chain: chain.iter().copied().max().unwrap_or(0),
            index: self.index_kind(),
            cluster_bytes: self.clusters.capacity() * size_of::<Cluster>()
                + self.clusters.iter().map(Cluster::heap_bytes).sum::<usize>(),
            index_bytes: self.index.heap_bytes(),
        }
    }

    /// A compact, deterministic text dump: a header line, then one line per cluster.
    ///
    /// ```text
    /// #id n=<members> s[<feature>:<bin>@<weight> …] a[<action>@<weight> …] q1=… q2=… sd=#… ad=#…
    /// ```
    /// `@<weight>` is left out when every member carries the token (weight 1); `sd` and `ad`
    /// are the "state differs" and "action differs" children, left out when empty. Numbers
    /// are rounded to 6 decimals.
    #[must_use]
    pub fn dump(&self) -> String {
        let stats = self.stats();
        let mut out = String::new();
        // Writing to a String cannot fail.
        let _ = writeln!(
            out,
            "ea-tree similarity={} tau_s={} tau_a={} samples={} clusters={} depth={} longest_chain={}",
            self.similarity.name(),
            round6(self.config.state_threshold),
            round6(self.config.action_threshold),
            stats.samples_seen,
            stats.clusters,
            stats.depth,
            stats.longest_chain,
        );
        for view in self.clusters() {
            let _ = write!(out, "{} n={} s[", view.id(), view.count());
            let members = view.count();
            let state = view.state_centre();
            for (i, (token, count)) in state.tokens().enumerate() {
                let sep = if i == 0 { "" } else { " " };
                let _ = write!(
                    out,
                    "{sep}{}:{}{}",
                    token.feature,
                    token.bin,
                    weight(count, members)
                );
            }
            out.push_str("] a[");
            for (i, (action, count)) in view.action_centre().actions().enumerate() {
                let sep = if i == 0 { "" } else { " " };
                let _ = write!(out, "{sep}{action}{}", weight(count, members));
            }
            let _ = write!(out, "] q1={} q2={}", round6(view.q1()), round6(view.q2()));
            if let Some(child) = view.state_differs() {
                let _ = write!(out, " sd={child}");
            }
            if let Some(child) = view.action_differs() {
                let _ = write!(out, " ad={child}");
            }
            out.push('\n');
        }
        out
    }
}

/// `@weight` for a token carried by `count` of `members`, empty when all carry it.
fn weight(count: u64, members: u64) -> String {
    if count == members {
        String::new()
    } else {
        format!(
            "@{}",
            round6(crate::encoding::count_ratio(count.into(), members.into()))
        )
    }
}

/// `x` rounded to 6 decimals, without a negative zero.
fn round6(x: f64) -> f64 {
    // Beyond 1e15 an f64 has no 6th decimal to round (and `x * 1e6` could overflow).
    if x.abs() >= 1e15 {
        return x;
    }
    let rounded = (x * 1e6).round() / 1e6;
    if rounded == 0.0 { 0.0 } else { rounded }
}
