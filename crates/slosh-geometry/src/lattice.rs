//! Lattice and part rules shared by the 2D section and 3D tank builders.

/// Part index given to boundary pieces that produce no wall particles (the virtual lid of an
/// open 3D tank and the shell above its top).
pub(crate) const NO_PART: u16 = u16::MAX;

/// Lattice index of the cell-centred point ((i+½)dx) nearest to coordinate `c` (m).
pub(crate) fn cell_of(c: f64, dx: f64) -> i64 {
    (c / dx - 0.5).round() as i64
}

/// Number of lattice rows (cell centres (k+½)dx, k ≥ 0) below the height `level` (m); a level
/// within 10⁻⁶ dx of a lattice level k·dx counts as that level. The still level the particles
/// represent is then rows·dx.
pub(crate) fn lattice_rows_below(level: f64, dx: f64) -> f64 {
    let ratio = level / dx;
    if (ratio - ratio.round()).abs() < 1e-6 {
        ratio.round()
    } else {
        (ratio - 0.5).ceil().max(0.0)
    }
}

/// Rank of a part where several parts meet at a corner or edge: the wall particle there goes
/// to the part of the nearest face line or plane, ties to the highest rank (roof over wall over
/// bottom; user parts above all; no part below all).
pub(crate) fn part_priority(part: u16) -> u8 {
    match part {
        NO_PART => 0,
        0 => 1,
        1 => 2,
        2 => 3,
        _ => 4,
    }
}

/// Scales the per-particle boundary areas so that each part's areas add up to `target[part]`:
/// `assigned[part]` is what the particles of that part received from the surface sampling.
/// Parts that received nothing keep zero areas.
pub(crate) fn scale_areas_to_part_totals(
    areas: &mut [f64],
    parts: &[u16],
    assigned: &[f64],
    target: &[f64],
) {
    let scale: Vec<f64> = assigned
        .iter()
        .zip(target)
        .map(|(&a, &t)| if a > 0.0 { t / a } else { 0.0 })
        .collect();
    for (a, &p) in areas.iter_mut().zip(parts) {
        *a *= scale[p as usize];
    }
}
