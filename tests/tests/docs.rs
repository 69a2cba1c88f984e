//! The user guide (`docs/`, an mdBook) and the README against the repository: every relative
//! link resolves to a file and, with `#anchor`, to a heading of it; every page is in the
//! book's `SUMMARY.md`; the case-script reference names every function a script can call and
//! every key the script reader accepts, read from the code, so that it cannot drift; the
//! README stays short; no code comment cites a README heading (a heading that moves breaks it
//! silently; the guide's pages are cited by name instead).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// Markdown files of the guide (under `docs/`, the built book excluded) and the README.
fn markdown_files() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|e| e == "md") {
                out.push(path);
            }
        }
    }
    let mut files = vec![repo().join("README.md")];
    walk(&repo().join("docs"), &mut files);
    files.sort();
    files
}

/// The lines of `text` outside fenced code blocks.
fn prose_lines(text: &str) -> Vec<&str> {
    let mut in_fence = false;
    let mut lines = Vec::new();
    for line in text.lines() {
        let trimmed = line.trim_start();
        if trimmed.starts_with("```") || trimmed.starts_with("~~~") {
            in_fence = !in_fence;
            continue;
        }
        if !in_fence {
            lines.push(line);
        }
    }
    lines
}

/// A heading's anchor as GitHub and mdBook make it: lower case, letters, digits, `_` and `-`
/// kept, spaces turned to `-`, everything else dropped.
fn slug(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '_' || c == '-' => Some(c),
            _ => None,
        })
        .collect()
}

/// The anchors of a Markdown file's headings (a repeated heading gets `-1`, `-2`, …).
fn anchors(text: &str) -> BTreeSet<String> {
    let mut seen = BTreeSet::new();
    for line in prose_lines(text) {
        let Some(rest) = line.strip_prefix('#') else {
            continue;
        };
        let title = rest.trim_start_matches('#');
        if !title.starts_with(' ') {
            continue;
        }
        // An explicit `{#id}` is the anchor; otherwise the heading's words: a closing run of
        // `#`, link targets, inline code and emphasis marks are not part of them.
        let title = title.trim().trim_end_matches('#').trim_end();
        if let Some(id) = title
            .rsplit_once("{#")
            .and_then(|(_, rest)| rest.strip_suffix('}'))
        {
            seen.insert(id.to_string());
            continue;
        }
        let base = slug(&link_text(title).replace(['`', '*'], ""));
        let mut anchor = base.clone();
        let mut k = 0;
        while seen.contains(&anchor) {
            k += 1;
            anchor = format!("{base}-{k}");
        }
        seen.insert(anchor);
    }
    seen
}

/// `text` with each inline link `[words](target)` replaced by its words.
fn link_text(text: &str) -> String {
    let mut out = String::new();
    let mut rest = text;
    while let Some(i) = rest.find("](") {
        let Some(end) = rest[i + 2..].find(')') else {
            break;
        };
        out.push_str(&rest[..i].replace('[', ""));
        rest = &rest[i + 2 + end + 1..];
    }
    out.push_str(&rest.replace(['[', ']'], ""));
    out
}

/// The targets of the inline links and images in `text` (`[..](target)`), code excluded.
fn link_targets(text: &str) -> Vec<String> {
    let mut targets = Vec::new();
    for line in prose_lines(text) {
        // inline code spans may hold `](` that is no link
        let mut clean = String::new();
        for (k, part) in line.split('`').enumerate() {
            if k % 2 == 0 {
                clean.push_str(part);
            }
        }
        let mut rest = clean.as_str();
        while let Some(i) = rest.find("](") {
            let after = &rest[i + 2..];
            let Some(end) = after.find(')') else {
                break;
            };
            let target = after[..end].split_whitespace().next().unwrap_or("");
            targets.push(target.trim_matches(['<', '>']).to_string());
            rest = &after[end..];
        }
    }
    targets
}

#[test]
fn anchors_follow_the_heading_rules_of_mdbook_and_github() {
    let text = "# Getting started\n## The `slosh run` command\n## See [formats](formats.md)\n\
                ## Closing hashes ##\n## Custom {#my-id}\n## Getting started\n\
                ~~~\n# not a heading\n~~~\n";
    let a = anchors(text);
    for expected in [
        "getting-started",
        "the-slosh-run-command",
        "see-formats",
        "closing-hashes",
        "my-id",
        "getting-started-1",
    ] {
        assert!(a.contains(expected), "{expected} not in {a:?}");
    }
    assert!(!a.contains("not-a-heading"), "{a:?}");
}

#[test]
fn every_relative_link_resolves_to_a_file_and_heading() {
    let mut broken = Vec::new();
    for file in markdown_files() {
        let text = std::fs::read_to_string(&file).unwrap();
        for target in link_targets(&text) {
            if target.is_empty() || target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            let (path, anchor) = match target.split_once('#') {
                Some((p, a)) => (p, Some(a)),
                None => (target.as_str(), None),
            };
            let resolved = if path.is_empty() {
                file.clone()
            } else {
                file.parent().unwrap().join(path)
            };
            if !resolved.exists() {
                broken.push(format!("{}: {target} (no such file)", file.display()));
                continue;
            }
            if let Some(anchor) = anchor {
                if resolved.extension().is_some_and(|e| e == "md") {
                    let target_text = std::fs::read_to_string(&resolved).unwrap();
                    if !anchors(&target_text).contains(anchor) {
                        broken.push(format!("{}: {target} (no such heading)", file.display()));
                    }
                }
            }
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

#[test]
fn every_page_of_the_guide_is_in_the_book() {
    let docs = repo().join("docs");
    let summary = std::fs::read_to_string(docs.join("SUMMARY.md")).unwrap();
    let listed: BTreeSet<PathBuf> = link_targets(&summary)
        .into_iter()
        .map(|t| docs.join(t.split('#').next().unwrap()))
        .collect();
    let missing: Vec<String> = markdown_files()
        .into_iter()
        .filter(|f| f.starts_with(&docs) && !f.ends_with("SUMMARY.md") && !listed.contains(f))
        .map(|f| f.display().to_string())
        .collect();
    assert!(
        missing.is_empty(),
        "pages missing from docs/SUMMARY.md: {missing:?}"
    );
    let book = std::fs::read_to_string(docs.join("book.toml")).unwrap();
    assert!(
        book.contains("[book]"),
        "docs/book.toml is not an mdBook configuration"
    );
}

/// The names in `source` that follow `pattern` up to the closing quote: `register_fn("name"`
/// gives `name` (whitespace and line breaks after the pattern allowed).
fn quoted_after(source: &str, pattern: &str) -> Vec<String> {
    let mut names = Vec::new();
    let mut rest = source;
    while let Some(i) = rest.find(pattern) {
        let after = rest[i + pattern.len()..].trim_start();
        if let Some(quoted) = after.strip_prefix('"') {
            if let Some(end) = quoted.find('"') {
                names.push(quoted[..end].to_string());
            }
        }
        rest = &rest[i + pattern.len()..];
    }
    names
}

/// Every function registered for scripts and every key the script reader takes, read from
/// `crates/slosh-script/src`: functions by `register_fn("name"` (and the three map functions
/// registered in a loop), keys by the map reader's methods (`.f64_or("key"`, …).
fn script_names() -> (BTreeSet<String>, BTreeSet<String>) {
    let src = repo().join("crates/slosh-script/src");
    let mut sources = Vec::new();
    for entry in std::fs::read_dir(&src).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "rs") {
            sources.push(std::fs::read_to_string(path).unwrap());
        }
    }
    let spec = std::fs::read_to_string(src.join("spec.rs")).unwrap();
    // The reader's methods: `pub(crate) fn NAME(&mut self, key: &str` (a generic one as
    // `NAME<T…>(`, its parameters on the next lines).
    let methods: Vec<String> = spec
        .split("pub(crate) fn ")
        .skip(1)
        .filter_map(|s| {
            let (head, rest) = s.split_once('(')?;
            let name = head.split('<').next()?;
            rest.trim_start().starts_with("&mut self,").then_some(())?;
            let params = rest.split(')').next()?;
            params.contains("key: &str").then(|| name.to_string())
        })
        .collect();
    assert!(
        methods.len() >= 5,
        "the map reader's methods were not found: {methods:?}"
    );
    let mut functions = BTreeSet::new();
    let mut keys = BTreeSet::new();
    for source in &sources {
        // test modules hold scripts of their own
        let code = source.split("#[cfg(test)]").next().unwrap();
        functions.extend(quoted_after(code, "register_fn("));
        for m in &methods {
            keys.extend(quoted_after(code, &format!(".{m}(")));
        }
    }
    // `for key in ["tank", "numerics", "run"] { engine.register_fn(key, …) }`
    functions.extend(["tank", "numerics", "run"].map(String::from));
    // Rhai's operators and conversions on the record types are not script functions.
    functions.retain(|f| f.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'));
    functions.retain(|f| f != "to_string" && f != "to_debug");
    (functions, keys)
}

#[test]
fn the_case_script_reference_names_every_function_and_key() {
    let page = std::fs::read_to_string(repo().join("docs/script-reference.md")).unwrap();
    let (functions, keys) = script_names();
    assert!(
        functions.len() >= 15 && keys.len() >= 40,
        "{functions:?} {keys:?}"
    );
    let missing: Vec<&String> = functions
        .iter()
        .chain(&keys)
        .filter(|name| !page.contains(&format!("`{name}`")) && !page.contains(&format!("`{name}(")))
        .collect();
    assert!(
        missing.is_empty(),
        "docs/script-reference.md does not name (in backticks): {missing:?}"
    );
}

#[test]
fn the_readme_is_short_and_code_cites_no_readme_heading() {
    let readme = std::fs::read_to_string(repo().join("README.md")).unwrap();
    let lines = readme.lines().count();
    assert!(
        lines <= 260,
        "README.md has {lines} lines; the guide in docs/ holds the rest"
    );
    let mut citing = Vec::new();
    fn walk(dir: &Path, citing: &mut Vec<String>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                if !path.ends_with("target") {
                    walk(&path, citing);
                }
            } else if path.extension().is_some_and(|e| e == "rs") {
                let text = std::fs::read_to_string(&path).unwrap();
                for (k, line) in text.lines().enumerate() {
                    if line.contains("README, *") || line.contains("README's *") {
                        citing.push(format!("{}:{}", path.display(), k + 1));
                    }
                }
            }
        }
    }
    walk(&repo().join("crates"), &mut citing);
    assert!(
        citing.is_empty(),
        "comments citing a README heading: {citing:?}"
    );
}
