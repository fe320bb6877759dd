//! Every relative link in the documentation resolves: README.md, BENCHMARKS.md,
//! shaders/README.md and every Markdown file under docs/. A link names a file or folder of the
//! repository (relative to the page), and a `#fragment` names a heading of the page it points
//! to. Links to other sites (`https:`, `mailto:`, ...) are not checked.

use std::collections::HashSet;
use std::path::{Component, Path, PathBuf};

/// One link of a page: where it points and the line it is on.
#[derive(Debug, PartialEq)]
struct Link {
    line: usize,
    target: String,
}

/// The links of a Markdown page: inline links and images `[text](target)`, `![alt](target)`,
/// and reference definitions `[id]: target`. Fenced code blocks and code spans are skipped.
fn links(markdown: &str) -> Vec<Link> {
    let mut found = Vec::new();
    let mut fence: Option<&str> = None;
    for (index, line) in markdown.lines().enumerate() {
        let trimmed = line.trim_start();
        if let Some(open) = fence {
            if trimmed.starts_with(open) {
                fence = None;
            }
            continue;
        }
        if trimmed.starts_with("```") || trimmed.starts_with("~~~") {
            fence = Some(&trimmed[..3]);
            continue;
        }
        let line_number = index + 1;
        if let Some(target) = reference_definition(trimmed) {
            found.push(Link {
                line: line_number,
                target,
            });
            continue;
        }
        let text = without_code_spans(line);
        let mut rest = text.as_str();
        while let Some(at) = rest.find("](") {
            let after = &rest[at + 2..];
            let Some(end) = closing_paren(after) else {
                break;
            };
            found.push(Link {
                line: line_number,
                target: destination(&after[..end]),
            });
            rest = &after[end..];
        }
    }
    found
}

/// `[id]: target` at the start of a line.
fn reference_definition(line: &str) -> Option<String> {
    let rest = line.strip_prefix('[')?;
    let (label, after) = rest.split_once("]:")?;
    if label.is_empty() || label.contains('[') {
        return None;
    }
    Some(destination(after))
}

/// The line with every `code span` blanked out.
fn without_code_spans(line: &str) -> String {
    let mut out = String::with_capacity(line.len());
    let mut in_code = false;
    for c in line.chars() {
        if c == '`' {
            in_code = !in_code;
            out.push(' ');
        } else {
            out.push(if in_code { ' ' } else { c });
        }
    }
    out
}

/// Where the `)` closing a link destination is, counting nested parentheses.
fn closing_paren(text: &str) -> Option<usize> {
    let mut depth = 0usize;
    for (at, c) in text.char_indices() {
        match c {
            '(' => depth += 1,
            ')' if depth == 0 => return Some(at),
            ')' => depth -= 1,
            _ => {}
        }
    }
    None
}

/// A link's destination without its title or angle brackets.
fn destination(raw: &str) -> String {
    let raw = raw.trim();
    if let Some(inner) = raw.strip_prefix('<') {
        return inner.split('>').next().unwrap_or("").to_owned();
    }
    raw.split_whitespace().next().unwrap_or("").to_owned()
}

/// True for a link to another site or protocol (`https:`, `mailto:`, ...).
fn is_external(target: &str) -> bool {
    match target.find(':') {
        Some(colon) => {
            let scheme = &target[..colon];
            !scheme.is_empty()
                && !scheme.contains(['/', '#', '.'])
                && scheme
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || "+-".contains(c))
        }
        None => false,
    }
}

/// The anchors GitHub gives a page's headings: lower case, punctuation other than `-` and `_`
/// dropped, spaces as `-`; a repeated anchor gets `-1`, `-2`, ...
fn anchors(markdown: &str) -> HashSet<String> {
    let mut seen = HashSet::new();
    let mut fence = false;
    for line in markdown.lines() {
        let trimmed = line.trim_start();
        if trimmed.starts_with("```") || trimmed.starts_with("~~~") {
            fence = !fence;
            continue;
        }
        if fence || !trimmed.starts_with('#') {
            continue;
        }
        let title = trimmed.trim_start_matches('#');
        if !title.starts_with(' ') {
            continue;
        }
        let slug: String = title
            .trim()
            .to_lowercase()
            .chars()
            .filter_map(|c| match c {
                ' ' => Some('-'),
                c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
                _ => None,
            })
            .collect();
        let mut anchor = slug.clone();
        let mut n = 0;
        while seen.contains(&anchor) {
            n += 1;
            anchor = format!("{slug}-{n}");
        }
        seen.insert(anchor);
    }
    seen
}

/// `%20` and the other percent escapes of a link's path, decoded.
fn percent_decoded(path: &str) -> String {
    let bytes = path.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = bytes
            .get(i + 1..i + 3)
            .and_then(|h| std::str::from_utf8(h).ok())
            .and_then(|h| u8::from_str_radix(h, 16).ok());
        match (bytes[i], hex) {
            (b'%', Some(byte)) => {
                out.push(byte);
                i += 3;
            }
            (byte, _) => {
                out.push(byte);
                i += 1;
            }
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// `path` with `.` and `..` folded; `None` when `..` climbs above the start.
fn normalized(path: &Path) -> Option<PathBuf> {
    let mut out = PathBuf::new();
    for part in path.components() {
        match part {
            Component::CurDir => {}
            Component::ParentDir => {
                if !out.pop() {
                    return None;
                }
            }
            Component::Normal(name) => out.push(name),
            Component::RootDir | Component::Prefix(_) => return None,
        }
    }
    Some(out)
}

/// What is wrong with each relative link of `page` (a path relative to `root`), one line each.
fn broken_links(root: &Path, page: &Path, markdown: &str) -> Vec<String> {
    let mut broken = Vec::new();
    let folder = page.parent().unwrap_or(Path::new(""));
    for link in links(markdown) {
        let target = link.target.as_str();
        if target.is_empty() {
            broken.push(format!("{}:{}: empty link", page.display(), link.line));
            continue;
        }
        if is_external(target) {
            continue;
        }
        let (path, fragment) = match target.split_once('#') {
            Some((path, fragment)) => (path, Some(fragment)),
            None => (target, None),
        };
        let file = if path.is_empty() {
            Some(page.to_path_buf())
        } else {
            normalized(&folder.join(percent_decoded(path)))
        };
        let Some(file) = file else {
            broken.push(format!(
                "{}:{}: {target} leaves the repository",
                page.display(),
                link.line
            ));
            continue;
        };
        let on_disk = root.join(&file);
        if !on_disk.exists() {
            broken.push(format!(
                "{}:{}: {target}: no file {}",
                page.display(),
                link.line,
                file.display()
            ));
            continue;
        }
        let Some(fragment) = fragment else {
            continue;
        };
        let is_markdown = on_disk.extension().is_some_and(|e| e == "md");
        if !is_markdown {
            continue;
        }
        let text = std::fs::read_to_string(&on_disk).unwrap_or_default();
        if !anchors(&text).contains(fragment) {
            broken.push(format!(
                "{}:{}: {target}: {} has no heading #{fragment}",
                page.display(),
                link.line,
                file.display()
            ));
        }
    }
    broken
}

/// The pages checked, relative to the repository root.
fn pages(root: &Path) -> Vec<PathBuf> {
    let mut pages: Vec<PathBuf> = ["README.md", "BENCHMARKS.md", "shaders/README.md"]
        .iter()
        .map(PathBuf::from)
        .filter(|p| root.join(p).exists())
        .collect();
    let mut folders = vec![PathBuf::from("docs")];
    while let Some(folder) = folders.pop() {
        let Ok(entries) = std::fs::read_dir(root.join(&folder)) else {
            continue;
        };
        for entry in entries.flatten() {
            let path = folder.join(entry.file_name());
            if entry.file_type().is_ok_and(|t| t.is_dir()) {
                folders.push(path);
            } else if path.extension().is_some_and(|e| e == "md") {
                pages.push(path);
            }
        }
    }
    pages.sort();
    pages
}

#[test]
fn every_relative_link_in_the_docs_resolves() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let pages = pages(root);
    assert!(pages.contains(&PathBuf::from("README.md")), "{pages:?}");
    assert!(pages.len() > 3, "docs/ holds pages: {pages:?}");
    let mut broken = Vec::new();
    let mut checked = 0;
    for page in &pages {
        let text = std::fs::read_to_string(root.join(page)).unwrap();
        checked += links(&text).len();
        broken.extend(broken_links(root, page, &text));
    }
    assert!(
        checked > 20,
        "only {checked} links found: is the extractor reading them?"
    );
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

const SAMPLE: &str = "\
# A page

See [the guide](docs/guide.md), ![a picture](pics/a.png \"title\") and
[a section](#a-page) or [elsewhere](https://example.com/x.md).

```sh
cat [not a link](nowhere.md)
```

Code: `[not a link](nowhere.md)`; [nested (parens)](notes_(1).md).

[ref]: <other file.md>

## Two words, and punctuation!
";

#[test]
fn the_extractor_finds_links_and_skips_code() {
    let targets: Vec<(usize, String)> = links(SAMPLE)
        .into_iter()
        .map(|l| (l.line, l.target))
        .collect();
    let expected = [
        (3, "docs/guide.md"),
        (3, "pics/a.png"),
        (4, "#a-page"),
        (4, "https://example.com/x.md"),
        (10, "notes_(1).md"),
        (12, "other file.md"),
    ];
    let expected: Vec<(usize, String)> = expected
        .iter()
        .map(|(line, target)| (*line, target.to_string()))
        .collect();
    assert_eq!(targets, expected);
}

#[test]
fn anchors_follow_github() {
    let found = anchors(SAMPLE);
    assert!(found.contains("a-page"), "{found:?}");
    assert!(found.contains("two-words-and-punctuation"), "{found:?}");
    let repeated = anchors("# Notes\n## Notes\n");
    assert!(repeated.contains("notes") && repeated.contains("notes-1"));
}

#[test]
fn a_broken_sample_is_caught() {
    let root = std::env::temp_dir().join(format!("chiaro-doc-links-{}", std::process::id()));
    std::fs::create_dir_all(root.join("docs")).unwrap();
    std::fs::write(root.join("docs/guide.md"), "# Guide\n\n## Install\n").unwrap();
    std::fs::write(root.join("README.md"), "# Readme\n").unwrap();
    let page = Path::new("README.md");
    let good = "[g](docs/guide.md) [i](docs/guide.md#install) [top](#readme) [w](https://x.y)";
    assert_eq!(broken_links(&root, page, good), Vec::<String>::new());
    let bad =
        "[a](docs/missing.md)\n[b](docs/guide.md#setup)\n[c](../../outside.md)\n[d](#nowhere)";
    let broken = broken_links(&root, page, bad);
    assert_eq!(broken.len(), 4, "{broken:#?}");
    assert!(broken[0].contains("README.md:1: docs/missing.md: no file"));
    assert!(broken[1].contains("has no heading #setup"));
    assert!(broken[2].contains("leaves the repository"));
    assert!(broken[3].contains("has no heading #nowhere"));
    std::fs::remove_dir_all(&root).unwrap();
}
