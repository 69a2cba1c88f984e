//! The sandbox: a script reads below its own folder and its marked project folder only;
//! `..`, absolute paths and symlinks that lead out are refused; `--allow-read` widens it; the
//! file system root and the home folder are never opened by default.

use slosh_script::{load_case, CaseOptions, ReadSandbox};
use std::path::{Path, PathBuf};

fn temp_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir()
        .join(format!("slosh-script-sandbox-{}", std::process::id()))
        .join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir.canonicalize().unwrap()
}

const AT2: &str =
    "t\nt\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS= 3, DT= 0.01 SEC\n0.1 0.2 0.3\n";

fn write(path: &Path, text: &str) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, text).unwrap();
}

/// A case in `dir` that reads `record` at its top level.
fn case_reading(dir: &Path, record: &str) -> PathBuf {
    let path = dir.join("case.rhai");
    write(
        &path,
        &format!(
            "let gm = load_record(\"{record}\", #{{ format: \"at2\" }});\n\
             tank(#{{ shape: \"rect\", width: 1.0, height: 1.0, depth: 0.5 }});\n\
             run(#{{ settle: 0.0, duration: 0.02 }});\n\
             fn ground_accel(t) {{ gm.at(t) }}\n"
        ),
    );
    path
}

fn load_error(case: &Path, options: &CaseOptions) -> String {
    match load_case(case, options) {
        Ok(_) => panic!("{}: the script should have been refused", case.display()),
        Err(e) => e.to_string(),
    }
}

#[test]
fn a_script_reads_below_its_folder() {
    let dir = temp_dir("own_folder");
    write(&dir.join("records/r.at2"), AT2);
    let case = case_reading(&dir, "records/r.at2");
    load_case(&case, &CaseOptions::default()).unwrap();
}

#[test]
fn dotdot_and_absolute_paths_out_of_the_folder_are_refused() {
    let dir = temp_dir("dotdot");
    write(&dir.join("outside.at2"), AT2);
    let inner = dir.join("case");
    std::fs::create_dir_all(&inner).unwrap();
    for record in [
        "../outside.at2".to_string(),
        "sub/../../outside.at2".to_string(),
        dir.join("outside.at2").display().to_string(),
        "/etc/passwd".to_string(),
        "../../../../../../../../etc/passwd".to_string(),
    ] {
        let message = load_error(&case_reading(&inner, &record), &CaseOptions::default());
        assert!(
            message.contains("leaves the folders"),
            "{record}: {message}"
        );
        assert!(message.contains("--allow-read"), "{record}: {message}");
        assert!(!message.contains("root:"), "{record}: {message}");
    }
}

#[test]
fn a_script_in_tmp_does_not_open_the_machine() {
    // The project folder of a script in a bare folder is not `/`: `etc/passwd` is looked up
    // below the script's folder only, where it does not exist.
    let dir = temp_dir("bare");
    let message = load_error(&case_reading(&dir, "etc/passwd"), &CaseOptions::default());
    assert!(message.contains("cannot read"), "{message}");
    assert!(!message.contains("root:"), "{message}");
    let sandbox = ReadSandbox::for_script(&dir, &[]).unwrap();
    assert_eq!(sandbox.roots(), std::slice::from_ref(&dir));
}

#[cfg(unix)]
#[test]
fn symlinks_that_leave_the_folder_are_refused() {
    let dir = temp_dir("symlink");
    let outside = temp_dir("symlink_target");
    write(&outside.join("secret.at2"), AT2);
    std::os::unix::fs::symlink(outside.join("secret.at2"), dir.join("record.at2")).unwrap();
    std::os::unix::fs::symlink("/etc/passwd", dir.join("passwd.at2")).unwrap();
    std::os::unix::fs::symlink(&outside, dir.join("linked_dir")).unwrap();
    for record in ["record.at2", "passwd.at2", "linked_dir/secret.at2"] {
        let message = load_error(&case_reading(&dir, record), &CaseOptions::default());
        assert!(
            message.contains("leaves the folders"),
            "{record}: {message}"
        );
        assert!(!message.contains("root:"), "{record}: {message}");
    }
    // A symlink that stays inside is fine.
    write(&dir.join("data/real.at2"), AT2);
    std::os::unix::fs::symlink(dir.join("data/real.at2"), dir.join("alias.at2")).unwrap();
    load_case(&case_reading(&dir, "alias.at2"), &CaseOptions::default()).unwrap();
}

#[test]
fn allow_read_widens_the_sandbox() {
    let dir = temp_dir("allow_read");
    let shared = temp_dir("allow_read_shared");
    write(&shared.join("motions/r.at2"), AT2);
    let absolute = shared.join("motions/r.at2").display().to_string();
    let case = case_reading(&dir, &absolute);
    load_error(&case, &CaseOptions::default());
    let options = CaseOptions {
        allow_read: vec![shared.clone()],
        ..CaseOptions::default()
    };
    load_case(&case, &options).unwrap();
    // Relative paths are looked up there too.
    load_case(&case_reading(&dir, "motions/r.at2"), &options).unwrap();
    // A folder that does not exist is an error naming it.
    let missing = CaseOptions {
        allow_read: vec![dir.join("no_such_folder")],
        ..CaseOptions::default()
    };
    let message = load_error(&case, &missing);
    assert!(
        message.contains("--allow-read") && message.contains("no_such_folder"),
        "{message}"
    );
}

#[test]
fn a_marked_project_folder_is_readable_from_its_scripts() {
    let project = temp_dir("project");
    write(&project.join("slosh.toml"), "");
    write(&project.join("data/r.at2"), AT2);
    let scripts = project.join("cases/tall");
    std::fs::create_dir_all(&scripts).unwrap();
    load_case(
        &case_reading(&scripts, "data/r.at2"),
        &CaseOptions::default(),
    )
    .unwrap();
    load_case(
        &case_reading(&scripts, "../../data/r.at2"),
        &CaseOptions::default(),
    )
    .unwrap();
    // Without the marker the project folder is not open.
    std::fs::remove_file(project.join("slosh.toml")).unwrap();
    let message = load_error(
        &case_reading(&scripts, "../../data/r.at2"),
        &CaseOptions::default(),
    );
    assert!(message.contains("leaves the folders"), "{message}");
}

#[test]
fn root_and_home_are_never_allowed_by_default() {
    let root = ReadSandbox::for_script(Path::new("/"), &[]).unwrap();
    assert!(
        root.roots().iter().all(|r| r.parent().is_some()),
        "{:?}",
        root.roots()
    );
    if let Some(home) = std::env::var_os("HOME").and_then(|h| PathBuf::from(h).canonicalize().ok())
    {
        let sandbox = ReadSandbox::for_script(&home, &[]).unwrap();
        assert!(!sandbox.roots().contains(&home), "{:?}", sandbox.roots());
        let widened = ReadSandbox::for_script(&home, std::slice::from_ref(&home)).unwrap();
        assert!(widened.roots().contains(&home));
    }
}

#[test]
fn the_repository_scripts_read_their_data_and_meshes() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    for script in ["elcentro_2d.rhai", "elcentro_3d.rhai"] {
        let case = load_case(&root.join("scripts").join(script), &CaseOptions::default())
            .unwrap_or_else(|e| panic!("{script}: {e}"));
        assert_eq!(case.motions.len(), 1, "{script}");
    }
    let case = load_case(
        &root.join("scripts/cylinder_mesh_roof.rhai"),
        &CaseOptions::default(),
    )
    .unwrap();
    let mesh = case
        .sandbox
        .resolve("geometry/cylinder_R0.5_H1.0_cone_roof.obj")
        .unwrap();
    assert!(mesh.is_file(), "{}", mesh.display());
}

/// A mesh tank reads its file through the sandbox: the shipped example lists its groups as
/// parts (with the mesh areas) and its column; a mesh outside the folder, or an open one, is
/// refused at the `tank` call (file:line) with the mesh file named.
#[test]
fn a_mesh_tank_reads_its_file_through_the_sandbox() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let case = load_case(
        &root.join("scripts/mesh_tank_3d.rhai"),
        &CaseOptions::default(),
    )
    .unwrap();
    let names: Vec<String> = case
        .tank
        .part_descriptions()
        .into_iter()
        .map(|p| p.0)
        .collect();
    assert_eq!(names, ["bottom", "wall", "roof", "sump", "column"]);

    let dir = temp_dir("mesh_tank");
    write(&dir.join("outside.obj"), "v 0 0 0\n");
    let inner = dir.join("case");
    let script = |mesh: &str| {
        let path = inner.join("case.rhai");
        write(
            &path,
            &format!(
                "run(#{{ settle: 0.0, duration: 0.02 }});\n\
                 tank(#{{ shape: \"mesh\", mesh: \"{mesh}\", depth: 0.1 }});\n"
            ),
        );
        path
    };
    let e = load_error(&script("../outside.obj"), &CaseOptions::default());
    assert!(e.contains("case.rhai:2"), "{e}");
    assert!(e.contains("outside.obj"), "{e}");
    // a single open triangle
    write(
        &inner.join("open.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    );
    let e = load_error(&script("open.obj"), &CaseOptions::default());
    assert!(e.contains("case.rhai:2") && e.contains("open.obj"), "{e}");
    assert!(e.contains("not watertight"), "{e}");
}

/// A named pipe (which would block the read forever) or a folder given as a record is
/// refused with its name before anything is read.
#[test]
fn a_fifo_or_a_folder_is_not_a_record() {
    let dir = temp_dir("fifo");
    let fifo = dir.join("fifo.at2");
    let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    // SAFETY: mkfifo with a valid NUL-terminated path.
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
    let case = case_reading(&dir, "fifo.at2");
    let e = load_error(&case, &CaseOptions::default());
    assert!(
        e.contains("fifo.at2") && e.contains("not a regular file"),
        "{e}"
    );
    std::fs::create_dir_all(dir.join("folder.at2")).unwrap();
    let case = case_reading(&dir, "folder.at2");
    let e = load_error(&case, &CaseOptions::default());
    assert!(e.contains("not a regular file"), "{e}");
}
