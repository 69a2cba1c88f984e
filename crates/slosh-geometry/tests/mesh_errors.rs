//! Mesh read errors name the line and quote at most a short, escaped excerpt of the file.

use slosh_geometry::SurfaceMesh;

#[test]
fn bad_tokens_are_quoted_short_and_escaped() {
    let secret = format!("root:x:0:0:{}\u{1b}[31m", "s".repeat(500));
    for (bytes, ext) in [
        (format!("v 0 0 {secret}\n"), "obj"),
        (
            format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 {secret}\n"),
            "obj",
        ),
        (
            format!("solid x\nfacet\nouter loop\nvertex 0 0 {secret}\n"),
            "stl",
        ),
    ] {
        let message = SurfaceMesh::parse(bytes.as_bytes(), ext, "m")
            .unwrap_err()
            .to_string();
        assert!(!message.contains(&"s".repeat(61)), "{message}");
        assert!(!message.contains('\u{1b}'), "{message}");
        assert!(message.contains("line"), "{message}");
    }
}
