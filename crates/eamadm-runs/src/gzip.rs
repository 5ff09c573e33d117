//! Gzip as the outputs use it: the run store's entries and `curves.csv.gz`.
//!
//! A gzip header normally carries a timestamp and the writer's operating system, and a DEFLATE
//! encoder's output depends on its level and implementation. Every output here must be a pure
//! function of the plan (a merge of shards equals an unsharded run byte for byte, on any
//! machine), so every encoder here fixes all of them: modification time 0, operating system
//! 255 ("unknown"), a fixed level, and a fixed implementation. Store entries and artefacts
//! ([`encoder`], level 1) use flate2's pure-Rust backend (`miniz_oxide`), which has no
//! platform-dependent code paths; tables ([`table_encoder`], level 6) use libdeflate, the C
//! library built from the source `libdeflate-sys` pins (Cargo.lock), whose output depends on
//! its version and level only. Any gzip reader (`zcat`, Python's `gzip`, pandas, R) reads
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
/// 35's 25 MB; beyond it the gain is a quarter of that for twice the time. libdeflate at the
/// same level (§24.2) is about 2.6 times as fast as `miniz_oxide` and 6 % smaller (the
/// 1000-seed Task I curves, 14.7 MB of CSV: 1.43 MB in 0.33 s against 1.34 MB in 0.13 s).
const TABLE_LEVEL: i32 = 6;

/// The CSV bytes of a table compressed as one gzip member: libdeflate compresses whole
/// buffers, so a table is a series of members (a valid gzip file, read whole by every gzip
/// reader) of this size, the last one shorter, and memory stays bounded however long the
/// table. Each member starts its DEFLATE window afresh, which costs a few hundred bytes per
/// 4 MiB.
const TABLE_MEMBER_BYTES: usize = 4 << 20;

/// A gzip encoder writing to `writer` whose bytes depend only on what is written: the run
/// store's entries, at the fast level.
#[must_use]
pub fn encoder<W: Write>(writer: W) -> GzEncoder<W> {
    encoder_at(writer, LEVEL)
}

/// A gzip encoder for tables written once per output folder, at a denser level than the
/// store's ([`TableEncoder`]).
#[must_use]
pub fn table_encoder<W: Write>(writer: W) -> TableEncoder<W> {
    TableEncoder {
        out: writer,
        buffer: Vec::new(),
        compressed: Vec::new(),
        compressor: None,
        members: 0,
    }
}

/// A table's gzip stream: its bytes are gathered into members of 4 MiB (`TABLE_MEMBER_BYTES`; the
/// boundaries depend on the bytes written only, not on how the writes were cut), each
/// compressed by libdeflate at level 6. [`TableEncoder::finish`] writes the last member and
/// returns the writer.
pub struct TableEncoder<W: Write> {
    out: W,
    buffer: Vec<u8>,
    compressed: Vec<u8>,
    compressor: Option<libdeflater::Compressor>,
    members: u64,
}

impl<W: Write> TableEncoder<W> {
    /// Compresses the gathered bytes as one member and writes it.
    fn write_member(&mut self) -> io::Result<()> {
        let compressor = self.compressor.get_or_insert_with(|| {
            libdeflater::Compressor::new(
                libdeflater::CompressionLvl::new(TABLE_LEVEL).unwrap_or_default(),
            )
        });
        self.compressed
            .resize(compressor.gzip_compress_bound(self.buffer.len()), 0);
        let len = compressor
            .gzip_compress(&self.buffer, &mut self.compressed)
            .map_err(|error| io::Error::other(format!("gzip: {error:?}")))?;
        self.out.write_all(&self.compressed[..len])?;
        self.buffer.clear();
        self.members += 1;
        Ok(())
    }

    /// Writes what is gathered as the last member (an empty member when nothing was written,
    /// so the file is valid gzip) and returns the writer, flushed.
    ///
    /// # Errors
    /// If the writer fails.
    pub fn finish(mut self) -> io::Result<W> {
        if !self.buffer.is_empty() || self.members == 0 {
            self.write_member()?;
        }
        self.out.flush()?;
        Ok(self.out)
    }
}

impl<W: Write> Write for TableEncoder<W> {
    fn write(&mut self, bytes: &[u8]) -> io::Result<usize> {
        let room = TABLE_MEMBER_BYTES - self.buffer.len();
        let taken = bytes.len().min(room);
        if self.buffer.capacity() == 0 {
            // Grown from 64 KiB rather than a member's 4 MiB at once: reserving it all saved no
            // page fault and raised the default run's peak by 8 MiB (docs/paper-notes.md §24.5).
            self.buffer
                .reserve_exact(TABLE_MEMBER_BYTES.min(bytes.len().max(64 << 10)));
        }
        self.buffer.extend_from_slice(&bytes[..taken]);
        if self.buffer.len() == TABLE_MEMBER_BYTES {
            self.write_member()?;
        }
        Ok(taken)
    }

    fn flush(&mut self) -> io::Result<()> {
        // A member is written only when full (or by `finish`), so that the boundaries depend on
        // the bytes alone; flushing passes on what the writer holds.
        self.out.flush()
    }
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
///
/// Written here rather than by a DEFLATE encoder at level 0, which copied the bytes through
/// its own buffers (3 % of the 1000-seed command, docs/paper-notes.md §24.2): the gzip header
/// of [`encoder`] (modification time 0, operating system 255; XFL 0), blocks of at most
/// 65,535 bytes each with its five-byte header (RFC 1951 §3.2.4), and the CRC-32 and length.
pub fn compress_stored(bytes: &[u8]) -> io::Result<Vec<u8>> {
    const BLOCK: usize = 65_535;
    let blocks = bytes.len().div_ceil(BLOCK).max(1);
    let mut member = Vec::with_capacity(bytes.len() + 5 * blocks + 18);
    member.extend_from_slice(&[0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 255]);
    let mut chunks = bytes.chunks(BLOCK).peekable();
    if chunks.peek().is_none() {
        // One empty final block.
        member.extend_from_slice(&[1, 0, 0, 0xff, 0xff]);
    }
    while let Some(chunk) = chunks.next() {
        let len = u16::try_from(chunk.len()).map_err(io::Error::other)?;
        member.push(u8::from(chunks.peek().is_none()));
        member.extend_from_slice(&len.to_le_bytes());
        member.extend_from_slice(&(!len).to_le_bytes());
        member.extend_from_slice(chunk);
    }
    let mut crc = flate2::Crc::new();
    crc.update(bytes);
    member.extend_from_slice(&crc.sum().to_le_bytes());
    // ISIZE: the length modulo 2^32 (RFC 1952).
    member.extend_from_slice(&((bytes.len() & 0xffff_ffff) as u32).to_le_bytes());
    Ok(member)
}

/// The length of [`compress_stored`]'s member of `len` bytes: its header, a five-byte header
/// per block of at most 65,535 bytes (one block when empty), the bytes, and the trailer.
#[must_use]
pub fn stored_member_len(len: u64) -> u64 {
    10 + 5 * len.div_ceil(65_535).max(1) + len + 8
}

/// The content of `member` if it is exactly a member as [`compress_stored`] writes it (its
/// header, stored blocks, the last one final, and a trailer whose CRC-32 and length match),
/// read without a DEFLATE decoder; `None` for anything else (another member, damage), which
/// [`decompress_member`] then reads or rejects.
#[must_use]
pub fn stored_member_content(member: &[u8]) -> Option<Vec<u8>> {
    let (header, mut rest) = member.split_at_checked(10)?;
    if header != [0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 255] {
        return None;
    }
    let mut content = Vec::with_capacity(rest.len().saturating_sub(13));
    loop {
        let (&[flags, l0, l1, n0, n1], after) = rest.split_first_chunk::<5>()?;
        let len = u16::from_le_bytes([l0, l1]);
        if flags > 1 || u16::from_le_bytes([n0, n1]) != !len {
            return None;
        }
        let (block, after) = after.split_at_checked(usize::from(len))?;
        content.extend_from_slice(block);
        rest = after;
        if flags == 1 {
            break;
        }
    }
    let (&[c0, c1, c2, c3, i0, i1, i2, i3], after) = rest.split_first_chunk::<8>()?;
    let mut crc = flate2::Crc::new();
    crc.update(&content);
    let length = (content.len() & 0xffff_ffff) as u32;
    (after.is_empty()
        && crc.sum() == u32::from_le_bytes([c0, c1, c2, c3])
        && length == u32::from_le_bytes([i0, i1, i2, i3]))
    .then_some(content)
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

    proptest::proptest! {
        /// A stored member reads back by itself as a DEFLATE decoder reads it, at the length
        /// `stored_member_len` says; any single changed byte makes it `None` or what the
        /// decoder reads (never other content).
        #[test]
        fn a_stored_member_reads_back_without_a_decoder(
            content in proptest::collection::vec(proptest::num::u8::ANY, 0..140_000),
            at in proptest::num::usize::ANY,
            flip in 1_u8..=255,
        ) {
            let member = compress_stored(&content).unwrap();
            proptest::prop_assert_eq!(member.len() as u64, stored_member_len(content.len() as u64));
            proptest::prop_assert_eq!(stored_member_content(&member), Some(content.clone()));
            let mut damaged = member.clone();
            let at = at % damaged.len();
            damaged[at] ^= flip;
            if let Some(read) = stored_member_content(&damaged) {
                let decoded = decompress_member(&damaged).map(|(content, _)| content).ok();
                proptest::prop_assert_eq!(Some(read), decoded);
            }
            proptest::prop_assert_eq!(stored_member_content(&member[..member.len() - 1]), None);
        }
    }

    #[test]
    fn a_compressed_member_is_not_read_as_stored() {
        let text = b"{\"a\":1}\n".repeat(20);
        assert_eq!(stored_member_content(&compress(&text).unwrap()), None);
        assert_eq!(stored_member_content(&[]), None);
    }

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

    /// A table is the same bytes however its writes are cut, is a series of members of
    /// `TABLE_MEMBER_BYTES` whose header says nothing of the machine or the time, and reads
    /// back whole through a gzip reader of concatenated members (as `zcat`, Python's `gzip`
    /// and R read them).
    #[test]
    fn a_table_is_deterministic_members_that_read_back_whole() {
        let text: Vec<u8> = (0..600_000_u32)
            .flat_map(|i| format!("task1,epsilon-greedy,{i},{}\n", i % 97).into_bytes())
            .collect();
        assert!(text.len() > 2 * TABLE_MEMBER_BYTES);
        let whole = {
            let mut table = table_encoder(Vec::new());
            table.write_all(&text).unwrap();
            table.finish().unwrap()
        };
        let pieces = {
            let mut table = table_encoder(Vec::new());
            for piece in text.chunks(4093) {
                table.write_all(piece).unwrap();
            }
            table.finish().unwrap()
        };
        assert_eq!(whole, pieces);
        assert_eq!(&whole[..10], &[0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 255]);
        let members = split_members(&whole).unwrap();
        assert_eq!(members.len(), text.len().div_ceil(TABLE_MEMBER_BYTES));
        assert!(
            members[..members.len() - 1]
                .iter()
                .all(|(_, content)| content.len() == TABLE_MEMBER_BYTES)
        );
        let mut read = Vec::new();
        flate2::read::MultiGzDecoder::new(whole.as_slice())
            .read_to_end(&mut read)
            .unwrap();
        assert_eq!(read, text);
        // An empty table is still a gzip file.
        let empty = table_encoder(Vec::new()).finish().unwrap();
        assert_eq!(split_members(&empty).unwrap().len(), 1);
    }

    /// A stored member reads back as its bytes through any gzip reader, whatever its length
    /// (empty, one block, several blocks), and damage to its bytes fails the CRC.
    #[test]
    fn a_stored_member_reads_back_and_damage_fails_its_crc() {
        for len in [0_usize, 1, 65_535, 65_536, 200_001] {
            let text: Vec<u8> = (0..len).map(|i| (i * 7 % 251) as u8).collect();
            let member = compress_stored(&text).unwrap();
            assert_eq!(
                member.len(),
                text.len() + 5 * len.div_ceil(65_535).max(1) + 18
            );
            let (content, used) = decompress_member(&member).unwrap();
            assert_eq!((content, used), (text.clone(), member.len()));
            let mut read = Vec::new();
            flate2::read::GzDecoder::new(member.as_slice())
                .read_to_end(&mut read)
                .unwrap();
            assert_eq!(read, text);
            if len > 0 {
                let mut flipped = member.clone();
                flipped[15] ^= 1;
                assert!(decompress_member(&flipped).is_err());
            }
        }
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
