//! What a tank builder hands to the solver: the initial particles, their wall tags,
//! and the few facts about the tank interior that measurements need.

use nalgebra::SVector;

/// The tank interior seen as a region of space (implemented by `slosh-geometry`).
pub trait TankInterior<const D: usize>: Send + Sync {
    /// True when `point` (m) lies inside the liquid-holding interior of the tank
    /// (open tanks: the interior extended upwards without limit).
    fn contains(&self, point: &SVector<f64, D>) -> bool;

    /// Distance (m) from `point` to the interior: 0 inside, else the distance to the nearest
    /// interior point. The default knows only inside (0) and outside (∞).
    fn distance_outside(&self, point: &SVector<f64, D>) -> f64 {
        if self.contains(point) {
            0.0
        } else {
            f64::INFINITY
        }
    }
}

/// Name of the part index `0`: the tank floor.
pub const PART_BOTTOM: &str = "bottom";
/// Name of the part index `1`: the side wall(s).
pub const PART_WALL: &str = "wall";
/// Name of the part index `2`: the fixed roof.
pub const PART_ROOF: &str = "roof";

/// Initial particles of a tank, produced by `slosh-geometry`.
///
/// The vertical axis is the last coordinate, up positive. All lengths in m.
pub struct ParticleSetup<const D: usize> {
    /// Lattice spacing dx (m); every particle stands for a dx^D cell of fluid.
    pub spacing: f64,
    /// Initial fluid particle positions (m).
    pub fluid_positions: Vec<SVector<f64, D>>,
    /// Fixed wall particle positions (m).
    pub wall_positions: Vec<SVector<f64, D>>,
    /// Per wall particle: index into `part_names`.
    pub wall_part: Vec<u16>,
    /// Per wall particle: unit normal of the tank boundary at the nearest boundary point,
    /// pointing out of the liquid into the wall (so the fluid pushes the wall along it).
    pub wall_normal: Vec<SVector<f64, D>>,
    /// Per wall particle: boundary area it stands for in load integration (m², in 2D m per m of
    /// tank depth). Non-zero only for the innermost layer; the areas of one part add up to the
    /// part's surface area.
    pub wall_area: Vec<f64>,
    /// Per wall particle: layer number, 1 = the layer next to the liquid.
    pub wall_layer: Vec<u8>,
    /// Part names; indices 0, 1, 2 are always `bottom`, `wall`, `roof` (a part may be empty).
    pub part_names: Vec<String>,
    /// Lower corner of the interior's bounding box (m).
    pub interior_min: SVector<f64, D>,
    /// Upper corner of the interior's bounding box (m); for an open tank the top of the shell.
    pub interior_max: SVector<f64, D>,
    /// Height of the still free surface (m), the level the wave elevation is measured from.
    pub fill_level: f64,
    /// The interior region, used to count the fluid particles still inside the tank.
    pub interior: Box<dyn TankInterior<D>>,
}

impl<const D: usize> ParticleSetup<D> {
    /// Keeps the wall particles for which `keep(position, part)` is true, with their tags
    /// (part, normal, area, layer) and in their order; drops the rest.
    pub fn retain_walls(&mut self, mut keep: impl FnMut(&SVector<f64, D>, u16) -> bool) {
        let mut kept = 0;
        for w in 0..self.wall_positions.len() {
            if !keep(&self.wall_positions[w], self.wall_part[w]) {
                continue;
            }
            self.wall_positions[kept] = self.wall_positions[w];
            self.wall_part[kept] = self.wall_part[w];
            self.wall_normal[kept] = self.wall_normal[w];
            self.wall_area[kept] = self.wall_area[w];
            self.wall_layer[kept] = self.wall_layer[w];
            kept += 1;
        }
        self.wall_positions.truncate(kept);
        self.wall_part.truncate(kept);
        self.wall_normal.truncate(kept);
        self.wall_area.truncate(kept);
        self.wall_layer.truncate(kept);
    }
}
