//! Script parameters: unit and description from the trailing comment or the third argument
//! of `param`, every shipped script documented, and `--set` given twice refused.

use slosh_script::{list_params, load_case, parse_set_value, CaseOptions, ScriptError};
use std::path::PathBuf;

fn temp_script(test: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir()
        .join(format!("slosh-script-params-{}", std::process::id()))
        .join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("case.rhai");
    std::fs::write(&path, text).unwrap();
    path
}

const CASE: &str = r#"
let width = param("width", 0.4);        // inner tank width (m)
let dx = param("dx", 0.04, "particle spacing (m)");
let scheme = param("scheme", "paper");  // "paper" or "modern"
let quiet = param("quiet", true);
tank(#{ shape: "rect", width: width, height: 0.4, depth: 0.2 });
numerics(#{ dx: dx, scheme: scheme });
run(#{ settle: 0.0, duration: 0.01 });
"#;

#[test]
fn unit_and_description_come_from_the_comment_or_the_third_argument() {
    let path = temp_script("docs", CASE);
    let params = list_params(&path).unwrap();
    let find = |name: &str| params.iter().find(|p| p.name == name).unwrap();
    assert_eq!(find("width").unit.as_deref(), Some("m"));
    assert_eq!(
        find("width").description.as_deref(),
        Some("inner tank width")
    );
    assert_eq!(find("dx").unit.as_deref(), Some("m"));
    assert_eq!(find("dx").description.as_deref(), Some("particle spacing"));
    assert_eq!(find("scheme").unit, None);
    assert_eq!(
        find("scheme").description.as_deref(),
        Some("\"paper\" or \"modern\"")
    );
    assert_eq!(find("quiet").description, None);
}

#[test]
fn every_parameter_of_the_shipped_scripts_is_documented() {
    let scripts = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scripts");
    let mut undocumented = Vec::new();
    for entry in std::fs::read_dir(&scripts).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "rhai") {
            continue;
        }
        for p in list_params(&path).unwrap() {
            if p.description.is_none() {
                undocumented.push(format!("{}: {}", path.display(), p.name));
            }
        }
    }
    assert!(undocumented.is_empty(), "{undocumented:#?}");
}

#[test]
fn set_twice_for_one_name_is_an_error_naming_it() {
    let path = temp_script("twice", CASE);
    let options = CaseOptions {
        overrides: vec![
            ("width".into(), parse_set_value("0.5")),
            ("width".into(), parse_set_value("0.6")),
        ],
        ..CaseOptions::default()
    };
    let err = load_case(&path, &options).err().expect("refused");
    let text = err.to_string();
    assert!(matches!(err, ScriptError::Case { .. }), "{text}");
    assert!(text.contains("--set width is given twice"), "{text}");
}

#[test]
fn non_finite_set_values_are_refused() {
    let path = temp_script("inf", CASE);
    for value in ["inf", "nan"] {
        let options = CaseOptions {
            overrides: vec![("width".into(), parse_set_value(value))],
            ..CaseOptions::default()
        };
        let text = load_case(&path, &options)
            .err()
            .expect("refused")
            .to_string();
        assert!(
            text.contains("--set width: must be a finite number"),
            "{text}"
        );
    }
}
