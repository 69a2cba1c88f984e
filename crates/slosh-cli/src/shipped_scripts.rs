//! The case scripts shipped in the repository's `scripts/` folder, listed by `slosh run
//! --help` with their one-line purpose.
//!
//! The list is read at run time, so it follows the scripts on disk: from `scripts/` in the
//! current folder, else from the repository that holds the executable (the first folder
//! above it with a `Cargo.toml` and a `scripts/` folder, as for `target/release/slosh`).

use std::path::{Path, PathBuf};

/// The `scripts/` folder to list: the current folder's, else the executable's repository's.
pub fn find_scripts_dir() -> Option<PathBuf> {
    let here = PathBuf::from("scripts");
    if has_scripts(&here) {
        return Some(here);
    }
    let exe = std::env::current_exe().ok()?;
    exe.ancestors()
        .skip(1)
        .find(|dir| dir.join("Cargo.toml").is_file() && has_scripts(&dir.join("scripts")))
        .map(|dir| dir.join("scripts"))
}

fn has_scripts(dir: &Path) -> bool {
    std::fs::read_dir(dir).is_ok_and(|entries| {
        entries
            .flatten()
            .any(|e| e.path().extension().is_some_and(|x| x == "rhai"))
    })
}

/// A script's purpose: its first comment line, without the `//` and a trailing comma.
pub fn purpose(source: &str) -> Option<String> {
    let line = source
        .lines()
        .map(str::trim)
        .find(|l| l.starts_with("//"))?;
    let text = line.trim_start_matches('/').trim();
    let text = text.trim_end_matches([',', ';', ':']).trim_end();
    (!text.is_empty()).then(|| text.to_string())
}

/// The `.rhai` files of `dir` with their purpose, sorted by file name.
pub fn list(dir: &Path) -> Vec<(String, String)> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut scripts: Vec<(String, String)> = entries
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "rhai"))
        .map(|p| {
            let name = p
                .file_name()
                .unwrap_or_default()
                .to_string_lossy()
                .to_string();
            let text = std::fs::read_to_string(&p).unwrap_or_default();
            (
                name,
                purpose(&text).unwrap_or_else(|| "(no comment)".into()),
            )
        })
        .collect();
    scripts.sort();
    scripts
}

/// The text `slosh run --help` ends with: the shipped scripts and their purpose, or where to
/// find them when no `scripts/` folder is found.
pub fn help_text() -> String {
    let Some(dir) = find_scripts_dir() else {
        return "Case scripts: none found (no scripts/ folder in the current folder or in the \
                repository of this executable); the repository's scripts/ folder holds the \
                shipped cases."
            .into();
    };
    let mut text = format!("Case scripts in {}:\n", dir.display());
    for (name, purpose) in list(&dir) {
        text.push_str(&format!("  {name:<26} {purpose}\n"));
    }
    text.push_str("\nTheir parameters: slosh run SCRIPT --list-params");
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn purpose_is_the_first_comment_line() {
        let source = "\n// Paper §3.1: 2D tank 1.0 m wide,\n// more\nlet a = 1;";
        assert_eq!(
            purpose(source).as_deref(),
            Some("Paper §3.1: 2D tank 1.0 m wide")
        );
        assert_eq!(purpose("let a = 1;"), None);
    }

    #[test]
    fn the_shipped_scripts_all_say_what_they_are() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scripts");
        let scripts = list(&dir);
        assert!(scripts.len() >= 5, "{scripts:?}");
        assert!(
            scripts.iter().all(|(_, p)| p != "(no comment)"),
            "{scripts:?}"
        );
    }
}
