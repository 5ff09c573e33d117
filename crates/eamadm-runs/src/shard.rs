//! Shards of a plan's runs: shard `K/N` holds the runs whose key falls in bucket `K` of `N`
//! (`cargo xtask reproduce-paper --shard K/N`). A run's shard depends on its [`RunKey`] only,
//! so every machine, process and thread count agrees on it.

use std::fmt;

use thiserror::Error;

use crate::key::RunKey;

/// Shard `index` (1-based) of `count`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// K, from 1 to `count`.
    pub index: u64,
    /// N ≥ 1.
    pub count: u64,
}

/// A `--shard` value that is not `K/N` with 1 ≤ K ≤ N.
#[derive(Debug, Error, PartialEq, Eq)]
#[error("--shard {given:?}: {problem}; write K/N with 1 ≤ K ≤ N, e.g. --shard 2/3")]
pub struct ShardError {
    given: String,
    problem: &'static str,
}

impl Shard {
    /// Parses `K/N`.
    ///
    /// # Errors
    /// [`ShardError`] when the text is not `K/N` with whole numbers `1 ≤ K ≤ N`.
    pub fn parse(text: &str) -> Result<Self, ShardError> {
        let error = |problem| ShardError {
            given: text.to_owned(),
            problem,
        };
        let (k, n) = text.split_once('/').ok_or_else(|| error("no `/`"))?;
        let index: u64 = k
            .trim()
            .parse()
            .map_err(|_| error("K is not a whole number"))?;
        let count: u64 = n
            .trim()
            .parse()
            .map_err(|_| error("N is not a whole number"))?;
        if count == 0 {
            return Err(error("N is 0"));
        }
        if index == 0 || index > count {
            return Err(error("K is outside 1..=N"));
        }
        Ok(Self { index, count })
    }

    /// Whether run `key` belongs to this shard: the key's first 64 bits (it is a BLAKE3 hash,
    /// so they are uniform) modulo N, plus one, is K. It depends on the key only, so every
    /// machine and thread count agrees.
    #[must_use]
    pub fn holds(self, key: &RunKey) -> bool {
        let bucket = u64::from_str_radix(&key.as_str()[..16], 16).unwrap_or(0) % self.count;
        bucket + 1 == self.index
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_parse_and_refuse_nonsense() {
        assert_eq!(Shard::parse("2/3"), Ok(Shard { index: 2, count: 3 }));
        assert_eq!(
            Shard::parse("1/1").map(|s| s.to_string()),
            Ok("1/1".to_owned())
        );
        for bad in ["0/3", "4/3", "1/0", "3", "a/3", "1/b", "-1/3"] {
            let error = Shard::parse(bad).expect_err("refused");
            assert!(error.to_string().contains("K/N"), "{error}");
        }
    }

    /// Every key is in exactly one shard, the shards share the work, and the bucket of a
    /// pinned key is fixed (so a change of the rule is deliberate).
    #[test]
    fn the_shards_split_the_keys_exactly_and_stably() {
        let keys: Vec<RunKey> = (0..72_u64)
            .map(|i| RunKey::of(&i).expect("an integer hashes"))
            .collect();
        let count = 3;
        for key in &keys {
            let holders = (1..=count)
                .filter(|&index| Shard { index, count }.holds(key))
                .count();
            assert_eq!(holders, 1, "each run is in exactly one shard");
        }
        for index in 1..=count {
            let size = keys
                .iter()
                .filter(|key| Shard { index, count }.holds(key))
                .count();
            // Hash buckets: every shard gets work (72 keys over 3 shards).
            assert!(size > 10, "shard {index}: {size}");
        }
        let key = RunKey::from_verified_hex(format!("{:016x}{}", 7_u64, "0".repeat(48)));
        assert!(Shard { index: 2, count: 3 }.holds(&key));
    }
}
