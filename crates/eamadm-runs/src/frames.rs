//! The container of the run store's files: compressed *frames* one after another, each
//! decompressing to whole lines (`\n`-terminated). A bundle holds many lines per Zstandard
//! frame, so runs compress against the runs beside them; a loose run file is one gzip member
//! holding one line (as are the bundles written before Zstandard, which are still read).
//! Frames are recognised by their magic bytes, so `zstdcat runs/*.jsonl.zst` and `zcat` print
//! the lines of the files each writes.
//!
//! # Same bytes everywhere
//!
//! [`FrameWriter`] fixes every parameter that changes the output: level [`LEVEL`], window
//! 2^[`WINDOW_LOG`] bytes, content checksum and size written, no dictionary id, one thread; the
//! Zstandard library is the one `zstd-sys` builds from the source it pins (Cargo.lock pins the
//! version), and a frame closes after the line that brings its content past
//! [`FRAME_CONTENT_BYTES`]. So a bundle's bytes are a function of its lines (the unit test
//! `frame_bytes_are_pinned` pins a hash of them).
//!
//! # Memory while reading
//!
//! Everything is read streaming, against caps checked while decompressing: a Zstandard frame
//! asking for a window above 2^[`WINDOW_LOG`] bytes is refused before any is allocated, a line
//! is held whole only up to [`HELD_LINE_BYTES`] (a longer one is counted and hashed as it
//! streams, refused past [`MAX_LINE_BYTES`], and read again into a buffer of its exact length
//! when under it), and a frame's content is capped at [`MAX_FRAME_CONTENT_BYTES`]. Reading one
//! frame therefore holds at most the decoder's window (4 MiB; gzip's 32 KiB) and one held line
//! (4 MiB) besides what the caller makes of a line: an entry that decompresses to a gibibyte
//! costs about 8 MiB and some CPU before it is refused.

use std::fs::File;
use std::io::{self, BufRead, BufReader, Read, Seek as _, SeekFrom, Write};
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The most bytes one line (one stored run) may decompress to: far above any run's line (the
/// largest, a robot run keeping all trajectories, is a few MB), far below what would strain
/// memory (and a line is held whole only when it is under [`HELD_LINE_BYTES`]).
pub const MAX_LINE_BYTES: u64 = 256 << 20;

/// Lines up to this length are held in memory as they stream; a longer one is only counted
/// and hashed on the first pass.
pub const HELD_LINE_BYTES: usize = 4 << 20;

/// The most content one frame may decompress to: the lines of a frame this crate writes come
/// to [`FRAME_CONTENT_BYTES`] plus one line.
pub const MAX_FRAME_CONTENT_BYTES: u64 = MAX_LINE_BYTES + FRAME_CONTENT_BYTES as u64;

/// A bundle's frame closes after the line that brings its content past this many bytes: as
/// large as the window, so little is lost at frame boundaries, and small enough that reading
/// one run of a frame decompresses at most this much before it.
pub const FRAME_CONTENT_BYTES: usize = 4 << 20;

/// The Zstandard window (log2 of its bytes) of the frames written, and the largest a reader
/// accepts: 4 MiB, enough to see the runs before a run in its frame.
pub const WINDOW_LOG: u32 = 22;

/// The Zstandard level of the bundles' frames, measured on the default run's bundles and on
/// the 1000-seed `--readings none` command's (docs/paper-notes.md §14.2 and §24.5): 2.7 % more
/// bytes than level 9 for a third less compression time.
pub const LEVEL: i32 = 6;

const GZIP_MAGIC: [u8; 2] = [0x1f, 0x8b];
const ZSTD_MAGIC: [u8; 4] = [0x28, 0xb5, 0x2f, 0xfd];

/// How a frame is compressed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Codec {
    /// One gzip member (loose run files; bundles written before Zstandard).
    Gzip,
    /// One Zstandard frame (bundles).
    Zstd,
}

impl Codec {
    /// The codec of a frame starting with `bytes`, if they are its magic.
    #[must_use]
    pub fn of(bytes: &[u8]) -> Option<Self> {
        if bytes.starts_with(&ZSTD_MAGIC) {
            Some(Self::Zstd)
        } else if bytes.starts_with(&GZIP_MAGIC) {
            Some(Self::Gzip)
        } else {
            None
        }
    }
}

/// A `BufRead` counting the bytes taken from the one it wraps (read or consumed from its
/// buffer): the compressed bytes of one frame, as its decoder takes them.
struct Counting<'a, R> {
    inner: &'a mut R,
    taken: u64,
}

impl<R: BufRead> Read for Counting<'_, R> {
    fn read(&mut self, into: &mut [u8]) -> io::Result<usize> {
        let read = self.inner.read(into)?;
        self.taken += read as u64;
        Ok(read)
    }
}

impl<R: BufRead> BufRead for Counting<'_, R> {
    fn fill_buf(&mut self) -> io::Result<&[u8]> {
        self.inner.fill_buf()
    }

    fn consume(&mut self, amount: usize) {
        self.taken += amount as u64;
        self.inner.consume(amount);
    }
}

/// A decoder of the one frame at the start of `reader`, which takes exactly that frame's bytes
/// from it (nothing of the next frame).
fn frame_decoder<'a, R>(mut reader: R) -> io::Result<Box<dyn Read + Send + 'a>>
where
    R: BufRead + Send + 'a,
{
    let head = reader.fill_buf()?;
    let (codec, empty) = (Codec::of(head), head.is_empty());
    match codec {
        Some(Codec::Gzip) => Ok(Box::new(flate2::bufread::GzDecoder::new(reader))),
        Some(Codec::Zstd) => {
            let mut decoder = zstd::stream::read::Decoder::with_buffer(reader)?.single_frame();
            // A frame asking for a larger window is refused before the window is allocated.
            decoder.window_log_max(WINDOW_LOG)?;
            Ok(Box::new(decoder))
        }
        None if empty => Err(io::Error::new(
            io::ErrorKind::UnexpectedEof,
            "the file ends where a frame should start",
        )),
        None => Err(io::Error::new(
            io::ErrorKind::InvalidData,
            "not the start of a gzip member or Zstandard frame",
        )),
    }
}

/// One line of a frame as [`read_frame`] hands it over.
#[derive(Debug)]
pub struct FrameLine {
    /// Where the line starts in the frame's content.
    pub offset: u64,
    /// Its length, newline included.
    pub len: u64,
    /// The BLAKE3 hash of its bytes, newline included.
    pub digest: blake3::Hash,
    /// The line with its newline, when at most [`HELD_LINE_BYTES`] long; `None` for a longer
    /// one (read it again with [`read_line_at`]).
    pub bytes: Option<Vec<u8>>,
}

/// Reads the frame at the start of `reader` (a gzip member or Zstandard frame), handing each
/// whole line to `on_line` as it streams; `on_line` may stop the hand-over (the frame is then
/// still read to its end, to know where it ends). Returns the frame's compressed length, or
/// why the frame is damaged, incomplete or over a cap (lines handed over before that stay
/// handed over: each line has its own checksum).
///
/// # Errors
/// The problem, as a sentence fragment.
pub fn read_frame<R: BufRead + Send>(
    reader: &mut R,
    on_line: &mut dyn FnMut(FrameLine) -> ControlFlow<()>,
) -> Result<u64, String> {
    let mut counting = Counting {
        inner: reader,
        taken: 0,
    };
    let mut decoder = frame_decoder(&mut counting).map_err(|e| e.to_string())?;
    let mut chunk = vec![0_u8; 64 << 10];
    let mut line: Vec<u8> = Vec::new();
    let mut held = true;
    let mut line_start = 0_u64;
    let mut line_len = 0_u64;
    let mut content = 0_u64;
    let mut hasher = blake3::Hasher::new();
    let mut handing_over = true;
    loop {
        let read = match decoder.read(&mut chunk) {
            Ok(0) => break,
            Ok(read) => read,
            Err(error) if error.kind() == io::ErrorKind::Interrupted => continue,
            Err(error) => return Err(format!("it does not decompress ({error})")),
        };
        content += read as u64;
        if content > MAX_FRAME_CONTENT_BYTES {
            return Err(format!(
                "it decompresses to more than {MAX_FRAME_CONTENT_BYTES} bytes, the cap of one frame"
            ));
        }
        let mut rest = &chunk[..read];
        while !rest.is_empty() {
            let newline = rest.iter().position(|&b| b == b'\n');
            let piece = &rest[..newline.map_or(rest.len(), |at| at + 1)];
            rest = &rest[piece.len()..];
            line_len += piece.len() as u64;
            if line_len > MAX_LINE_BYTES {
                return Err(format!(
                    "a line decompresses to more than {MAX_LINE_BYTES} bytes, the cap of one \
                     entry"
                ));
            }
            if !handing_over {
                if newline.is_some() {
                    line_start += line_len;
                    line_len = 0;
                }
                continue;
            }
            hasher.update(piece);
            if held && line.len() + piece.len() <= HELD_LINE_BYTES {
                line.extend_from_slice(piece);
            } else if held {
                held = false;
                line = Vec::new();
            }
            if newline.is_some() {
                let whole = FrameLine {
                    offset: line_start,
                    len: line_len,
                    digest: hasher.finalize(),
                    bytes: held.then(|| std::mem::take(&mut line)),
                };
                if on_line(whole).is_break() {
                    handing_over = false;
                }
                line_start += line_len;
                line_len = 0;
                hasher = blake3::Hasher::new();
                held = true;
                line.clear();
            }
        }
    }
    drop(decoder);
    if line_len > 0 {
        return Err("it ends inside a line (no newline at its end)".to_owned());
    }
    Ok(counting.taken)
}

/// Reads `len` bytes at `offset` of the content of the frame at the start of `reader`.
///
/// # Errors
/// If the frame does not decompress that far.
pub fn read_line_at<R: BufRead + Send>(reader: R, offset: u64, len: u64) -> io::Result<Vec<u8>> {
    let mut decoder = frame_decoder(reader)?;
    skip(&mut decoder, offset)?;
    read_exactly(&mut decoder, len)
}

/// Reads and drops `count` bytes of `reader`.
fn skip(reader: &mut dyn Read, count: u64) -> io::Result<()> {
    let skipped = io::copy(&mut reader.take(count), &mut io::sink())?;
    if skipped == count {
        Ok(())
    } else {
        Err(io::Error::new(
            io::ErrorKind::UnexpectedEof,
            "the frame ends before the line",
        ))
    }
}

/// The next `len` bytes of `reader`, in a buffer of exactly that size.
fn read_exactly(reader: &mut dyn Read, len: u64) -> io::Result<Vec<u8>> {
    if len > MAX_LINE_BYTES {
        return Err(io::Error::new(
            io::ErrorKind::InvalidData,
            "a line longer than the cap of one entry",
        ));
    }
    let mut bytes = vec![0; usize::try_from(len).unwrap_or(usize::MAX)];
    reader.read_exact(&mut bytes)?;
    Ok(bytes)
}

/// An open frame being read forward, to read the lines of a file in storage order without
/// decompressing a frame again for each of its lines.
struct OpenFrame {
    file: Arc<PathBuf>,
    frame: u64,
    /// How much of the frame's content has been read.
    position: u64,
    decoder: Box<dyn Read + Send>,
}

/// Reads lines of store files by place, keeping the last frame open: lines asked for in
/// storage order (job order, for a packed bundle) decompress each frame once.
#[derive(Default)]
pub struct LineReader {
    open: Option<OpenFrame>,
}

impl std::fmt::Debug for LineReader {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LineReader")
            .field("open", &self.open.as_ref().map(|o| (&o.file, o.frame)))
            .finish()
    }
}

impl LineReader {
    /// The `len` bytes at `line` of the content of the frame at byte `frame` of `file`. A
    /// file is opened without following links ([`crate::no_follow`]); `reopen` opens it again
    /// even when the frame is open (a loose file replaced by another process since).
    ///
    /// # Errors
    /// If the file cannot be opened or the frame does not decompress that far.
    pub fn read(
        &mut self,
        file: &Arc<PathBuf>,
        frame: u64,
        line: u64,
        len: u64,
        reopen: bool,
    ) -> io::Result<Vec<u8>> {
        if reopen
            && line == 0
            && let Some(content) = read_stored_member(file, frame, len)?
        {
            // A loose run as the store's appends write it: read whole, without a decoder.
            self.open = None;
            return Ok(content);
        }
        let reusable = !reopen
            && self.open.as_ref().is_some_and(|open| {
                open.file == *file && open.frame == frame && open.position <= line
            });
        if !reusable {
            self.open = None;
            let mut handle = crate::no_follow::open_regular(file)?;
            handle.seek(SeekFrom::Start(frame))?;
            let decoder = frame_decoder(BufReader::new(handle))?;
            self.open = Some(OpenFrame {
                file: Arc::clone(file),
                frame,
                position: 0,
                decoder,
            });
        }
        let open = self
            .open
            .as_mut()
            .ok_or_else(|| io::Error::other("no frame open"))?;
        let result = skip(&mut open.decoder, line - open.position)
            .and_then(|()| read_exactly(&mut open.decoder, len));
        match result {
            Ok(bytes) => {
                open.position = line + len;
                Ok(bytes)
            }
            Err(error) => {
                self.open = None;
                Err(error)
            }
        }
    }
}

/// The content of the frame at byte `frame` of `file` if it is a stored gzip member of a
/// `len`-byte content ([`crate::gzip::compress_stored`], one loose run): one read of exactly
/// that member's bytes, checked by [`crate::gzip::stored_member_content`] (CRC-32 and length
/// included). `None` if the bytes there are anything else (a member of an earlier version,
/// compressed; damage; a file too short), which the caller then decodes as a stream and
/// reports as it always did.
///
/// # Errors
/// If the file cannot be opened or positioned.
fn read_stored_member(file: &Path, frame: u64, len: u64) -> io::Result<Option<Vec<u8>>> {
    if len > MAX_LINE_BYTES {
        return Ok(None);
    }
    let Ok(size) = usize::try_from(crate::gzip::stored_member_len(len)) else {
        return Ok(None);
    };
    let mut handle = crate::no_follow::open_regular(file)?;
    handle.seek(SeekFrom::Start(frame))?;
    let mut member = vec![0; size];
    if handle.read_exact(&mut member).is_err() {
        return Ok(None);
    }
    Ok(crate::gzip::stored_member_content(&member).filter(|content| content.len() as u64 == len))
}

/// Writes lines into Zstandard frames (see the module docs), reporting where each line lands.
pub struct FrameWriter<W: Write> {
    out: W,
    compressor: zstd::bulk::Compressor<'static>,
    buffer: Vec<u8>,
    written: u64,
}

impl<W: Write> FrameWriter<W> {
    /// A writer of frames into `out`.
    ///
    /// # Errors
    /// If the compressor cannot be set up.
    pub fn new(out: W) -> io::Result<Self> {
        use zstd::zstd_safe::CParameter;
        let mut compressor = zstd::bulk::Compressor::new(LEVEL)?;
        for parameter in [
            CParameter::WindowLog(WINDOW_LOG),
            CParameter::ChecksumFlag(true),
            CParameter::ContentSizeFlag(true),
            CParameter::DictIdFlag(false),
        ] {
            compressor.set_parameter(parameter)?;
        }
        Ok(Self {
            out,
            compressor,
            buffer: Vec::new(),
            written: 0,
        })
    }

    /// Adds `line` (with its newline); returns the byte offset of its frame in the output and
    /// its offset in the frame's content.
    ///
    /// # Errors
    /// If a frame cannot be compressed or written.
    pub fn push(&mut self, line: &[u8]) -> io::Result<(u64, u64)> {
        if self.buffer.capacity() == 0 {
            // A frame's content at once: grown by doubling, it was copied and its pages faulted
            // in at every step (untouched, the room costs no memory for a small bundle).
            self.buffer.reserve(FRAME_CONTENT_BYTES + line.len());
        }
        let at = (self.written, self.buffer.len() as u64);
        self.buffer.extend_from_slice(line);
        if self.buffer.len() >= FRAME_CONTENT_BYTES {
            self.close_frame()?;
        }
        Ok(at)
    }

    fn close_frame(&mut self) -> io::Result<()> {
        if self.buffer.is_empty() {
            return Ok(());
        }
        let frame = self.compressor.compress(&self.buffer)?;
        self.out.write_all(&frame)?;
        self.written += frame.len() as u64;
        self.buffer.clear();
        Ok(())
    }

    /// Closes the last frame; returns the output and its length.
    ///
    /// # Errors
    /// If the last frame cannot be compressed or written.
    pub fn finish(mut self) -> io::Result<(W, u64)> {
        self.close_frame()?;
        Ok((self.out, self.written))
    }
}

/// `content` as the frames a bundle would hold (for tools and tests).
///
/// # Errors
/// If compression fails.
pub fn compress(content: &[u8]) -> io::Result<Vec<u8>> {
    let mut writer = FrameWriter::new(Vec::new())?;
    for line in content.split_inclusive(|&b| b == b'\n') {
        writer.push(line)?;
    }
    Ok(writer.finish()?.0)
}

/// The content of every frame of `bytes`, concatenated (what `zstdcat` prints), for tools and
/// tests; capped like [`read_frame`].
///
/// # Errors
/// If a frame is damaged or over a cap.
pub fn decompress(bytes: &[u8]) -> io::Result<Vec<u8>> {
    let mut rest = bytes;
    let mut content = Vec::new();
    while !rest.is_empty() {
        let mut take = |line: FrameLine| {
            content.extend(line.bytes.unwrap_or_default());
            ControlFlow::Continue(())
        };
        let len = read_frame(&mut rest, &mut take).map_err(io::Error::other)?;
        if len == 0 {
            break;
        }
    }
    Ok(content)
}

/// The file `path` as a `BufReader` positioned at `offset`, opened without following links.
pub(crate) fn reader_at(path: &std::path::Path, offset: u64) -> io::Result<BufReader<File>> {
    let mut file = crate::no_follow::open_regular(path)?;
    file.seek(SeekFrom::Start(offset))?;
    Ok(BufReader::new(file))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lines(frame: &[u8]) -> Result<(Vec<FrameLine>, u64), String> {
        let mut found = Vec::new();
        let mut reader = frame;
        let len = read_frame(&mut reader, &mut |line| {
            found.push(line);
            ControlFlow::Continue(())
        })?;
        Ok((found, len))
    }

    #[test]
    fn lines_round_trip_and_frames_close_past_the_content_size() {
        let text: Vec<u8> = (0..40_000)
            .flat_map(|i| {
                format!("{{\"run\":{i},\"x\":\"{}\"}}\n", "y".repeat(i % 200)).into_bytes()
            })
            .collect();
        let bytes = compress(&text).unwrap();
        assert_eq!(decompress(&bytes).unwrap(), text);
        // More than one frame, each starting with the magic, and every line where the writer
        // said it is.
        let mut writer = FrameWriter::new(Vec::new()).unwrap();
        let places: Vec<(u64, u64)> = text
            .split_inclusive(|&b| b == b'\n')
            .map(|line| writer.push(line).unwrap())
            .collect();
        let (written, len) = writer.finish().unwrap();
        assert_eq!(written, bytes);
        assert_eq!(len, bytes.len() as u64);
        let frames: std::collections::BTreeSet<u64> = places.iter().map(|&(f, _)| f).collect();
        assert!(frames.len() > 1, "{frames:?}");
        let mut reader = LineReader::default();
        let dir = tempfile::tempdir().unwrap();
        let path = Arc::new(dir.path().join("bundle"));
        std::fs::write(&*path, &bytes).unwrap();
        for (line, &(frame, offset)) in text
            .split_inclusive(|&b| b == b'\n')
            .zip(&places)
            .step_by(997)
        {
            let got = reader
                .read(&path, frame, offset, line.len() as u64, false)
                .unwrap();
            assert_eq!(got, line);
            let again = read_line_at(
                &bytes[usize::try_from(frame).unwrap()..],
                offset,
                line.len() as u64,
            )
            .unwrap();
            assert_eq!(again, line);
        }
        // A frame's length is what `read_frame` reports.
        let (found, first) = lines(&bytes).unwrap();
        assert_eq!(
            Codec::of(&bytes[usize::try_from(first).unwrap()..]),
            Some(Codec::Zstd)
        );
        assert_eq!(
            found[0].bytes.as_deref(),
            text.split_inclusive(|&b| b == b'\n').next()
        );
    }

    #[test]
    fn frame_bytes_are_pinned() {
        // The same bytes on every machine: a change of library version or parameters that
        // changes the output fails here, before it changes anyone's bundles.
        let text: Vec<u8> = (0..2000)
            .flat_map(|i| {
                format!(
                    "{{\"seed\":{i},\"steps\":[{},{},{}]}}\n",
                    i * 7 % 13,
                    i % 5,
                    i / 3
                )
                .into_bytes()
            })
            .collect();
        let bytes = compress(&text).unwrap();
        assert_eq!(
            blake3::hash(&bytes).to_hex().as_str(),
            "3fa805b8a8f8d090d00698228a139a73b121cd9b9cb5eec8eff31577d892f1b2",
            "{} bytes",
            bytes.len()
        );
    }

    #[test]
    fn gzip_members_are_frames_too_and_damage_is_named() {
        let member = crate::gzip::compress(b"one line\n").unwrap();
        let (found, len) = lines(&member).unwrap();
        assert_eq!((found.len(), len), (1, member.len() as u64));
        assert_eq!(found[0].bytes.as_deref(), Some(&b"one line\n"[..]));
        let cut = &member[..member.len() - 3];
        assert!(lines(cut).is_err());
        let no_newline = crate::gzip::compress(b"no newline").unwrap();
        assert!(
            lines(&no_newline)
                .unwrap_err()
                .contains("ends inside a line")
        );
        assert!(lines(b"junk").unwrap_err().contains("not the start"));
        let mut bytes = compress(b"a\nb\n").unwrap();
        let last = bytes.len() - 1;
        bytes[last] ^= 1; // the content checksum
        assert!(lines(&bytes).is_err());
    }

    /// Zeros that decompress to `size` bytes in one line without a newline: a bomb.
    fn bomb(size: usize) -> Vec<u8> {
        let mut encoder = zstd::stream::write::Encoder::new(Vec::new(), 1).unwrap();
        encoder.window_log(WINDOW_LOG).unwrap();
        let block = vec![b'0'; 1 << 20];
        for _ in 0..size >> 20 {
            encoder.write_all(&block).unwrap();
        }
        encoder.finish().unwrap()
    }

    #[test]
    fn a_bomb_is_refused_holding_at_most_the_held_line() {
        let bytes = bomb((MAX_LINE_BYTES as usize) + (1 << 20));
        assert!(bytes.len() < 1 << 20, "{}", bytes.len());
        let mut handed = 0;
        let mut reader = bytes.as_slice();
        let problem = read_frame(&mut reader, &mut |_| {
            handed += 1;
            ControlFlow::Continue(())
        })
        .unwrap_err();
        assert!(problem.contains("the cap of one entry"), "{problem}");
        assert_eq!(handed, 0);
        // A frame asking for a window above the cap is refused at once.
        let mut wide = zstd::stream::write::Encoder::new(Vec::new(), 3).unwrap();
        wide.window_log(WINDOW_LOG + 2).unwrap();
        wide.long_distance_matching(true).unwrap();
        wide.write_all(&vec![7_u8; 40 << 20]).unwrap();
        let wide = wide.finish().unwrap();
        let mut reader = wide.as_slice();
        let problem = read_frame(&mut reader, &mut |_| ControlFlow::Continue(())).unwrap_err();
        assert!(problem.contains("does not decompress"), "{problem}");
    }

    #[test]
    fn a_line_longer_than_the_held_size_is_handed_over_without_its_bytes() {
        let long = [vec![b'x'; HELD_LINE_BYTES + 10], b"\nshort\n".to_vec()].concat();
        let bytes = compress(&long).unwrap();
        // The long line fills its frame, which closes after it.
        let (mut found, first) = lines(&bytes).unwrap();
        found.extend(lines(&bytes[usize::try_from(first).unwrap()..]).unwrap().0);
        assert_eq!(found.len(), 2);
        assert!(found[0].bytes.is_none());
        assert_eq!(found[0].len, HELD_LINE_BYTES as u64 + 11);
        assert_eq!(found[0].digest, blake3::hash(&long[..HELD_LINE_BYTES + 11]));
        assert_eq!(found[1].bytes.as_deref(), Some(&b"short\n"[..]));
        let again = read_line_at(bytes.as_slice(), 0, found[0].len).unwrap();
        assert_eq!(blake3::hash(&again), found[0].digest);
    }
}
