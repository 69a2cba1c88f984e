//! The folders a case script may read files from (records, meshes), and the check of every
//! path it asks for.
//!
//! A script reads below its own folder, below its project folder — the nearest folder above
//! it that is marked as one (it holds a `slosh.toml`, or is a repository root holding both
//! `scripts/` and `Cargo.toml`) — and below the folders given with `--allow-read`. The file
//! system root and the user's home folder are never allowed by these rules alone (a script
//! saved in `/tmp` or in `~` does not open the machine or the home folder); `--allow-read`
//! names them explicitly when that is really wanted. Every path is resolved (`..` and
//! symlinks included) and must end inside an allowed folder.

use std::path::{Component, Path, PathBuf};

/// The file marking a folder as a slosh project: scripts below it may read anything below it.
pub const PROJECT_MARKER: &str = "slosh.toml";

/// The folders a script may read below, each canonical (symlinks resolved).
#[derive(Clone, Debug, Default)]
pub struct ReadSandbox {
    /// Allowed folders, in the order relative paths are looked up: the script's folder, the
    /// project folder, then the `--allow-read` folders.
    roots: Vec<PathBuf>,
}

impl ReadSandbox {
    /// The folders a script in `script_dir` may read: its folder and its project folder (when
    /// either is neither `/` nor the home folder) and each of `allow_read` (which must exist).
    pub fn for_script(script_dir: &Path, allow_read: &[PathBuf]) -> Result<Self, String> {
        let mut roots = Vec::new();
        let script_dir = if script_dir.as_os_str().is_empty() {
            canonical_or_same(Path::new("."))
        } else {
            canonical_or_same(script_dir)
        };
        if !is_too_wide(&script_dir) {
            roots.push(script_dir.clone());
        }
        if let Some(project) = project_folder(&script_dir) {
            push_unique(&mut roots, project);
        }
        for dir in allow_read {
            let canonical = dir.canonicalize().map_err(|e| {
                format!(
                    "--allow-read {}: {e}; give an existing folder",
                    dir.display()
                )
            })?;
            push_unique(&mut roots, canonical);
        }
        Ok(ReadSandbox { roots })
    }

    /// The allowed folders, canonical, in lookup order.
    pub fn roots(&self) -> &[PathBuf] {
        &self.roots
    }

    /// Resolves a path a script gave: a relative path is looked up below each allowed folder
    /// in turn (the script's folder first); an absolute path is taken as it is. The path is
    /// refused when it ends (after `..` and symlinks) outside every allowed folder. A path
    /// that exists nowhere resolves below the first folder, where the reader reports it missing.
    pub fn resolve(&self, requested: &str) -> Result<PathBuf, String> {
        let path = Path::new(requested);
        if requested.is_empty() || path.components().any(|c| matches!(c, Component::Prefix(_))) {
            return Err(format!("\"{requested}\": not a file path"));
        }
        let candidates: Vec<PathBuf> = if path.is_absolute() {
            vec![path.to_path_buf()]
        } else {
            self.roots.iter().map(|root| root.join(path)).collect()
        };
        for candidate in &candidates {
            if let Ok(real) = candidate.canonicalize() {
                let real = self.inside(real, requested)?;
                // A named pipe, a device or a folder would block the read or make no sense
                // as a record or a mesh.
                if !real.is_file() {
                    return Err(format!(
                        "\"{requested}\" ({}) is not a regular file: a record or a mesh must be \
                         a file",
                        real.display()
                    ));
                }
                return Ok(real);
            }
        }
        match candidates.first() {
            Some(first) => self.inside(lexically_normal(first), requested),
            None => Err(self.refusal(requested)),
        }
    }

    /// `path` when it lies below an allowed folder, else the refusal for `requested`.
    fn inside(&self, path: PathBuf, requested: &str) -> Result<PathBuf, String> {
        if self.roots.iter().any(|root| path.starts_with(root)) {
            Ok(path)
        } else {
            Err(self.refusal(requested))
        }
    }

    fn refusal(&self, requested: &str) -> String {
        let allowed = if self.roots.is_empty() {
            "none: the script's folder is / or a home folder, which are never opened by \
             default"
                .to_string()
        } else {
            self.roots
                .iter()
                .map(|r| r.display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        };
        format!(
            "\"{requested}\" leaves the folders scripts may read files from: scripts may only \
             read files below their own folder or their project folder (one holding \
             {PROJECT_MARKER}, or the repository root with scripts/ and Cargo.toml), and `..`, \
             absolute paths and symlinks may not lead out of them (allowed: {allowed}); give a \
             path such as \"data/record.at2\", or widen the set with --allow-read DIR"
        )
    }
}

/// The nearest folder at or above `dir` marked as a project folder, unless it is `/` or the
/// home folder.
fn project_folder(dir: &Path) -> Option<PathBuf> {
    let marked = dir.ancestors().find(|a| {
        a.join(PROJECT_MARKER).is_file()
            || (a.join("scripts").is_dir() && a.join("Cargo.toml").is_file())
    })?;
    (!is_too_wide(marked)).then(|| marked.to_path_buf())
}

/// True for the folders never opened by default: the file system root and the home folder.
fn is_too_wide(dir: &Path) -> bool {
    let home = std::env::var_os("HOME").map(|h| canonical_or_same(Path::new(&h)));
    dir.parent().is_none() || home.is_some_and(|h| h == dir)
}

fn canonical_or_same(path: &Path) -> PathBuf {
    path.canonicalize()
        .unwrap_or_else(|_| lexically_normal(path))
}

fn push_unique(roots: &mut Vec<PathBuf>, dir: PathBuf) {
    if !roots.contains(&dir) {
        roots.push(dir);
    }
}

/// `path` with `.` removed and each `..` taking away the component before it (no file system
/// access: for paths that do not exist).
fn lexically_normal(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                if !out.pop() {
                    out.push("..");
                }
            }
            other => out.push(other.as_os_str()),
        }
    }
    out
}
