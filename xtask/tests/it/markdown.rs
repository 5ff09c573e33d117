//! The Markdown check of `README.md` and `docs/*.md`, run by `cargo test -p xtask`: every fenced
//! code block is closed and names its language, no fence line hides inside a code block (the
//! mark of a block left open that a later fence "closes"), and every relative link or image
//! points at a file that exists. Parsing is pulldown-cmark's (`CommonMark`).

use std::ops::Range;
use std::path::Path;

use pulldown_cmark::{CodeBlockKind, Event, Parser, Tag};

/// One problem at one line of a Markdown file.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Problem {
    /// 1-based line.
    line: usize,
    what: String,
}

fn line_of(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())].matches('\n').count() + 1
}

/// The opening fence of a fenced block's source: its character (`` ` `` or `~`) and length.
fn fence(line: &str) -> Option<(char, usize)> {
    let trimmed = line.trim_start();
    let first = trimmed.chars().next()?;
    if first != '`' && first != '~' {
        return None;
    }
    let count = trimmed.chars().take_while(|&c| c == first).count();
    (count >= 3).then_some((first, count))
}

/// Every problem in `text`; `exists` says whether a relative link target (relative to the
/// Markdown file's folder, anchor removed) exists.
fn check(text: &str, exists: &dyn Fn(&str) -> bool) -> Vec<Problem> {
    let mut problems = Vec::new();
    for (event, range) in Parser::new(text).into_offset_iter() {
        match event {
            Event::Start(Tag::CodeBlock(CodeBlockKind::Fenced(info))) => {
                check_code_block(text, range, &info, &mut problems);
            }
            Event::Start(Tag::Link { dest_url, .. } | Tag::Image { dest_url, .. }) => {
                let target = dest_url.split('#').next().unwrap_or_default();
                let external = dest_url.contains("://") || dest_url.starts_with("mailto:");
                if !external && !target.is_empty() && !exists(target) {
                    problems.push(Problem {
                        line: line_of(text, range.start),
                        what: format!("the link target `{dest_url}` does not exist"),
                    });
                }
            }
            _ => {}
        }
    }
    problems
}

fn check_code_block(text: &str, range: Range<usize>, info: &str, problems: &mut Vec<Problem>) {
    let source = &text[range.clone()];
    let line = line_of(text, range.start);
    let lines: Vec<&str> = source.trim_end().lines().collect();
    let Some((mark, length)) = lines.first().and_then(|l| fence(l)) else {
        return;
    };
    if info.trim().is_empty() {
        problems.push(Problem {
            line,
            what: "a code block without a language (write ```sh, ```text, ```rust, …; rustdoc \
                   runs an unnamed block as Rust)"
                .to_owned(),
        });
    }
    let closed = lines.len() >= 2
        && lines.last().is_some_and(|last| {
            let last = last.trim();
            last.chars().all(|c| c == mark) && last.len() >= length
        });
    if !closed {
        problems.push(Problem {
            line,
            what: "a code block that is never closed".to_owned(),
        });
    }
    let body = if closed {
        &lines[1..lines.len() - 1]
    } else {
        &lines[1..]
    };
    for (index, inner) in body.iter().enumerate() {
        if fence(inner).is_some_and(|(c, n)| c == mark && n >= length) {
            problems.push(Problem {
                line: line + 1 + index,
                what: format!(
                    "a fence line inside the code block opened at line {line}: a block above \
                     is left open"
                ),
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn workspace_root() -> std::path::PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .parent()
            .expect("xtask sits in the workspace root")
            .to_path_buf()
    }

    #[test]
    fn readme_and_docs_are_well_formed_markdown() {
        let root = workspace_root();
        let mut files = vec![root.join("README.md")];
        let mut docs: Vec<_> = std::fs::read_dir(root.join("docs"))
            .expect("docs/ is readable")
            .flatten()
            .map(|entry| entry.path())
            .filter(|path| path.extension().is_some_and(|e| e == "md"))
            .collect();
        docs.sort();
        files.extend(docs);
        assert!(files.len() >= 3, "README.md and docs/*.md: {files:?}");
        let mut report = String::new();
        for file in &files {
            let text = std::fs::read_to_string(file).expect("a Markdown file is UTF-8");
            let folder = file.parent().expect("a file has a folder");
            for problem in check(&text, &|target| folder.join(target).exists()) {
                report.push_str(&format!(
                    "{}:{}: {}\n",
                    file.strip_prefix(&root).unwrap_or(file).display(),
                    problem.line,
                    problem.what
                ));
            }
        }
        assert!(report.is_empty(), "Markdown problems:\n{report}");
    }

    #[test]
    fn an_unclosed_block_and_the_fence_it_swallows_are_found() {
        // The shape of the old README's fuzzing section: a block left open, a heading, and a
        // later block whose opening fence then reads as code.
        let text = "# A\n\n```sh\ncargo fuzz\n\n## Python\n\n```sh\npip install .\n```\n\nend\n";
        let problems = check(text, &|_| true);
        let what: Vec<(usize, &str)> = problems.iter().map(|p| (p.line, p.what.as_str())).collect();
        assert_eq!(what.len(), 1, "{problems:?}");
        assert_eq!(what[0].0, 8);
        assert!(
            what[0]
                .1
                .starts_with("a fence line inside the code block opened at line 3")
        );
        let open = check("text\n\n```rust\nfn main() {}\n", &|_| true);
        assert_eq!(open.len(), 1);
        assert_eq!(open[0].what, "a code block that is never closed");
        assert_eq!(open[0].line, 3);
    }

    #[test]
    fn a_block_without_a_language_and_a_dead_link_are_found() {
        let text = "[arch](docs/ARCH.md) [web](https://example.org/x.md) [here](#top)\n\n```\nx\n```\n\n~~~~text\n```\n~~~~\n";
        let problems = check(text, &|target| target != "docs/ARCH.md");
        let what: Vec<&str> = problems.iter().map(|p| p.what.as_str()).collect();
        assert_eq!(what.len(), 2, "{problems:?}");
        assert_eq!(what[0], "the link target `docs/ARCH.md` does not exist");
        assert!(what[1].starts_with("a code block without a language"));
        assert!(check("fine\n\n```text\nok\n```\n", &|_| false).is_empty());
    }
}
