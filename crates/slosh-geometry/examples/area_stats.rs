//! Prints statistics of the innermost-layer wall areas of a cylinder (development aid).
use slosh_geometry::{CylinderTank, Roof};
fn main() {
    let dx = 0.02;
    let s = CylinderTank::new(0.5, 1.0, 0.5, Roof::Cone { apex_height: 0.2 })
        .build(dx)
        .unwrap();
    for part in 0..3u16 {
        let a: Vec<f64> = (0..s.wall_positions.len())
            .filter(|&w| s.wall_part[w] == part && s.wall_layer[w] == 1)
            .map(|w| s.wall_area[w] / (dx * dx))
            .collect();
        let n = a.len() as f64;
        let mean = a.iter().sum::<f64>() / n;
        let zero = a.iter().filter(|&&x| x == 0.0).count();
        let max = a.iter().cloned().fold(0.0, f64::max);
        let sd = (a.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n).sqrt();
        println!(
            "part {part}: {} layer-1, mean {mean:.3} dx², sd {sd:.3}, max {max:.3}, zero {zero}",
            a.len()
        );
    }
}
