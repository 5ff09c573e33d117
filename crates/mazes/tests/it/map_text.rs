//! The text map format: round trips and every parse error.

use crate::common;

use mazes::{Marker, Maze, ParseError, Pos};
use proptest::prelude::*;

proptest! {
    /// parse ∘ format is the identity on mazes.
    #[test]
    fn parse_inverts_format(maze in common::small_maze(9)) {
        let text = maze.to_text();
        prop_assert_eq!(Maze::parse(&text).unwrap(), maze);
    }

    /// format ∘ parse is the identity on canonical texts (those `to_text` writes).
    #[test]
    fn format_inverts_parse_on_canonical_text(maze in common::small_maze(9)) {
        let text = maze.to_text();
        prop_assert_eq!(Maze::parse(&text).unwrap().to_text(), text);
    }

    /// Comments, CRLF line ends and a missing final newline do not change the maze.
    #[test]
    fn tolerated_variations_parse_to_the_same_maze(
        maze in common::small_maze(9),
        comment_after in 0usize..10,
    ) {
        let text = maze.to_text();
        let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
        lines.insert(comment_after.min(lines.len()), "; a comment: S T # ? anything".to_owned());
        let crlf = lines.join("\r\n");
        prop_assert_eq!(Maze::parse(&crlf).unwrap(), maze.clone());
        let no_final_newline = text.trim_end_matches('\n');
        prop_assert_eq!(Maze::parse(no_final_newline).unwrap(), maze);
    }

    /// Arbitrary text never panics the parser.
    #[test]
    fn parse_never_panics(text in "[.#ST;\\n\\rx ]{0,80}") {
        let _ = Maze::parse(&text);
    }
}

#[test]
fn serde_uses_the_map_text() {
    let maze = Maze::parse("S.\n#T\n").unwrap();
    let json = serde_json::to_string(&maze).unwrap();
    assert_eq!(json, r#""S.\n#T\n""#);
    assert_eq!(serde_json::from_str::<Maze>(&json).unwrap(), maze);
    let invalid = serde_json::from_str::<Maze>(r#""S.\n##\n.T\n""#).unwrap_err();
    assert!(
        invalid.to_string().contains("cannot be reached"),
        "{invalid}"
    );
}

#[test]
fn parse_reads_the_layout() {
    let maze = Maze::parse("; header\nS.#\n.#.\n..T").unwrap();
    assert_eq!((maze.width(), maze.height()), (3, 3));
    assert_eq!(maze.start(), Pos::new(0, 0));
    assert_eq!(maze.target(), Pos::new(2, 2));
    assert_eq!(
        maze.obstacles().collect::<Vec<_>>(),
        vec![Pos::new(2, 0), Pos::new(1, 1)]
    );
    assert_eq!(maze.to_text(), "S.#\n.#.\n..T\n");
}

fn error(text: &str) -> ParseError {
    Maze::parse(text).expect_err("the text is invalid")
}

#[test]
fn empty_map() {
    assert_eq!(error(""), ParseError::EmptyMap);
    assert_eq!(error("; only a comment\n;another\n"), ParseError::EmptyMap);
}

#[test]
fn empty_row() {
    assert_eq!(error("\n"), ParseError::EmptyRow { line: 1 });
    assert_eq!(error("S.\n\n.T\n"), ParseError::EmptyRow { line: 2 });
    assert_eq!(error("S.\n.T\n\n"), ParseError::EmptyRow { line: 3 });
}

#[test]
fn unknown_character() {
    assert_eq!(
        error("S..\n.x.\n..T\n"),
        ParseError::UnknownCharacter {
            line: 2,
            column: 2,
            found: 'x'
        }
    );
    // Columns count characters, not bytes.
    assert_eq!(
        error("; é\nS.é\n"),
        ParseError::UnknownCharacter {
            line: 2,
            column: 3,
            found: 'é'
        }
    );
    assert_eq!(
        error("S T\n"),
        ParseError::UnknownCharacter {
            line: 1,
            column: 2,
            found: ' '
        }
    );
}

#[test]
fn ragged_rows() {
    assert_eq!(
        error("S..\n..\n..T\n"),
        ParseError::RaggedRow {
            line: 2,
            column: 3,
            found: 2,
            expected: 3,
            first_line: 1
        }
    );
    assert_eq!(
        error(";c\nS..\n....\n..T\n"),
        ParseError::RaggedRow {
            line: 3,
            column: 4,
            found: 4,
            expected: 3,
            first_line: 2
        }
    );
}

#[test]
fn missing_markers() {
    assert_eq!(
        error("...\n..T\n"),
        ParseError::MissingMarker {
            marker: Marker::Start
        }
    );
    assert_eq!(
        error("S..\n...\n"),
        ParseError::MissingMarker {
            marker: Marker::Target
        }
    );
}

#[test]
fn repeated_markers() {
    assert_eq!(
        error("S.S\n..T\n"),
        ParseError::RepeatedMarker {
            marker: Marker::Start,
            line: 1,
            column: 3,
            first_line: 1,
            first_column: 1
        }
    );
    assert_eq!(
        error("S.T\n;x\nT..\n"),
        ParseError::RepeatedMarker {
            marker: Marker::Target,
            line: 3,
            column: 1,
            first_line: 1,
            first_column: 3
        }
    );
}

#[test]
fn unreachable_target() {
    assert_eq!(
        error("S#.\n##.\n..T\n"),
        ParseError::UnreachableTarget {
            line: 3,
            column: 3,
            start_line: 1,
            start_column: 1
        }
    );
}

#[test]
fn too_large() {
    let side = 4097; // 4097² > MAX_TILES = 4096²
    let mut text = String::with_capacity((side + 1) * side);
    for y in 0..side {
        for x in 0..side {
            text.push(match (x, y) {
                (0, 0) => 'S',
                (1, 0) => 'T',
                _ => '.',
            });
        }
        text.push('\n');
    }
    assert_eq!(error(&text), ParseError::TooLarge { line: 4096 });
}

/// Every message names the place and the problem; pinned so they stay readable.
#[test]
fn error_messages() {
    let cases = [
        "",
        "S.\n\n.T\n",
        "S..\n.x.\n..T\n",
        "S..\n..\n..T\n",
        "S..\n....\n..T\n",
        "...\n..T\n",
        "S..\n...\n",
        "S.S\n..T\n",
        "S.T\n;x\nT..\n",
        "S#.\n##.\n..T\n",
    ];
    let messages: Vec<String> = cases
        .iter()
        .map(|text| format!("{text:?}\n  -> {}", error(text)))
        .collect();
    insta::assert_snapshot!(messages.join("\n"));
}
