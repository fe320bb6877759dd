//! docs/cli.md holds, between two markers, the `--help` of `chiaro` and of each of its commands,
//! as the built binary prints them. This test prints them again and compares, so the page
//! cannot drift from the command line. When they differ, regenerate the page with
//! `CHIARO_BLESS=1 cargo test --test cli_doc`.

use std::path::Path;
use std::process::Command;

const BEGIN: &str =
    "<!-- BEGIN GENERATED from `chiaro --help`: CHIARO_BLESS=1 cargo test --test cli_doc -->";
const END: &str = "<!-- END GENERATED -->";
const BLESS: &str = "CHIARO_BLESS=1 cargo test --test cli_doc";

/// What the built binary prints for `args`, without colour.
fn help(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_chiaro"))
        .args(args)
        .env("NO_COLOR", "1")
        .env_remove("CLICOLOR_FORCE")
        .env_remove("CLICOLOR")
        .output()
        .expect("runs chiaro");
    assert!(
        out.status.success(),
        "chiaro {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("UTF-8 help")
}

/// The commands a `--help` lists under `Commands:`, `help` left out.
fn commands(top_help: &str) -> Vec<String> {
    top_help
        .lines()
        .skip_while(|line| line.trim_end() != "Commands:")
        .skip(1)
        .take_while(|line| !line.trim().is_empty())
        .filter(|line| line.starts_with("  ") && !line.starts_with("   "))
        .filter_map(|line| line.split_whitespace().next())
        .filter(|name| *name != "help")
        .map(str::to_owned)
        .collect()
}

/// The generated part of the page: one section per command, its help in a text block.
fn generated() -> String {
    let top = help(&["--help"]);
    let commands = commands(&top);
    assert!(!commands.is_empty(), "no commands in:\n{top}");
    let mut out = section("chiaro", &top);
    for command in &commands {
        out.push_str(&section(
            &format!("chiaro {command}"),
            &help(&[command, "--help"]),
        ));
    }
    out
}

fn section(title: &str, help: &str) -> String {
    format!("\n## {title}\n\n```text\n{}\n```\n", help.trim_end())
}

/// `page` with the text between the markers replaced by `body`; `None` without both markers.
fn splice(page: &str, body: &str) -> Option<String> {
    let start = page.find(BEGIN)? + BEGIN.len();
    let end = start + page[start..].find(END)?;
    Some(format!(
        "{}\n{}\n{}",
        &page[..start],
        body.trim(),
        &page[end..]
    ))
}

#[test]
fn cli_md_is_the_help_of_every_command() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/cli.md");
    let page = std::fs::read_to_string(&path).expect("docs/cli.md");
    let expected = splice(&page, &generated())
        .unwrap_or_else(|| panic!("docs/cli.md lacks the markers:\n{BEGIN}\n{END}"));
    if std::env::var_os("CHIARO_BLESS").is_some() {
        if expected != page {
            std::fs::write(&path, &expected).expect("writes docs/cli.md");
            eprintln!("docs/cli.md regenerated");
        }
        return;
    }
    if expected != page {
        let first = page
            .lines()
            .zip(expected.lines())
            .position(|(a, b)| a != b)
            .unwrap_or_else(|| page.lines().count().min(expected.lines().count()));
        panic!(
            "docs/cli.md differs from `chiaro --help` (first at line {}: {:?} where the help \
             gives {:?}); regenerate it with `{BLESS}`",
            first + 1,
            page.lines().nth(first).unwrap_or(""),
            expected.lines().nth(first).unwrap_or(""),
        );
    }
}

#[test]
fn commands_are_read_from_the_help() {
    let sample = "A tool\n\nUsage: tool <COMMAND>\n\nCommands:\n  render  Draws\n          more \
                  about it\n  info    Tells\n  help    Print this message\n\nOptions:\n  -h, --help\n";
    assert_eq!(commands(sample), ["render", "info"]);
}

#[test]
fn splicing_replaces_only_what_lies_between_the_markers() {
    let page = format!("# Title\n\nProse.\n\n{BEGIN}\nold\n{END}\n\nAfter.\n");
    let new = splice(&page, "\n## new\n").unwrap();
    assert_eq!(
        new,
        format!("# Title\n\nProse.\n\n{BEGIN}\n## new\n{END}\n\nAfter.\n")
    );
    assert_eq!(splice(&new, "## new"), Some(new.clone()));
    assert!(splice("# no markers\n", "x").is_none());
    assert_ne!(splice(&page, "## other").unwrap(), new, "a change is seen");
}
