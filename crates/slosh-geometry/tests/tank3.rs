//! Tests of the 3D builders: cylinder (roofs, open, tilt, solids), box, mesh files.

use std::f64::consts::PI;
use std::path::PathBuf;
use std::time::Instant;

use nalgebra::Vector3;
use slosh_core::ParticleSetup;
use slosh_geometry::{
    cylinder_roof_mesh_obj, BoxTank, CylinderLattice, CylinderTank, GeometryError, InternalSolid,
    Roof, SphereTank, SurfaceMesh,
};

fn part_area(s: &ParticleSetup<3>, part: u16) -> f64 {
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

/// Cubic B-spline kernel, 3D normalisation 1/(π h³).
fn kernel(r: f64, h: f64) -> f64 {
    let q = r / h;
    let sigma = 1.0 / (PI * h * h * h);
    if q < 1.0 {
        sigma * (1.0 - 1.5 * q * q + 0.75 * q * q * q)
    } else if q < 2.0 {
        sigma * 0.25 * (2.0 - q).powi(3)
    } else {
        0.0
    }
}

/// Σ_j dx³ W(|x − x_j|, 1.3 dx) over fluid and wall particles.
fn kernel_sum(s: &ParticleSetup<3>, x: Vector3<f64>) -> f64 {
    let dx = s.spacing;
    let h = 1.3 * dx;
    s.fluid_positions
        .iter()
        .chain(&s.wall_positions)
        .map(|p| dx.powi(3) * kernel((p - x).norm(), h))
        .sum()
}

fn temp_dir(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("slosh-geometry-test-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Distance from a point outside a closed flat-roof cylinder to its surface.
fn cyl_outside_distance(p: &Vector3<f64>, r: f64, h: f64) -> f64 {
    let rr = (p.x * p.x + p.y * p.y).sqrt();
    let a = (rr - r).max(0.0);
    let b = (-p.z).max(0.0);
    let c = (p.z - h).max(0.0);
    (a * a + b * b + c * c).sqrt()
}

#[test]
fn flat_roof_cylinder_counts_areas_layers() {
    let (r, h, dx) = (0.5, 1.0, 0.04);
    let s = CylinderTank::new(r, h, 0.5, Roof::Flat).build(dx).unwrap();
    // depth 0.5 = 12.5 rows: the rows with centres below 0.5 fill to 0.48
    assert!((s.fill_level - 0.48).abs() < 1e-12);
    let expected = PI * r * r * 0.48 / dx.powi(3);
    let n = s.fluid_positions.len() as f64;
    assert!(rel(n, expected) < 0.03, "fluid {n} vs {expected}");
    assert_eq!(s.part_names, vec!["bottom", "wall", "roof"]);
    for p in &s.fluid_positions {
        assert!(p.x * p.x + p.y * p.y <= r * r && p.z > 0.0 && p.z < 0.48);
        assert!(s.interior.contains(p));
    }
    for p in &s.wall_positions {
        assert!(!s.interior.contains(p));
        let d = cyl_outside_distance(p, r, h);
        assert!(
            d > 0.0 && d <= 3.0 * dx + 1e-6 * dx + 1e-3 * dx,
            "wall point {p} at {d}"
        );
    }
    assert!(rel(part_area(&s, 0), PI * r * r) < 1e-9);
    assert!(rel(part_area(&s, 1), 2.0 * PI * r * h) < 1e-9);
    assert!(rel(part_area(&s, 2), PI * r * r) < 1e-9);
    for part in 0..3u16 {
        for layer in 1..=3u8 {
            let c = (0..s.wall_positions.len())
                .filter(|&w| s.wall_part[w] == part && s.wall_layer[w] == layer)
                .count();
            assert!(c > 100, "part {part} layer {layer}: {c}");
        }
    }
    for w in 0..s.wall_positions.len() {
        let p = s.wall_positions[w];
        let n = s.wall_normal[w];
        assert!((n.norm() - 1.0).abs() < 1e-9);
        if s.wall_layer[w] > 1 {
            assert_eq!(s.wall_area[w], 0.0);
        }
        let rr = (p.x * p.x + p.y * p.y).sqrt();
        match s.wall_part[w] {
            0 => {
                assert!(p.z < 0.0);
                if rr < r - dx {
                    assert!((n - Vector3::new(0.0, 0.0, -1.0)).norm() < 1e-9);
                }
            }
            2 => assert!(p.z > h),
            1 => {
                let radial = Vector3::new(p.x / rr, p.y / rr, 0.0);
                assert!(n.dot(&radial) > 0.99, "wall normal {n} at {p}");
            }
            _ => unreachable!(),
        }
    }
    // interior box
    assert_eq!(s.interior_min, Vector3::new(-r, -r, 0.0));
    assert!((s.interior_max.z - h).abs() < 1e-12);
}

#[test]
fn full_cylinder_has_no_gaps_in_the_wall() {
    let (r, h, dx) = (0.3, 0.4, 0.03);
    let s = CylinderTank::new(r, h, h, Roof::Flat).build(dx).unwrap();
    let eps = 0.01 * dx;
    let mut points = Vec::new();
    for k in 0..24 {
        let a = 2.0 * PI * k as f64 / 24.0 + 0.1;
        let (sn, cs) = a.sin_cos();
        for z in [eps, 0.1, 0.2, 0.3, h - eps] {
            points.push(Vector3::new((r - eps) * cs, (r - eps) * sn, z));
        }
        for rr in [0.0, 0.1, 0.2] {
            points.push(Vector3::new(rr * cs, rr * sn, eps));
            points.push(Vector3::new(rr * cs, rr * sn, h - eps));
        }
    }
    let mut min = f64::MAX;
    for x in &points {
        let ks = kernel_sum(&s, *x);
        min = min.min(ks);
        assert!(ks >= 0.95, "kernel sum {ks} at {x}");
    }
    println!("min kernel sum on the cylinder boundary: {min}");
}

#[test]
fn cone_roof_areas_and_full_kernel() {
    let (r, h, apex, dx) = (0.3, 0.3, 0.15, 0.03);
    let s = CylinderTank::new(r, h, h + apex, Roof::Cone { apex_height: apex })
        .build(dx)
        .unwrap();
    assert!(rel(part_area(&s, 2), PI * r * (r * r + apex * apex).sqrt()) < 1e-9);
    assert!(rel(part_area(&s, 1), 2.0 * PI * r * h) < 1e-9);
    assert!(rel(part_area(&s, 0), PI * r * r) < 1e-9);
    // points just inside the cone
    let eps = 0.01 * dx;
    let slope_len = (r * r + apex * apex).sqrt();
    let inward = [-apex / slope_len, -r / slope_len]; // (dr, dz) into the liquid
    let mut min = f64::MAX;
    for k in 0..16 {
        let a = 2.0 * PI * k as f64 / 16.0 + 0.05;
        let (sn, cs) = a.sin_cos();
        for t in [0.05, 0.3, 0.5, 0.7, 0.9] {
            let rr = r * (1.0 - t) + inward[0] * eps;
            let z = h + apex * t + inward[1] * eps;
            let x = Vector3::new(rr * cs, rr * sn, z);
            assert!(s.interior.contains(&x));
            let ks = kernel_sum(&s, x);
            min = min.min(ks);
            assert!(ks >= 0.95, "kernel sum {ks} at {x}");
        }
    }
    println!("min kernel sum under the cone: {min}");
    // roof particles lie above the shell top or beside the rim
    let maxd = s
        .wall_positions
        .iter()
        .zip(&s.wall_part)
        .filter(|(_, p)| **p == 2)
        .map(|(p, _)| p.z)
        .fold(f64::MIN, f64::max);
    assert!(maxd <= h + apex + 3.0 * dx + 1e-9);
    for l in 1..=3u8 {
        assert!(s
            .wall_layer
            .iter()
            .zip(&s.wall_part)
            .any(|(a, p)| *a == l && *p == 2));
    }
}

#[test]
fn dome_roof_area() {
    let (r, h, rise, dx) = (0.4, 0.5, 0.1, 0.04);
    let s = CylinderTank::new(r, h, 0.3, Roof::Dome { rise })
        .build(dx)
        .unwrap();
    assert!(rel(part_area(&s, 2), PI * (r * r + rise * rise)) < 1e-9);
    assert!(s
        .interior
        .contains(&Vector3::new(0.0, 0.0, h + rise - 0.001)));
    assert!(!s
        .interior
        .contains(&Vector3::new(0.0, 0.0, h + rise + 0.001)));
    assert!((s.interior_max.z - (h + rise)).abs() < 1e-9);
}

#[test]
fn open_cylinder_has_no_roof() {
    let (r, h, dx) = (0.4, 0.6, 0.04);
    let s = CylinderTank::new(r, h, 0.4, Roof::None).build(dx).unwrap();
    assert!(!s.wall_part.contains(&2));
    assert!(s.wall_positions.iter().all(|p| p.z < h));
    assert!(rel(part_area(&s, 1), 2.0 * PI * r * h) < 1e-9);
    assert_eq!(part_area(&s, 2), 0.0);
    assert!(s.interior.contains(&Vector3::new(0.0, 0.0, 50.0)));
    assert!(!s.interior.contains(&Vector3::new(0.0, r + 0.01, 50.0)));
    assert!((s.interior_max.z - h).abs() < 1e-12);
}

#[test]
fn tilted_cylinder_surface() {
    let (r, dx) = (0.4, 0.04);
    let flat = CylinderTank::new(r, 0.8, 0.4, Roof::Flat)
        .build(dx)
        .unwrap();
    let tilt = CylinderTank::new(r, 0.8, 0.4, Roof::Flat)
        .with_initial_tilt(0.1)
        .build(dx)
        .unwrap();
    let (a, b) = (
        flat.fluid_positions.len() as f64,
        tilt.fluid_positions.len() as f64,
    );
    assert!(rel(b, a) < 0.02, "{a} vs {b}");
    let top = |x0: f64| {
        tilt.fluid_positions
            .iter()
            .filter(|p| (p.x - x0).abs() < 0.1 * dx && p.y.abs() < 0.6 * dx)
            .map(|p| p.z)
            .fold(f64::MIN, f64::max)
    };
    assert!(top(-0.38) > top(0.38) + 0.15);
}

#[test]
fn box_tank_matches_2d_block() {
    let (w, b, h, d, dx) = (1.0, 0.2, 0.6, 0.5, 0.05);
    let s = BoxTank::new(w, b, h, d).build(dx).unwrap();
    assert_eq!(s.fluid_positions.len(), 20 * 4 * 10);
    assert!(rel(part_area(&s, 0), w * b) < 1e-9);
    assert!(rel(part_area(&s, 1), 2.0 * (w + b) * h) < 1e-9);
    assert!(rel(part_area(&s, 2), w * b) < 1e-9);
    // wall particles: Euclidean 3-layer shell of the box
    for p in &s.wall_positions {
        let ox = (-p.x).max(p.x - w).max(0.0);
        let oy = (-p.y).max(p.y - b).max(0.0);
        let oz = (-p.z).max(p.z - h).max(0.0);
        let dist = (ox * ox + oy * oy + oz * oz).sqrt();
        assert!(dist > 0.0 && dist <= 3.0 * dx + 1e-9);
    }
    // a face particle below the floor, away from the edges, carries dx² of area
    let k = s
        .wall_positions
        .iter()
        .position(|p| {
            (p.x - 0.525).abs() < 1e-9 && (p.y - 0.075).abs() < 1e-9 && (p.z + 0.025).abs() < 1e-9
        })
        .unwrap();
    assert_eq!(s.wall_part[k], 0);
    assert!(rel(s.wall_area[k], dx * dx) < 1e-9, "{}", s.wall_area[k]);
    // bottom-edge corner point (-dx/2, y, -dx/2): tie goes to the wall, as in 2D
    let k = s
        .wall_positions
        .iter()
        .position(|p| {
            (p.x + 0.025).abs() < 1e-9 && (p.y - 0.075).abs() < 1e-9 && (p.z + 0.025).abs() < 1e-9
        })
        .unwrap();
    assert_eq!(s.wall_part[k], 1);
    assert!((s.wall_normal[k] - Vector3::new(-1.0, 0.0, 0.0)).norm() < 1e-9);
    // top-edge corner point: tie goes to the roof
    let k = s
        .wall_positions
        .iter()
        .position(|p| {
            (p.x + 0.025).abs() < 1e-9 && (p.y - 0.075).abs() < 1e-9 && (p.z - 0.625).abs() < 1e-9
        })
        .unwrap();
    assert_eq!(s.wall_part[k], 2);
}

/// (The ring is 2 dx high, the thinnest solid allowed.)
#[test]
fn column_and_ring_solids() {
    let (r, h, dx) = (0.5, 0.6, 0.04);
    let s = CylinderTank::new(r, h, 0.4, Roof::Flat)
        .with_solid(InternalSolid::column("column", [0.0, 0.0], 0.1, -0.1, 0.7))
        .with_solid(InternalSolid::ring("baffle", 0.35, 0.55, 0.2, 0.28))
        .build(dx)
        .unwrap();
    assert_eq!(
        s.part_names,
        vec!["bottom", "wall", "roof", "column", "baffle"]
    );
    for p in &s.fluid_positions {
        let rr = (p.x * p.x + p.y * p.y).sqrt();
        assert!(rr > 0.1);
        assert!(!(rr >= 0.35 && p.z >= 0.2 && p.z <= 0.28));
        assert!(s.interior.contains(p));
    }
    let column: Vec<usize> = (0..s.wall_positions.len())
        .filter(|&w| s.wall_part[w] == 3)
        .collect();
    assert!(!column.is_empty());
    for &w in &column {
        let p = s.wall_positions[w];
        let rr = (p.x * p.x + p.y * p.y).sqrt();
        assert!(rr < 0.1 && rr >= 0.1 - 3.0 * dx - 1e-9);
        let n = s.wall_normal[w];
        if p.z > 0.1 && p.z < 0.5 {
            assert!(
                n.dot(&Vector3::new(-p.x / rr, -p.y / rr, 0.0)) > 0.99,
                "{n}"
            );
        }
    }
    // wetted column area: lateral surface from the floor to the roof
    let col_area = part_area(&s, 3);
    assert!(rel(col_area, 2.0 * PI * 0.1 * h) < 0.01, "{col_area}");
    // ring wetted area: top + bottom annuli (0.35..0.5) + inner rim
    let ring_area = part_area(&s, 4);
    let expect = 2.0 * PI * (0.5f64.powi(2) - 0.35f64.powi(2)) + 2.0 * PI * 0.35 * 0.08;
    assert!(rel(ring_area, expect) < 0.01, "{ring_area} vs {expect}");
    // the shell behind the ring is not wetted
    assert!(rel(part_area(&s, 1), 2.0 * PI * r * (h - 0.08)) < 0.01);
}

#[test]
fn mesh_roof_from_file_matches_cone() {
    let dir = temp_dir("cone");
    let path = dir.join("cone.obj");
    let (r, h, apex, dx) = (0.3, 0.3, 0.1, 0.03);
    let written =
        cylinder_roof_mesh_obj(&path, r, h, Roof::Cone { apex_height: apex }, 0.01).unwrap();
    written.check_closed("generated").unwrap();
    let read = SurfaceMesh::read(&path).unwrap();
    assert_eq!(read.triangles.len(), written.triangles.len());
    let from_mesh = CylinderTank::new(r, h, 0.3, Roof::Mesh(path.clone()))
        .build(dx)
        .unwrap();
    let analytic = CylinderTank::new(r, h, 0.3, Roof::Cone { apex_height: apex })
        .build(dx)
        .unwrap();
    assert_eq!(
        from_mesh.fluid_positions.len(),
        analytic.fluid_positions.len()
    );
    let d = from_mesh.wall_positions.len() as f64 - analytic.wall_positions.len() as f64;
    assert!(d.abs() / (analytic.wall_positions.len() as f64) < 0.01);
    assert!(
        rel(
            part_area(&from_mesh, 2),
            PI * r * (r * r + apex * apex).sqrt()
        ) < 1e-3
    );
    // the mesh interior is used for containment
    assert!(from_mesh
        .interior
        .contains(&Vector3::new(0.0, 0.0, h + apex - 0.01)));
    assert!(!from_mesh
        .interior
        .contains(&Vector3::new(0.0, 0.0, h + apex + 0.01)));
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn open_or_flipped_mesh_is_refused_with_the_file_name() {
    let dir = temp_dir("bad");
    let good = dir.join("good.obj");
    let mesh = cylinder_roof_mesh_obj(&good, 0.3, 0.3, Roof::Flat, 0.05).unwrap();
    // open: drop one triangle
    let mut open = mesh.clone();
    open.triangles.pop();
    let open_path = dir.join("open_roof.obj");
    open.write_obj(&open_path, "open").unwrap();
    let e = match CylinderTank::new(0.3, 0.3, 0.2, Roof::Mesh(open_path.clone())).build(0.03) {
        Err(e) => e,
        Ok(_) => panic!("open mesh accepted"),
    };
    assert!(
        matches!(e, GeometryError::MeshNotWatertight { open_edges: 3, .. }),
        "{e}"
    );
    assert!(e.to_string().contains("open_roof.obj"), "{e}");
    assert!(e.to_string().contains("3 open edge"), "{e}");
    // one flipped triangle
    let mut flipped = mesh.clone();
    flipped.triangles[5].swap(1, 2);
    let flipped_path = dir.join("flipped.obj");
    flipped.write_obj(&flipped_path, "flipped").unwrap();
    let e = match CylinderTank::new(0.3, 0.3, 0.2, Roof::Mesh(flipped_path)).build(0.03) {
        Err(e) => e,
        Ok(_) => panic!("flipped mesh accepted"),
    };
    assert!(
        matches!(
            e,
            GeometryError::MeshInconsistentOrientation { edges: 3, .. }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("flipped.obj"));
    // missing file
    let e = SurfaceMesh::read(&dir.join("nope.stl")).unwrap_err();
    assert!(e.to_string().contains("nope.stl"));
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn stl_ascii_and_binary_round_trip() {
    let dir = temp_dir("stl");
    let mesh = slosh_geometry::box_mesh([0.0; 3], [1.0, 0.5, 0.25], 0.25);
    mesh.check_closed("box").unwrap();
    assert!(rel(mesh.signed_volume(), 0.125) < 1e-12);
    // ASCII
    let mut text = String::from("solid box\n");
    let mut bin = vec![0u8; 80];
    bin.extend_from_slice(&(mesh.triangles.len() as u32).to_le_bytes());
    for t in &mesh.triangles {
        text.push_str("facet normal 0 0 0\nouter loop\n");
        bin.extend_from_slice(&[0u8; 12]);
        for &i in t {
            let v = mesh.vertices[i as usize];
            text.push_str(&format!("vertex {} {} {}\n", v[0], v[1], v[2]));
            for c in v {
                bin.extend_from_slice(&(c as f32).to_le_bytes());
            }
        }
        text.push_str("endloop\nendfacet\n");
        bin.extend_from_slice(&[0u8; 2]);
    }
    text.push_str("endsolid box\n");
    std::fs::write(dir.join("a.stl"), text).unwrap();
    std::fs::write(dir.join("b.stl"), bin).unwrap();
    for name in ["a.stl", "b.stl"] {
        let m = SurfaceMesh::read(&dir.join(name)).unwrap();
        m.check_closed(name).unwrap();
        assert_eq!(m.vertices.len(), mesh.vertices.len());
        assert!(rel(m.signed_volume(), 0.125) < 1e-6);
    }
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn errors_3d() {
    let e = CylinderTank::new(0.5, 0.6, 0.7, Roof::None)
        .build(0.02)
        .err()
        .unwrap();
    assert_eq!(
        e.to_string(),
        "fill depth 0.7 m is above the tank height 0.6 m"
    );
    let e = CylinderTank::new(0.5, 1.0, 0.5, Roof::Flat)
        .build(2.0)
        .err()
        .unwrap();
    assert_eq!(
        e.to_string(),
        "dx 2 m is larger than the tank (radius 0.5 m)"
    );
    let e = CylinderTank::new(0.5, 1.0, 0.5, Roof::Dome { rise: 0.7 })
        .build(0.05)
        .err()
        .unwrap();
    assert!(e.to_string().contains("dome roof rise 0.7 m"), "{e}");
    let e = CylinderTank::new(-1.0, 1.0, 0.5, Roof::Flat)
        .build(0.05)
        .err()
        .unwrap();
    assert_eq!(e.to_string(), "tank radius must be > 0 (got -1)");
    let e = BoxTank::new(1.0, 0.33, 1.0, 0.5).build(0.02).err().unwrap();
    assert!(e.to_string().contains("tank breadth 0.33 m"), "{e}");
}

/// Timing is only meaningful in release builds (`cargo test --release`).
#[test]
#[cfg_attr(debug_assertions, ignore)]
fn half_million_particles_in_seconds() {
    let t = Instant::now();
    let s = CylinderTank::new(0.5, 0.8, 0.6, Roof::Cone { apex_height: 0.1 })
        .build(0.0095)
        .unwrap();
    let secs = t.elapsed().as_secs_f64();
    let n = s.fluid_positions.len() + s.wall_positions.len();
    println!(
        "{n} particles ({} fluid) in {secs:.2} s",
        s.fluid_positions.len()
    );
    assert!(n > 450_000);
    assert!(secs < 30.0);
}

/// Regenerates the example meshes in `geometry/` (run with `--ignored`).
#[test]
#[ignore]
fn write_example_meshes() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../geometry");
    let cone = cylinder_roof_mesh_obj(
        &dir.join("cylinder_R0.5_H1.0_cone_roof.obj"),
        0.5,
        1.0,
        Roof::Cone { apex_height: 0.2 },
        0.1,
    )
    .unwrap();
    cone.check_closed("cone").unwrap();
    let dome = cylinder_roof_mesh_obj(
        &dir.join("cylinder_R0.5_H1.0_dome_roof.obj"),
        0.5,
        1.0,
        Roof::Dome { rise: 0.15 },
        0.1,
    )
    .unwrap();
    dome.check_closed("dome").unwrap();
}

#[test]
fn example_meshes_in_the_repository_build() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../geometry");
    let path = dir.join("cylinder_R0.5_H1.0_cone_roof.obj");
    if !path.exists() {
        return;
    }
    let s = CylinderTank::new(0.5, 1.0, 0.5, Roof::Mesh(path))
        .build(0.05)
        .unwrap();
    let cone = CylinderTank::new(0.5, 1.0, 0.5, Roof::Cone { apex_height: 0.2 })
        .build(0.05)
        .unwrap();
    assert_eq!(s.fluid_positions.len(), cone.fluid_positions.len());
    assert!(rel(part_area(&s, 2), PI * 0.5 * (0.25f64 + 0.04).sqrt()) < 2e-3);
}

/// A tilt smaller than the spacing still tilts the lattice surface: error diffusion gives the
/// left half more liquid than the right (here a quarter-spacing tilt at dx = 0.04 m).
#[test]
fn sub_spacing_tilt_moves_liquid_to_the_left() {
    use slosh_geometry::{CylinderTank, Roof};
    let dx = 0.04;
    let flat = CylinderTank::new(0.5, 0.6, 0.5, Roof::None)
        .build(dx)
        .unwrap();
    let tilted = CylinderTank::new(0.5, 0.6, 0.5, Roof::None)
        .with_initial_tilt(0.01)
        .build(dx)
        .unwrap();
    let left = |s: &slosh_core::ParticleSetup<3>| {
        s.fluid_positions.iter().filter(|p| p.x < 0.0).count() as f64
    };
    let right = |s: &slosh_core::ParticleSetup<3>| {
        s.fluid_positions.iter().filter(|p| p.x > 0.0).count() as f64
    };
    eprintln!(
        "flat {} / {}, tilted {} / {}",
        left(&flat),
        right(&flat),
        left(&tilted),
        right(&tilted)
    );
    // Expected excess volume on the left: ∫ tilt·(−x/R) over the left half-disc ≈ (2/3) tilt R²,
    // i.e. ≈ 26 particles of dx³ at these numbers; accept 10–45 (staircase rounding).
    let excess = (left(&tilted) - right(&tilted)) / 2.0;
    assert!((10.0..=45.0).contains(&excess), "excess {excess}");
}

#[test]
fn sphere_parts_are_the_zones_and_half_full_holds_half_the_volume() {
    let (r, dx) = (1.0, 0.1);
    let s = SphereTank::new(r, r).build(dx).unwrap();
    // polar caps above ±45°: 2πR²(1 − 1/√2); the zone between: 2√2 πR² (exact by rescaling)
    let cap = 2.0 * PI * r * r * (1.0 - std::f64::consts::FRAC_1_SQRT_2);
    let exact = [cap, 4.0 * PI * r * r - 2.0 * cap, cap];
    for (p, a) in exact.iter().enumerate() {
        assert!(rel(part_area(&s, p as u16), *a) < 1e-9, "part {p}");
    }
    // half full: the particles stand for (2/3)πR³ within 2 % at R/dx = 10
    let volume = s.fluid_positions.len() as f64 * dx.powi(3);
    assert!(rel(volume, 2.0 / 3.0 * PI * r.powi(3)) < 0.02, "{volume}");
    // every wall particle is outside the sphere, within 3 dx of it, its normal radial
    let centre = Vector3::new(0.0, 0.0, r);
    for (x, n) in s.wall_positions.iter().zip(&s.wall_normal) {
        let d = (x - centre).norm() - r;
        assert!(d > 0.0 && d <= 3.0 * dx + 1e-6, "{d}");
        assert!((x - centre).normalize().dot(n) > 0.95);
    }
    assert!(SphereTank::new(r, 2.5).build(dx).is_err());
    assert!(SphereTank::new(-1.0, 0.5).build(dx).is_err());
}

/// The polar lattice ([`CylinderLattice::Polar`]): beside the shell every wall particle lies
/// on the ring of its layer, R + (k − ½)dx (to rounding, 1e-12 m), with a radial normal and
/// neighbours dx apart along the ring to within the rounding of 2πr/dx to whole points
/// (≤ dx/(2 · 2πR/dx) ≈ 1.3 % here); the liquid holds the cubic build's volume to within one
/// particle per ring and column rounding (0.5 %), lies inside the radius and below the fill
/// level; the part areas are the exact ones; and the kernel of a point just inside the shell
/// sees a full support (≥ 0.95, the bound the cubic lattice meets above).
#[test]
fn polar_lattice_fits_the_shell() {
    let (r, h, depth, dx, layers) = (0.5, 0.6, 0.5, 0.04, 4u8);
    let cubic = CylinderTank::new(r, h, depth, Roof::Flat)
        .with_layers(layers)
        .build(dx)
        .unwrap();
    let polar = CylinderTank::new(r, h, depth, Roof::Flat)
        .with_layers(layers)
        .with_lattice(CylinderLattice::Polar)
        .build(dx)
        .unwrap();
    let exact = PI * r * r * polar.fill_level / dx.powi(3);
    let count = polar.fluid_positions.len() as f64;
    assert!(rel(count, exact) < 0.005, "{count} particles for {exact}");
    println!(
        "liquid particles: polar {count}, cubic {}, πR²·level/dx³ = {exact:.0}",
        cubic.fluid_positions.len()
    );
    for p in &polar.fluid_positions {
        assert!((p.x * p.x + p.y * p.y).sqrt() < r && p.z > 0.0 && p.z < polar.fill_level);
    }
    assert!(rel(part_area(&polar, 0), PI * r * r) < 1e-9);
    assert!(rel(part_area(&polar, 1), 2.0 * PI * r * h) < 1e-9);
    assert!(rel(part_area(&polar, 2), PI * r * r) < 1e-9);
    let mut beside = 0;
    for (w, p) in polar.wall_positions.iter().enumerate() {
        let radius = (p.x * p.x + p.y * p.y).sqrt();
        if !(p.z > 0.0 && p.z < h && radius > r) {
            continue;
        }
        beside += 1;
        let layer = polar.wall_layer[w];
        assert!(
            (radius - (r + (layer as f64 - 0.5) * dx)).abs() < 1e-12,
            "{p} layer {layer}"
        );
        assert_eq!(polar.wall_part[w], 1);
        let radial = Vector3::new(p.x / radius, p.y / radius, 0.0);
        assert!((polar.wall_normal[w] - radial).norm() < 1e-12);
        let nearest = polar
            .wall_positions
            .iter()
            .filter(|q| (q.z - p.z).abs() < 1e-12 && *q != p)
            .map(|q| (q - p).norm())
            .fold(f64::INFINITY, f64::min);
        assert!(
            (nearest / dx - 1.0).abs() < 0.013,
            "ring spacing {nearest} at {p}"
        );
    }
    let rows = (h / dx).round() as usize;
    let per_row: usize = (1..=layers)
        .map(|k| (2.0 * PI * (r + (k as f64 - 0.5) * dx) / dx).round() as usize)
        .sum();
    assert_eq!(beside, rows * per_row);
    let mut min = f64::INFINITY;
    for a in 0..36 {
        let (sn, cs) = (a as f64 * PI / 18.0 + 0.01).sin_cos();
        for z in [0.1, 0.2, 0.3] {
            let x = Vector3::new((r - 0.25 * dx) * cs, (r - 0.25 * dx) * sn, z);
            let ks = kernel_sum(&polar, x);
            min = min.min(ks);
            assert!(ks >= 0.95, "kernel sum {ks} at {x}");
        }
    }
    println!("min kernel sum inside the polar shell: {min}");
    // A meshed tank has no analytic shell to fit; internal solids stand on the cubic lattice.
    let mesh = CylinderTank::new(r, h, depth, Roof::Mesh(PathBuf::from("any.obj")))
        .with_lattice(CylinderLattice::Polar)
        .build(dx)
        .err();
    assert!(
        matches!(mesh, Some(GeometryError::InvalidShape(_))),
        "{mesh:?}"
    );
    let column = CylinderTank::new(r, h, depth, Roof::Flat)
        .with_lattice(CylinderLattice::Polar)
        .with_solid(InternalSolid::column("column", [0.0, 0.0], 0.1, 0.0, h))
        .build(dx)
        .err();
    assert!(
        matches!(column, Some(GeometryError::InvalidShape(_))),
        "{column:?}"
    );
}

/// Liquid filled above the shell top into a cone roof: the polar lattice's columns stop at the
/// roof as the cubic lattice's do, and the liquid holds the cylinder and the cone frustum below
/// the fill level (exact volume; the lattice rounds each column at the slanted roof to the
/// nearest row, an error of a fraction of a cell per column that averages out over the rings).
#[test]
fn polar_lattice_fills_into_a_cone_roof() {
    let (r, h, rise, depth, dx) = (0.5, 0.4, 0.2, 0.5, 0.025);
    let build = |lattice| {
        CylinderTank::new(r, h, depth, Roof::Cone { apex_height: rise })
            .with_layers(4)
            .with_lattice(lattice)
            .build(dx)
            .unwrap()
    };
    let (polar, cubic) = (build(CylinderLattice::Polar), build(CylinderLattice::Cubic));
    let level = polar.fill_level;
    // The cone's radius at height z above the shell top: R (1 − (z − h)/rise).
    let top = r * (1.0 - (level - h) / rise);
    let exact = PI * r * r * h + PI / 3.0 * (level - h) * (r * r + r * top + top * top);
    let volume = |s: &ParticleSetup<3>| s.fluid_positions.len() as f64 * dx.powi(3);
    println!(
        "fill level {level} m: exact {exact:.5} m³, polar {:.5}, cubic {:.5}",
        volume(&polar),
        volume(&cubic)
    );
    assert!(rel(volume(&polar), exact) < 0.01);
    for p in &polar.fluid_positions {
        let radius = (p.x * p.x + p.y * p.y).sqrt();
        let roof = h + rise * (1.0 - radius / r);
        assert!(radius < r && p.z > 0.0 && p.z < level.min(roof), "{p}");
    }
}
