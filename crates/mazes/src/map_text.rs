//! The plain-text map format: parsing (with line and column in every error) and its inverse.
//!
//! One character per tile, one line per row, top row first: `.` free, `#` obstacle, `S`
//! the start, `T` the target (both free tiles). Lines whose first character is `;` are
//! comments and are skipped wherever they appear. Lines end in `\n` (a `\r` before it is
//! tolerated); the final newline is optional when parsing. [`Maze::to_text`] writes the
//! canonical form: `\n` after every row (so a final newline), no comments.

use thiserror::Error;

use crate::geometry::Pos;
use crate::maze::{MAX_TILES, Maze};

/// A free tile.
pub const FREE: char = '.';
/// An obstacle tile.
pub const OBSTACLE: char = '#';
/// The start tile (free).
pub const START: char = 'S';
/// The target tile (free).
pub const TARGET: char = 'T';
/// A line starting with this character is a comment.
pub const COMMENT: char = ';';

/// The two markers every map holds exactly once.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Marker {
    /// The start, `S`.
    Start,
    /// The target, `T`.
    Target,
}

impl std::fmt::Display for Marker {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Start => "start `S`",
            Self::Target => "target `T`",
        })
    }
}

/// Why a text map was rejected. Lines and columns are 1-based and count every line of
/// the text (comments included) and every character (not byte) of a line.
#[derive(Clone, Debug, PartialEq, Eq, Error)]
#[non_exhaustive]
pub enum ParseError {
    /// The text holds no map row (it is empty or only comments).
    #[error("empty map: the text has no rows (only comments or nothing at all)")]
    EmptyMap,
    /// A line inside the map is empty.
    #[error("line {line}: empty row; every row needs at least one tile (remove blank lines)")]
    EmptyRow {
        /// The blank line.
        line: usize,
    },
    /// A character that is not `.`, `#`, `S` or `T`.
    #[error(
        "line {line}, column {column}: unknown character {found:?}; \
         expected `.` (free), `#` (obstacle), `S` (start) or `T` (target)"
    )]
    UnknownCharacter {
        /// Line of the character.
        line: usize,
        /// Column of the character.
        column: usize,
        /// The character found.
        found: char,
    },
    /// A row whose length differs from the first row's.
    #[error(
        "line {line}, column {column}: ragged row of {found} tiles; the first row \
         (line {first_line}) has {expected}"
    )]
    RaggedRow {
        /// Line of the ragged row.
        line: usize,
        /// First column where the row disagrees with the first row: one past the shorter.
        column: usize,
        /// Tiles in this row.
        found: usize,
        /// Tiles in the first row.
        expected: usize,
        /// Line of the first row.
        first_line: usize,
    },
    /// The map would have more than [`MAX_TILES`] tiles.
    #[error("line {line}: the map grows beyond the {MAX_TILES} tiles allowed")]
    TooLarge {
        /// Line at which the limit was passed.
        line: usize,
    },
    /// No `S` or no `T`.
    #[error("the map has no {marker}; it needs exactly one")]
    MissingMarker {
        /// Which marker is missing.
        marker: Marker,
    },
    /// A second `S` or `T`.
    #[error(
        "line {line}, column {column}: a second {marker} (the first is at line {first_line}, \
         column {first_column}); a map has exactly one"
    )]
    RepeatedMarker {
        /// Which marker is repeated.
        marker: Marker,
        /// Line of the repeat.
        line: usize,
        /// Column of the repeat.
        column: usize,
        /// Line of the first occurrence.
        first_line: usize,
        /// Column of the first occurrence.
        first_column: usize,
    },
    /// No path of free tiles leads from `S` to `T`.
    #[error(
        "line {line}, column {column}: the target `T` cannot be reached from the start `S` \
         at line {start_line}, column {start_column} (moves are up/down/left/right over \
         non-`#` tiles)"
    )]
    UnreachableTarget {
        /// Line of `T`.
        line: usize,
        /// Column of `T`.
        column: usize,
        /// Line of `S`.
        start_line: usize,
        /// Column of `S`.
        start_column: usize,
    },
}

/// Where a marker was seen: its tile and its (line, column) in the text.
#[derive(Clone, Copy)]
struct Seen {
    pos: Pos,
    line: usize,
    column: usize,
}

impl Maze {
    /// Parses a text map (format in the crate docs and the [module docs](crate::map_text)).
    ///
    /// # Errors
    ///
    /// A [`ParseError`] with the line and column of the first problem: unknown
    /// character, ragged or empty row, empty map, missing or repeated `S`/`T`, a map
    /// beyond [`MAX_TILES`] tiles, or an unreachable target.
    pub fn parse(text: &str) -> Result<Self, ParseError> {
        let mut obstacle: Vec<bool> = Vec::new();
        // (width, line of the first row)
        let mut first_row: Option<(usize, usize)> = None;
        let mut height = 0;
        let mut start: Option<Seen> = None;
        let mut target: Option<Seen> = None;

        for (index, raw) in text.split_inclusive('\n').enumerate() {
            let line = index + 1;
            let row = raw.strip_suffix('\n').unwrap_or(raw);
            let row = row.strip_suffix('\r').unwrap_or(row);
            if row.starts_with(COMMENT) {
                continue;
            }
            if row.is_empty() {
                return Err(ParseError::EmptyRow { line });
            }
            let mut found = 0;
            for (offset, character) in row.chars().enumerate() {
                let column = offset + 1;
                if let Some((expected, first_line)) = first_row
                    && offset >= expected
                {
                    return Err(ParseError::RaggedRow {
                        line,
                        column,
                        found: row.chars().count(),
                        expected,
                        first_line,
                    });
                }
                if obstacle.len() >= MAX_TILES {
                    return Err(ParseError::TooLarge { line });
                }
                let here = Seen {
                    pos: Pos::new(offset, height),
                    line,
                    column,
                };
                let blocked = match character {
                    FREE => false,
                    OBSTACLE => true,
                    START => {
                        record_marker(&mut start, Marker::Start, here)?;
                        false
                    }
                    TARGET => {
                        record_marker(&mut target, Marker::Target, here)?;
                        false
                    }
                    found => {
                        return Err(ParseError::UnknownCharacter {
                            line,
                            column,
                            found,
                        });
                    }
                };
                obstacle.push(blocked);
                found += 1;
            }
            match first_row {
                None => first_row = Some((found, line)),
                Some((expected, first_line)) if found < expected => {
                    return Err(ParseError::RaggedRow {
                        line,
                        column: found + 1,
                        found,
                        expected,
                        first_line,
                    });
                }
                Some(_) => {}
            }
            height += 1;
        }

        let Some((width, _)) = first_row else {
            return Err(ParseError::EmptyMap);
        };
        let start = start.ok_or(ParseError::MissingMarker {
            marker: Marker::Start,
        })?;
        let target = target.ok_or(ParseError::MissingMarker {
            marker: Marker::Target,
        })?;
        let maze = Self::from_parts_unchecked(width, height, obstacle, start.pos, target.pos);
        if maze.target_reachable() {
            Ok(maze)
        } else {
            Err(ParseError::UnreachableTarget {
                line: target.line,
                column: target.column,
                start_line: start.line,
                start_column: start.column,
            })
        }
    }
}

fn record_marker(slot: &mut Option<Seen>, marker: Marker, here: Seen) -> Result<(), ParseError> {
    match slot {
        Some(first) => Err(ParseError::RepeatedMarker {
            marker,
            line: here.line,
            column: here.column,
            first_line: first.line,
            first_column: first.column,
        }),
        None => {
            *slot = Some(here);
            Ok(())
        }
    }
}
