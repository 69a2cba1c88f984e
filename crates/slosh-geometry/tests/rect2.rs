//! Tests of the 2D rectangular tank builder.

use nalgebra::Vector2;
use slosh_geometry::{GeometryError, Layout, RectTank2};

fn part_area(setup: &slosh_core::ParticleSetup<2>, part: u16) -> f64 {
    setup
        .wall_part
        .iter()
        .zip(&setup.wall_area)
        .filter(|(p, _)| **p == part)
        .map(|(_, a)| a)
        .sum()
}

fn count_part_layer(setup: &slosh_core::ParticleSetup<2>, part: u16, layer: u8) -> usize {
    setup
        .wall_part
        .iter()
        .zip(&setup.wall_layer)
        .filter(|(p, l)| **p == part && **l == layer)
        .count()
}

#[test]
fn offset_layout_gives_the_exact_block() {
    let setup = RectTank2::new(1.0, 1.0, 0.5).build(0.02).unwrap();
    assert_eq!(setup.fluid_positions.len(), 1250);
    // closed ring around a 50 x 50 interior
    assert_eq!(setup.wall_positions.len(), 56 * 56 - 50 * 50);
    assert_eq!(setup.fill_level, 0.5);
    assert_eq!(setup.interior_min, Vector2::new(0.0, 0.0));
    assert_eq!(setup.interior_max, Vector2::new(1.0, 1.0));
    let ymax = setup
        .fluid_positions
        .iter()
        .map(|p| p.y)
        .fold(f64::MIN, f64::max);
    assert!((ymax - 0.49).abs() < 1e-12);
    for p in &setup.fluid_positions {
        assert!(setup.interior.contains(p));
    }
    for p in &setup.wall_positions {
        assert!(!setup.interior.contains(p));
    }
    // face lengths
    assert!((part_area(&setup, 0) - 1.0).abs() < 1e-12);
    assert!((part_area(&setup, 1) - 2.0).abs() < 1e-12);
    assert!((part_area(&setup, 2) - 1.0).abs() < 1e-12);
    // each side wall separately: H
    let left: f64 = (0..setup.wall_positions.len())
        .filter(|&w| setup.wall_part[w] == 1 && setup.wall_positions[w].x < 0.5)
        .map(|w| setup.wall_area[w])
        .sum();
    assert!((left - 1.0).abs() < 1e-12);
}

#[test]
fn paper_layout_counts_1974() {
    let setup = RectTank2::new(1.0, 1.0, 0.5)
        .with_layout(Layout::Paper)
        .build(0.02)
        .unwrap();
    assert_eq!(setup.fluid_positions.len(), 51 * 26);
    assert_eq!(setup.wall_positions.len(), 57 * 57 - 51 * 51);
    assert_eq!(setup.wall_positions.len(), 648);
    assert_eq!(
        setup.fluid_positions.len() + setup.wall_positions.len(),
        1974
    );
    assert!((setup.fill_level - 0.51).abs() < 1e-12);
    assert!((setup.interior_min.x + 0.01).abs() < 1e-12);
    assert!((setup.interior_max.x - 1.01).abs() < 1e-12);
    assert!((setup.interior_max.y - 1.01).abs() < 1e-12);
    // fluid on x = 0, dx, ..., W and y = 0, ..., depth
    let xmin = setup
        .fluid_positions
        .iter()
        .map(|p| p.x)
        .fold(f64::MAX, f64::min);
    let xmax = setup
        .fluid_positions
        .iter()
        .map(|p| p.x)
        .fold(f64::MIN, f64::max);
    let ymax = setup
        .fluid_positions
        .iter()
        .map(|p| p.y)
        .fold(f64::MIN, f64::max);
    assert!(xmin.abs() < 1e-12 && (xmax - 1.0).abs() < 1e-12 && (ymax - 0.5).abs() < 1e-12);
    // effective face lengths W + dx and H + dx
    assert!((part_area(&setup, 0) - 1.02).abs() < 1e-12);
    assert!((part_area(&setup, 1) - 2.0 * 1.02).abs() < 1e-12);
    assert!((part_area(&setup, 2) - 1.02).abs() < 1e-12);
}

#[test]
fn wall_tags_layers_and_normals() {
    let dx = 0.02;
    let setup = RectTank2::new(1.0, 0.6, 0.5).build(dx).unwrap();
    for l in 1..=3u8 {
        // 50 face points plus the corner points nearer the bottom line (out_x = l > out_y)
        assert_eq!(count_part_layer(&setup, 0, l), 50 + 2 * (l as usize - 1));
    }
    for (k, p) in setup.wall_positions.iter().enumerate() {
        let n = setup.wall_normal[k];
        assert!((n.norm() - 1.0).abs() < 1e-12);
        match setup.wall_part[k] {
            0 => assert_eq!(n, Vector2::new(0.0, -1.0)),
            2 => assert_eq!(n, Vector2::new(0.0, 1.0)),
            1 => assert_eq!(n, Vector2::new(if p.x < 0.5 { -1.0 } else { 1.0 }, 0.0)),
            _ => unreachable!(),
        }
        // max-norm distance from the interior box in cells
        let ox = if p.x < 0.0 {
            -p.x
        } else {
            (p.x - 1.0).max(0.0)
        };
        let oy = if p.y < 0.0 {
            -p.y
        } else {
            (p.y - 0.6).max(0.0)
        };
        let d = ox.max(oy);
        assert_eq!(setup.wall_layer[k] as f64, (d / dx + 0.5).round());
        assert!(d <= 2.5 * dx + 1e-12);
    }
    // corner tie rule: (-dx/2, -dx/2) -> wall, (-dx/2, H + dx/2) -> roof
    let find = |x: f64, y: f64| {
        setup
            .wall_positions
            .iter()
            .position(|p| (p.x - x).abs() < 1e-9 && (p.y - y).abs() < 1e-9)
            .unwrap()
    };
    assert_eq!(setup.wall_part[find(-0.01, -0.01)], 1);
    assert_eq!(setup.wall_part[find(-0.01, 0.61)], 2);
    assert_eq!(setup.wall_part[find(-0.05, -0.01)], 0);
    assert_eq!(setup.wall_part[find(-0.01, -0.05)], 1);
    assert_eq!(setup.wall_area[find(-0.01, -0.01)], 0.0);
}

#[test]
fn open_tank_has_no_roof_and_walls_to_the_shell_top() {
    let setup = RectTank2::new(1.0, 0.8, 0.5)
        .with_roof(false)
        .build(0.02)
        .unwrap();
    assert_eq!(count_part_layer(&setup, 2, 1), 0);
    let ytop = setup
        .wall_positions
        .iter()
        .map(|p| p.y)
        .fold(f64::MIN, f64::max);
    assert!((ytop - 0.79).abs() < 1e-12);
    assert!((part_area(&setup, 1) - 1.6).abs() < 1e-12);
    assert!((part_area(&setup, 0) - 1.0).abs() < 1e-12);
    assert!(setup.interior.contains(&Vector2::new(0.5, 100.0)));
    assert!(!setup.interior.contains(&Vector2::new(-0.01, 100.0)));
    assert!((setup.interior_max.y - 0.8).abs() < 1e-12);
}

#[test]
fn tilt_preserves_volume_and_slope() {
    let flat = RectTank2::new(1.0, 1.0, 0.5).build(0.02).unwrap();
    let tilted = RectTank2::new(1.0, 1.0, 0.5)
        .with_initial_tilt(0.05)
        .build(0.02)
        .unwrap();
    assert_eq!(flat.fluid_positions.len(), tilted.fluid_positions.len());
    let top_left = tilted
        .fluid_positions
        .iter()
        .filter(|p| p.x < 0.02)
        .map(|p| p.y)
        .fold(f64::MIN, f64::max);
    let top_right = tilted
        .fluid_positions
        .iter()
        .filter(|p| p.x > 0.98)
        .map(|p| p.y)
        .fold(f64::MIN, f64::max);
    assert!(top_left > 0.529 && top_left < 0.55, "{top_left}");
    assert!(top_right > 0.43 && top_right < 0.46, "{top_right}");
}

#[test]
fn fill_depth_not_a_multiple_is_rounded_to_rows() {
    let lat = RectTank2::new(1.0, 1.0, 0.55).lattice(0.04).unwrap();
    // rows with centre below 0.55: 0.02, 0.06, ..., 0.54 -> 14 rows, level 0.56
    assert_eq!(lat.rows_fluid, 14);
    assert!((lat.fill_level - 0.56).abs() < 1e-12);
}

#[test]
fn clear_errors() {
    let e = err(RectTank2::new(0.0, 1.0, 0.5).build(0.02));
    assert_eq!(e.to_string(), "tank width must be > 0 (got 0)");
    let e = err(RectTank2::new(1.0, 0.6, 0.7).build(0.02));
    assert_eq!(
        e.to_string(),
        "fill depth 0.7 m is above the tank height 0.6 m"
    );
    let e = err(RectTank2::new(1.0, 3.0, 2.5).build(2.0));
    assert_eq!(e.to_string(), "dx 2 m is larger than the tank (width 1 m)");
    let e = err(RectTank2::new(1.01, 1.0, 0.5).build(0.02));
    assert!(
        matches!(e, GeometryError::NotMultipleOfSpacing { .. }),
        "{e}"
    );
    assert!(e.to_string().contains("tank width 1.01 m"), "{e}");
    let e = err(RectTank2::new(f64::NAN, 1.0, 0.5).build(0.02));
    assert!(e.to_string().contains("finite"), "{e}");
    let e = err(RectTank2::new(1.0, 1.0, 0.5)
        .with_initial_tilt(0.6)
        .build(0.02));
    assert!(matches!(e, GeometryError::TiltTooLarge { .. }), "{e}");
    let e = err(RectTank2::new(1.0, 1.0, 0.5).with_layers(0).build(0.02));
    assert!(matches!(e, GeometryError::BadLayers(0)));
}

fn err<T>(r: Result<T, GeometryError>) -> GeometryError {
    match r {
        Ok(_) => panic!("expected an error"),
        Err(e) => e,
    }
}

/// Cubic B-spline kernel, 2D normalisation 10/(7π h²).
fn kernel2(r: f64, h: f64) -> f64 {
    let q = r / h;
    let sigma = 10.0 / (7.0 * std::f64::consts::PI * h * h);
    if q < 1.0 {
        sigma * (1.0 - 1.5 * q * q + 0.75 * q * q * q)
    } else if q < 2.0 {
        sigma * 0.25 * (2.0 - q).powi(3)
    } else {
        0.0
    }
}

#[test]
fn full_tank_wall_has_no_gaps_in_2d() {
    for layout in [Layout::Offset, Layout::Paper] {
        let dx = 0.02;
        let s = RectTank2::new(0.4, 0.3, 0.3)
            .with_layout(layout)
            .build(dx)
            .unwrap();
        let (lo, hi) = (s.interior_min, s.interior_max);
        let e = 0.01 * dx;
        let mut pts = vec![
            Vector2::new(lo.x + e, lo.y + e),
            Vector2::new(hi.x - e, lo.y + e),
            Vector2::new(lo.x + e, hi.y - e),
            Vector2::new(hi.x - e, hi.y - e),
        ];
        for k in 1..10 {
            let t = k as f64 / 10.0;
            pts.push(Vector2::new(lo.x + t * (hi.x - lo.x), lo.y + e));
            pts.push(Vector2::new(lo.x + t * (hi.x - lo.x), hi.y - e));
            pts.push(Vector2::new(lo.x + e, lo.y + t * (hi.y - lo.y)));
        }
        for x in pts {
            let sum: f64 = s
                .fluid_positions
                .iter()
                .chain(&s.wall_positions)
                .map(|p| dx * dx * kernel2((p - x).norm(), 1.3 * dx))
                .sum();
            assert!(sum >= 0.95, "{layout:?}: kernel sum {sum} at {x}");
        }
    }
}
