//! Gzip as the outputs use it: the run store's entries and `curves.csv.gz`.
//!
//! A gzip header normally carries a timestamp and the writer's operating system, and a DEFLATE
//! encoder's output depends on its level and implementation. Every output here must be a pure
//! function of the plan (a merge of shards equals an unsharded run byte for byte, on any
//! machine), so [`encoder`] fixes all of them: modification time 0, operating system 255
//! ("unknown"), level 1 for store entries and 6 for tables, and flate2's pure-Rust backend
//! (`miniz_oxide`), which has no platform-dependent code paths. Any gzip reader (`zcat`, Python's `gzip`, pandas, R) reads
//! the files.

use std::io::{self, Read as _, Write};

use flate2::Compression;
use flate2::GzBuilder;
use flate2::write::GzEncoder;

/// The DEFLATE level: the fastest, measured on the default run's store entries (docs/paper-notes.md
/// §"Per-run overhead"): level 1 compresses them 5.05× at 45 % of level 6's CPU, level 6 5.62×;
/// at level 6 deflate was 27.6 % of a 1000-seed ε-greedy run.
const LEVEL: u32 = 1;

/// The DEFLATE level of the tables (`curves.csv.gz`, `trajectories.csv.gz`): written once per
/// output folder rather than once per run, so a denser level than the store's pays. Level 4
/// was the knee on full-precision curves (docs/paper-notes.md §16: level 6 took twice its CPU
/// for 1.9 %). Since the curves' reals are written at single precision (§24.1), measured on the
/// default run's five curves tables (68.1 MB of CSV, `miniz_oxide`, 2-core machine under load):
/// level 4 9.24 MB in 0.9 s, level 5 9.14 MB in 1.1 s, level 6 9.04 MB in 2.0 s, level 9
/// 8.99 MB in 4.5 s. Level 6 buys the 0.2 MB that keep the default run's folder under issue
/// 35's 25 MB for about 1 s of a 70 s run; beyond it the gain is a quarter of that for
/// twice the time.
const TABLE_LEVEL: u32 = 6;

/// A gzip encoder writing to `writer` whose bytes depend only on what is written: the run
/// store's entries, at the fast level.
#[must_use]
pub fn encoder<W: Write>(writer: W) -> GzEncoder<W> {
    encoder_at(writer, LEVEL)
}

/// Like [`encoder`], at the denser level for tables written once per output folder.
#[must_use]
pub fn table_encoder<W: Write>(writer: W) -> GzEncoder<W> {
    encoder_at(writer, TABLE_LEVEL)
}

fn encoder_at<W: Write>(writer: W, level: u32) -> GzEncoder<W> {
    GzBuilder::new()
        .mtime(0)
        .operating_system(255)
        .write(writer, Compression::new(level))
}

/// `bytes` as one gzip member.
pub fn compress(bytes: &[u8]) -> io::Result<Vec<u8>> {
    let mut encoder = encoder(Vec::with_capacity(bytes.len() / 4 + 64));
    encoder.write_all(bytes)?;
    encoder.finish()
}

/// `bytes` as one gzip member of stored (uncompressed) DEFLATE blocks: the loose runs of the
/// store ([`crate::store::RunStore::append`]), which live only until the next pack moves them
/// into a Zstandard bundle, so compressing them is work thrown away (at level 1 it was about
/// 8 % of a 1000-seed ε-greedy `reproduce-paper`, docs/paper-notes.md §24). The member keeps
/// gzip's CRC-32 and length, so a torn or damaged loose file is still detected.
pub fn compress_stored(bytes: &[u8]) -> io::Result<Vec<u8>> {
    // Five bytes of block header per 64 KiB stored block, plus header and trailer.
    let mut encoder = encoder_at(Vec::with_capacity(bytes.len() + bytes.len() / 8192 + 64), 0);
    encoder.write_all(bytes)?;
    encoder.finish()
}

/// The content of the first gzip member at the start of `bytes`, and how many bytes of `bytes`
/// the member takes (header, compressed data and trailer). Fails on a damaged or incomplete
/// member (the CRC and length in the trailer are checked).
pub fn decompress_member(bytes: &[u8]) -> io::Result<(Vec<u8>, usize)> {
    let mut rest = bytes;
    let mut content = Vec::new();
    // The bufread decoder consumes exactly the member from the slice, so what is left of
    // `rest` says where the member ends.
    flate2::bufread::GzDecoder::new(&mut rest).read_to_end(&mut content)?;
    Ok((content, bytes.len() - rest.len()))
}

/// The members of `bytes`, each as its compressed bytes and its content (for tools and tests
/// that inspect, damage or edit one entry of a bundle).
pub fn split_members(bytes: &[u8]) -> io::Result<Vec<(&[u8], Vec<u8>)>> {
    let mut members = Vec::new();
    let mut rest = bytes;
    while !rest.is_empty() {
        let (content, len) = decompress_member(rest)?;
        members.push((&rest[..len], content));
        rest = &rest[len..];
    }
    Ok(members)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compress_is_deterministic_and_round_trips() {
        let text = b"{\"a\":1}\t{\"b\":[1,2,3]}\n".repeat(50);
        let first = compress(&text).unwrap();
        assert_eq!(first, compress(&text).unwrap());
        assert!(first.len() < text.len() / 4);
        // mtime 0, OS 255: nothing of the machine or the time in the header (XFL 4 says
        // "fastest", which level 1 is).
        assert_eq!(&first[..10], &[0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 4, 255]);
        let (content, len) = decompress_member(&first).unwrap();
        assert_eq!((content, len), (text.clone(), first.len()));
    }

    #[test]
    fn members_are_found_one_after_another_and_damage_is_an_error() {
        let mut bytes = compress(b"first\n").unwrap();
        let first_len = bytes.len();
        bytes.extend(compress(b"second\n").unwrap());
        let (content, len) = decompress_member(&bytes).unwrap();
        assert_eq!((content.as_slice(), len), (&b"first\n"[..], first_len));
        let (content, _) = decompress_member(&bytes[len..]).unwrap();
        assert_eq!(content, b"second\n");
        // Cut short: incomplete.
        assert!(decompress_member(&bytes[..first_len - 3]).is_err());
        // One flipped bit in the trailer's CRC: damaged.
        let mut flipped = bytes.clone();
        flipped[first_len - 8] ^= 1;
        assert!(decompress_member(&flipped).is_err());
    }
}
