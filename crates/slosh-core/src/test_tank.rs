//! A minimal closed box tank (offset lattice) for the solver's own unit tests; the real
//! tank builders live in `slosh-geometry`.

use crate::setup::{ParticleSetup, TankInterior};
use crate::sim::Vector;

struct BoxInterior<const D: usize> {
    lo: Vector<D>,
    hi: Vector<D>,
}

impl<const D: usize> TankInterior<D> for BoxInterior<D> {
    fn contains(&self, p: &Vector<D>) -> bool {
        (0..D).all(|k| p[k] >= self.lo[k] && p[k] <= self.hi[k])
    }
}

/// Closed box [0, size] with liquid up to `depth` (surface tilted by `tilt` m at x = 0),
/// three wall layers, lattice spacing dx.
pub fn box_tank<const D: usize>(
    size: [f64; D],
    depth: f64,
    tilt: f64,
    dx: f64,
) -> ParticleSetup<D> {
    box_tank_with_layers(size, depth, tilt, dx, 3)
}

/// [`box_tank`] with as many wall layers as `params` need ([`SphParams::wall_layers`]).
pub fn box_tank_for<const D: usize>(
    params: &crate::SphParams,
    size: [f64; D],
    depth: f64,
    tilt: f64,
    dx: f64,
) -> ParticleSetup<D> {
    box_tank_with_layers(size, depth, tilt, dx, params.wall_layers())
}

/// [`box_tank`] with `layers` wall layers.
pub fn box_tank_with_layers<const D: usize>(
    size: [f64; D],
    depth: f64,
    tilt: f64,
    dx: f64,
    layers: u8,
) -> ParticleSetup<D> {
    let layers = i64::from(layers);
    let mut counts = [0i64; D];
    for k in 0..D {
        counts[k] = (size[k] / dx).round() as i64;
    }
    let mut fluid = Vec::new();
    let mut walls = Vec::new();
    let (mut part, mut normal, mut area, mut layer) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut idx = [-layers; D];
    loop {
        let mut p = Vector::<D>::zeros();
        let mut outside = [0i64; D]; // signed layer distance per axis
        for k in 0..D {
            p[k] = (idx[k] as f64 + 0.5) * dx;
            outside[k] = if idx[k] < 0 {
                idx[k]
            } else if idx[k] >= counts[k] {
                idx[k] - counts[k] + 1
            } else {
                0
            };
        }
        let lay = outside.iter().map(|o| o.abs()).max().unwrap();
        if lay == 0 {
            let surface = depth + tilt * (1.0 - 2.0 * p[0] / size[0]);
            if p[D - 1] < surface {
                fluid.push(p);
            }
        } else {
            walls.push(p);
            // Part/normal from the axis with the largest offset (vertical wins ties).
            let mut axis = D - 1;
            for k in (0..D).rev() {
                if outside[k].abs() == lay {
                    axis = k;
                    break;
                }
            }
            let mut n = Vector::<D>::zeros();
            n[axis] = outside[axis].signum() as f64;
            let pid = if axis == D - 1 {
                if outside[axis] < 0 {
                    0
                } else {
                    2
                }
            } else {
                1
            };
            part.push(pid);
            normal.push(n);
            let face = (0..D).filter(|&k| k != axis).all(|k| outside[k] == 0);
            area.push(if lay == 1 && face {
                dx.powi(D as i32 - 1)
            } else {
                0.0
            });
            layer.push(lay as u8);
        }
        let mut k = 0;
        loop {
            if k == D {
                let mut hi = Vector::<D>::zeros();
                for a in 0..D {
                    hi[a] = size[a];
                }
                return ParticleSetup {
                    spacing: dx,
                    fluid_positions: fluid,
                    wall_positions: walls,
                    wall_part: part,
                    wall_normal: normal,
                    wall_area: area,
                    wall_layer: layer,
                    part_names: vec!["bottom".into(), "wall".into(), "roof".into()],
                    interior_min: Vector::<D>::zeros(),
                    interior_max: hi,
                    fill_level: depth,
                    interior: Box::new(BoxInterior {
                        lo: Vector::<D>::zeros(),
                        hi,
                    }),
                };
            }
            idx[k] += 1;
            if idx[k] < counts[k] + layers {
                break;
            }
            idx[k] = -layers;
            k += 1;
        }
    }
}
