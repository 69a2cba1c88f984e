//! Tests of the mesh tank (`shape: "mesh"`): part areas against the closed-form areas of a box
//! and a cylinder, named groups, internal solids, and the refusal of bad meshes.

use std::f64::consts::PI;
use std::path::PathBuf;

use slosh_core::ParticleSetup;
use slosh_geometry::{
    box_mesh, circle_segments, revolve_profile, GeometryError, InternalSolid, MeshTank,
    SurfaceMesh, TankMesh,
};

fn part_area(s: &ParticleSetup<3>, name: &str) -> f64 {
    let part = s.part_names.iter().position(|n| n == name).unwrap() as u16;
    s.wall_part
        .iter()
        .zip(&s.wall_area)
        .filter(|(p, _)| **p == part)
        .map(|(_, a)| a)
        .sum()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("slosh-mesh-tank-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A box given as an untagged STL-like OBJ (parts by facing), raised 1 m in the file: the
/// per-particle areas of each part add up to the box's faces (closed form) within 1 %, the
/// lowest point goes to z = 0, and the fluid block is W·B·depth/dx³ particles.
#[test]
fn box_mesh_parts_by_facing_sum_to_the_face_areas() {
    let (w, b, h, depth, dx) = (0.4, 0.3, 0.5, 0.25, 0.05);
    let mut mesh = box_mesh([0.0, 0.0, 0.0], [w, b, h], 0.1);
    mesh.translate([0.0, 0.0, 1.0]);
    let path = temp_dir("box").join("box.obj");
    mesh.write_obj(&path, "box").unwrap();
    let s = MeshTank::new(&path, depth).build(dx).unwrap();
    assert_eq!(s.part_names, vec!["bottom", "wall", "roof"]);
    // 1 %: the tolerance for the boundary areas
    assert!(rel(part_area(&s, "bottom"), w * b) < 0.01);
    assert!(rel(part_area(&s, "wall"), 2.0 * (w + b) * h) < 0.01);
    assert!(rel(part_area(&s, "roof"), w * b) < 0.01);
    let expect = (w / dx).round() * (b / dx).round() * (depth / dx).round();
    assert_eq!(s.fluid_positions.len() as f64, expect);
    assert!(s.fluid_positions.iter().all(|p| p.z > 0.0 && p.z < depth));
}

/// An upright cylinder from `revolve_profile` with its lid in a group "lid" and a centre
/// column: parts bottom, wall, roof (empty), lid, column; the areas add up to πR², 2πRH, πR²
/// and the column's wetted side 2πrH within 1 %.
#[test]
fn cylinder_mesh_with_a_named_group_and_a_column() {
    let (r, h, depth, dx) = (0.3, 0.4, 0.2, 0.03);
    let n = circle_segments(r, dx, 1e-3 * dx);
    let mesh = revolve_profile(&[[0.0, 0.0], [r, 0.0], [r, h], [0.0, h]], false, n, dx);
    let groups: Vec<Option<String>> = mesh
        .triangles
        .iter()
        .map(|t| {
            let top = t.iter().all(|&i| mesh.vertices[i as usize][2] == h);
            top.then(|| "lid".to_string())
        })
        .collect();
    let path = temp_dir("cyl").join("cylinder.obj");
    mesh.write_obj_grouped(&path, "cylinder with a lid group", &groups)
        .unwrap();
    let read = TankMesh::read(&path).unwrap();
    assert_eq!(read.part_names, vec!["bottom", "wall", "roof", "lid"]);
    let s = MeshTank::new(&path, depth)
        .with_solid(InternalSolid::column(
            "column",
            [0.0, 0.0],
            0.06,
            -0.05,
            h + 0.05,
        ))
        .build(dx)
        .unwrap();
    assert_eq!(
        s.part_names,
        vec!["bottom", "wall", "roof", "lid", "column"]
    );
    let disc = PI * r * r;
    assert!(rel(part_area(&s, "bottom"), disc - PI * 0.06 * 0.06) < 0.01);
    assert!(rel(part_area(&s, "wall"), 2.0 * PI * r * h) < 0.01);
    assert!(rel(part_area(&s, "lid"), disc - PI * 0.06 * 0.06) < 0.01);
    assert_eq!(part_area(&s, "roof"), 0.0);
    assert!(rel(part_area(&s, "column"), 2.0 * PI * 0.06 * h) < 0.01);
    for p in &s.fluid_positions {
        assert!((p.x * p.x + p.y * p.y).sqrt() > 0.06);
    }
}

/// An open mesh, a zero-area triangle and a bad group name are refused, naming the file.
#[test]
fn bad_meshes_are_refused_with_the_file_named() {
    let dir = temp_dir("bad");
    let mesh = box_mesh([0.0; 3], [0.3, 0.3, 0.3], 0.1);
    let mut open = mesh.clone();
    open.triangles.pop();
    let open_path = dir.join("holed_tank.obj");
    open.write_obj(&open_path, "open").unwrap();
    let e = MeshTank::new(&open_path, 0.1).build(0.03).err().unwrap();
    assert!(
        matches!(e, GeometryError::MeshNotWatertight { open_edges: 3, .. }),
        "{e}"
    );
    assert!(e.to_string().contains("holed_tank.obj"), "{e}");

    let stl = "solid my tank\n".to_string() + &facets(&mesh) + "endsolid\n";
    let e = SurfaceMesh::parse_grouped(stl.as_bytes(), "stl", "named.stl")
        .and_then(|(m, g)| TankMesh::from_grouped(m, g, "named.stl"))
        .unwrap_err();
    assert!(
        e.to_string().contains("named.stl") && e.to_string().contains("my tank"),
        "{e}"
    );
    let stl = "solid tank_shell\n".to_string() + &facets(&mesh) + "endsolid\n";
    let (m, g) = SurfaceMesh::parse_grouped(stl.as_bytes(), "stl", "ok.stl").unwrap();
    let read = TankMesh::from_grouped(m, g, "ok.stl").unwrap();
    assert_eq!(
        read.part_names,
        vec!["bottom", "wall", "roof", "tank_shell"]
    );
}

/// A solid thinner than 2 dx is refused with its name and the limit.
#[test]
fn thin_solid_is_refused() {
    let mesh = box_mesh([0.0; 3], [0.4, 0.4, 0.4], 0.1);
    let path = temp_dir("thin").join("box.obj");
    mesh.write_obj(&path, "box").unwrap();
    let e = MeshTank::new(&path, 0.2)
        .with_solid(InternalSolid::block(
            "plate",
            [0.1, 0.0, 0.0],
            [0.13, 0.4, 0.3],
        ))
        .build(0.02)
        .err()
        .unwrap();
    assert!(e.to_string().contains("solid 'plate'"), "{e}");
    assert!(e.to_string().contains("thinner than 2 dx"), "{e}");
}

/// The triangles of `mesh` as ASCII STL facets.
fn facets(mesh: &SurfaceMesh) -> String {
    let mut out = String::new();
    for t in &mesh.triangles {
        out.push_str("facet normal 0 0 0\nouter loop\n");
        for &i in t {
            let v = mesh.vertices[i as usize];
            out.push_str(&format!("vertex {} {} {}\n", v[0], v[1], v[2]));
        }
        out.push_str("endloop\nendfacet\n");
    }
    out
}

/// Writes `geometry/cylinder_cone_roof_sump.obj` (run with `--ignored`): an upright cylinder
/// R = 0.5 m on the z axis with a central sump (R = 0.15 m, 0.12 m deep; its floor is the
/// lowest point, z = 0), the tank floor at z = 0.12 m, the shell to z = 0.92 m and a cone roof
/// to z = 1.07 m; 72 facets around, profile pieces ≤ 0.1 m; groups `sump`, `bottom`, `wall`,
/// `roof`.
#[test]
#[ignore]
fn write_example_tank_mesh() {
    let (r, rs, floor, shell_top, apex) = (0.5, 0.15, 0.12, 0.92, 1.07);
    let profile = [
        [0.0, 0.0],
        [rs, 0.0],
        [rs, floor],
        [r, floor],
        [r, shell_top],
        [0.0, apex],
    ];
    let mesh = revolve_profile(&profile, false, 72, 0.1);
    let eps = 1e-9;
    let groups: Vec<Option<String>> = mesh
        .triangles
        .iter()
        .map(|t| {
            let v = t.map(|i| mesh.vertices[i as usize]);
            let radius = |p: [f64; 3]| (p[0] * p[0] + p[1] * p[1]).sqrt();
            let name = if v
                .iter()
                .all(|p| p[2] <= floor + eps && radius(*p) <= rs + eps)
            {
                "sump"
            } else if v.iter().all(|p| (p[2] - floor).abs() <= eps) {
                "bottom"
            } else if v.iter().all(|p| p[2] >= shell_top - eps) {
                "roof"
            } else {
                "wall"
            };
            Some(name.to_string())
        })
        .collect();
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../geometry/cylinder_cone_roof_sump.obj");
    mesh.write_obj_grouped(
        &path,
        "slosh tank interior: upright cylinder R = 0.5 m with a central sump R = 0.15 m, 0.12 m deep\n\
         (sump floor z = 0, tank floor z = 0.12 m), shell to z = 0.92 m, cone roof to z = 1.07 m\n\
         units m; axis x = y = 0; normals point out of the liquid; groups sump, bottom, wall, roof",
        &groups,
    )
    .unwrap();
    let read = TankMesh::read(&path).unwrap();
    assert_eq!(read.part_names, vec!["bottom", "wall", "roof", "sump"]);
}
