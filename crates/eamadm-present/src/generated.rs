//! Generated text and the committed files it goes into (the README's and `docs/outputs.md`'s
//! generated blocks, `fixtures/`): [`splice`] puts a generated block between its marker lines,
//! and [`first_difference`] gives a short, readable account of how two texts differ (the first
//! differing line with a few lines of context, marked `-` expected and `+` actual), enough to
//! review a fixture change without a diff library.

use std::fmt::Write as _;

/// Lines of context shown around the first difference.
const CONTEXT: usize = 3;
/// Differing lines shown at most.
const SHOWN: usize = 8;

/// `None` when `expected == actual`; otherwise the first differing line (1-based) and a short
/// diff around it (`xtask regen-fixtures --check` shows it for a generated file that is out of
/// date).
#[must_use]
pub fn first_difference(expected: &str, actual: &str) -> Option<String> {
    if expected == actual {
        return None;
    }
    let old: Vec<&str> = expected.lines().collect();
    let new: Vec<&str> = actual.lines().collect();
    let first = old
        .iter()
        .zip(&new)
        .position(|(a, b)| a != b)
        .unwrap_or(old.len().min(new.len()));
    let mut text = String::new();
    let _ = writeln!(
        text,
        "first difference at line {} ({} lines expected, {} found):",
        first + 1,
        old.len(),
        new.len()
    );
    for line in &old[first.saturating_sub(CONTEXT)..first] {
        let _ = writeln!(text, "  {line}");
    }
    // The changed region ends where the common tail begins.
    let common_tail = old[first..]
        .iter()
        .rev()
        .zip(new[first..].iter().rev())
        .take_while(|(a, b)| a == b)
        .count();
    let end_old = (old.len() - common_tail).min(first + SHOWN);
    let end_new = (new.len() - common_tail).min(first + SHOWN);
    for line in &old[first..end_old] {
        let _ = writeln!(text, "- {line}");
    }
    for line in &new[first..end_new] {
        let _ = writeln!(text, "+ {line}");
    }
    if old.len() == new.len() && first == old.len() {
        let _ = writeln!(
            text,
            "(the texts differ only in line endings or a final newline)"
        );
    }
    Some(text)
}

/// `text` with the lines between `<!-- generated:NAME … -->` and `<!-- /generated:NAME -->`
/// replaced by `content` (the marker lines stay).
///
/// # Errors
/// A message naming the marker line the text lacks (`README.md lacks …`).
pub fn splice(text: &str, name: &str, content: &str) -> Result<String, String> {
    let open = format!("<!-- generated:{name}");
    let close = format!("<!-- /generated:{name} -->");
    let missing = |marker: &str| {
        format!(
            "README.md lacks the marker line `{marker}`; put the generated part back between `{open} -->` and `{close}`"
        )
    };
    let start = text.find(&open).ok_or_else(|| missing(&open))?;
    let body = start + text[start..].find('\n').ok_or_else(|| missing(&open))? + 1;
    let end = body + text[body..].find(&close).ok_or_else(|| missing(&close))?;
    let mut out = String::with_capacity(text.len() + content.len());
    out.push_str(&text[..body]);
    out.push_str(content.trim_end());
    out.push('\n');
    out.push_str(&text[end..]);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_texts_have_no_difference() {
        assert_eq!(first_difference("a\nb\n", "a\nb\n"), None);
    }

    #[test]
    fn the_first_differing_line_is_shown_with_context() {
        let diff = first_difference("1\n2\n3\n4\n5\n", "1\n2\n3\nX\n5\n").unwrap();
        insta::assert_snapshot!(diff, @r"
        first difference at line 4 (5 lines expected, 5 found):
          1
          2
          3
        - 4
        + X
        ");
    }

    #[test]
    fn a_missing_tail_or_newline_is_reported() {
        let diff = first_difference("a\nb\n", "a\n").unwrap();
        assert!(diff.starts_with("first difference at line 2"), "{diff}");
        assert!(diff.contains("- b"), "{diff}");
        let diff = first_difference("a\n", "a").unwrap();
        assert!(diff.contains("line endings or a final newline"), "{diff}");
    }

    #[test]
    fn splice_replaces_only_between_the_markers_and_names_a_missing_one() {
        let text = "a\n<!-- generated:x: do not edit -->\nold\nlines\n<!-- /generated:x -->\nb\n";
        assert_eq!(
            splice(text, "x", "new\n").unwrap(),
            "a\n<!-- generated:x: do not edit -->\nnew\n<!-- /generated:x -->\nb\n"
        );
        let error = splice("a\n", "x", "new").unwrap_err();
        assert!(error.contains("`<!-- generated:x`"), "{error}");
        let error = splice("<!-- generated:x -->\nold\n", "x", "new").unwrap_err();
        assert!(error.contains("`<!-- /generated:x -->`"), "{error}");
    }
}
