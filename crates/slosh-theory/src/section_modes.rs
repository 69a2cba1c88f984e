//! First antisymmetric sloshing frequency of 2D sections symmetric about a vertical axis, by
//! the Ritz method of linear potential theory (Ibrahim 2005, *Liquid Sloshing Dynamics*, §2:
//! the eigenvalue λ = ω²/g is the minimum of the Rayleigh quotient ∫_D |∇φ|² dA / ∫_F φ² dx
//! over functions φ in the liquid D, F the still free surface). The trial functions are the
//! harmonic polynomials odd in x about the section's axis, r^k cos kθ (k odd) and r^k sin kθ
//! (k even) centred on the middle of the free surface, so ∫_D |∇φ|² dA = ∮ φ ∂φ/∂n ds is a
//! boundary integral, evaluated by Gauss–Legendre quadrature. Ritz values are upper bounds
//! that fall as the degree grows; the routine checks the last two degrees agree.
//!
//! Checked against the exact rectangle, ω²/g = (π/L) tanh(πH/L), the exact 90° wedge (45°
//! walls, ω²/g = 1/H) and the half-full circle, ω²R/g = 1.3557 (Budiansky 1960, J. Aerospace
//! Sci. 27, 161–173; McIver 1989, J. Fluid Mech. 201, 243–257).

use num_complex::Complex64;

/// A piece of the wetted boundary of a section, traversed counter-clockwise (liquid on the
/// left), from the left end of the free surface down and round to its right end.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum WettedPiece {
    /// A straight side from `from` to `to` (x, y in m).
    Line {
        /// Start point (m).
        from: [f64; 2],
        /// End point (m).
        to: [f64; 2],
    },
    /// An arc of the circle of `radius` (m) about `centre` from angle `from` to `to` (rad,
    /// counter-clockwise, to > from), the liquid inside the circle.
    Arc {
        /// Centre (m).
        centre: [f64; 2],
        /// Radius (m).
        radius: f64,
        /// Start angle (rad).
        from: f64,
        /// End angle (rad), larger than `from`.
        to: f64,
    },
}

/// A 2D section symmetric about x = 0: the still free surface y = `surface` (m) from
/// x = −`half_width` to `half_width`, and the wetted boundary below it.
#[derive(Debug, Clone, PartialEq)]
pub struct SymmetricSection {
    /// Height of the still free surface (m).
    pub surface: f64,
    /// Half the free-surface width (m).
    pub half_width: f64,
    /// Wetted boundary, counter-clockwise from (−half_width, surface) to (half_width, surface).
    pub wetted: Vec<WettedPiece>,
}

impl SymmetricSection {
    /// A rectangle `width` × `depth` (m), floor at y = 0.
    pub fn rectangle(width: f64, depth: f64) -> Self {
        let c = 0.5 * width;
        SymmetricSection {
            surface: depth,
            half_width: c,
            wetted: vec![
                WettedPiece::Line {
                    from: [-c, depth],
                    to: [-c, 0.0],
                },
                WettedPiece::Line {
                    from: [-c, 0.0],
                    to: [c, 0.0],
                },
                WettedPiece::Line {
                    from: [c, 0.0],
                    to: [c, depth],
                },
            ],
        }
    }

    /// A horizontal circular tank of `radius` (m) holding `depth` (m) of liquid
    /// (0 < depth < 2 radius), lowest point at y = 0: above half full, the circle's upper part
    /// overhangs the liquid (a roof sloping down to the surface).
    pub fn circle(radius: f64, depth: f64) -> Self {
        let y = depth - radius; // surface height above the centre
        let alpha = (y / radius).clamp(-1.0, 1.0).asin();
        SymmetricSection {
            surface: depth,
            half_width: radius * alpha.cos(),
            wetted: vec![WettedPiece::Arc {
                centre: [0.0, radius],
                radius,
                from: std::f64::consts::PI - alpha,
                to: 2.0 * std::f64::consts::PI + alpha,
            }],
        }
    }

    /// A 90° wedge (walls at 45°) of `depth` (m), apex at y = 0.
    pub fn wedge_90(depth: f64) -> Self {
        SymmetricSection {
            surface: depth,
            half_width: depth,
            wetted: vec![
                WettedPiece::Line {
                    from: [-depth, depth],
                    to: [0.0, 0.0],
                },
                WettedPiece::Line {
                    from: [0.0, 0.0],
                    to: [depth, depth],
                },
            ],
        }
    }
}

/// Gauss–Legendre nodes and weights on [−1, 1] (Newton on the Legendre recurrence).
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                    p0 = p1;
                    p1 = p2;
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / dp;
                x -= dx;
                if dx.abs() < 1e-15 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

/// Quadrature points of the wetted boundary: (point, outward normal, weight) (m, –, m).
fn boundary_samples(section: &SymmetricSection) -> Vec<([f64; 2], [f64; 2], f64)> {
    const PANELS: usize = 16;
    let rule = gauss_legendre(24);
    let mut out = Vec::new();
    for piece in &section.wetted {
        for p in 0..PANELS {
            for &(s, w) in &rule {
                let t = (p as f64 + 0.5 * (s + 1.0)) / PANELS as f64;
                match *piece {
                    WettedPiece::Line { from, to } => {
                        let d = [to[0] - from[0], to[1] - from[1]];
                        let len = d[0].hypot(d[1]);
                        out.push((
                            [from[0] + t * d[0], from[1] + t * d[1]],
                            [d[1] / len, -d[0] / len],
                            0.5 * w * len / PANELS as f64,
                        ));
                    }
                    WettedPiece::Arc {
                        centre,
                        radius,
                        from,
                        to,
                    } => {
                        let th = from + t * (to - from);
                        let n = [th.cos(), th.sin()];
                        out.push((
                            [centre[0] + radius * n[0], centre[1] + radius * n[1]],
                            n,
                            0.5 * w * radius * (to - from) / PANELS as f64,
                        ));
                    }
                }
            }
        }
    }
    out
}

/// Trial function k (degree k + 1) and its gradient at `z` (relative to the middle of the
/// free surface, scaled by the farthest boundary point): Re zⁿ for odd n, Im zⁿ for even n.
fn trial(k: usize, z: Complex64) -> (f64, [f64; 2]) {
    let n = k as i32 + 1;
    let f = z.powi(n);
    let df = z.powi(n - 1) * n as f64; // d/dz; ∇Re f = (Re f', −Im f'), ∇Im f = (Im f', Re f')
    if n % 2 == 1 {
        (f.re, [df.re, -df.im])
    } else {
        (f.im, [df.im, df.re])
    }
}

/// Eigenvalues and eigenvectors (columns) of the symmetric matrix `a` (cyclic Jacobi).
fn symmetric_eigen(mut a: Vec<Vec<f64>>) -> (Vec<f64>, Vec<Vec<f64>>) {
    let n = a.len();
    let mut v = vec![vec![0.0; n]; n];
    for (i, row) in v.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    for _ in 0..100 {
        let off: f64 = (0..n)
            .flat_map(|i| (0..n).filter(move |&j| j != i).map(move |j| (i, j)))
            .map(|(i, j)| a[i][j] * a[i][j])
            .sum();
        let diag: f64 = (0..n).map(|i| a[i][i] * a[i][i]).sum();
        if off <= 1e-30 * diag {
            break;
        }
        for p in 0..n {
            for q in p + 1..n {
                if a[p][q] == 0.0 {
                    continue;
                }
                let theta = 0.5 * (a[q][q] - a[p][p]) / a[p][q];
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for row in a.iter_mut() {
                    let (akp, akq) = (row[p], row[q]);
                    row[p] = c * akp - s * akq;
                    row[q] = s * akp + c * akq;
                }
                // rows p and q (p < q)
                let (upper, lower) = a.split_at_mut(q);
                for (ap, aq) in upper[p].iter_mut().zip(lower[0].iter_mut()) {
                    let (apk, aqk) = (*ap, *aq);
                    *ap = c * apk - s * aqk;
                    *aq = s * apk + c * aqk;
                }
                for row in v.iter_mut() {
                    let (vp, vq) = (row[p], row[q]);
                    row[p] = c * vp - s * vq;
                    row[q] = s * vp + c * vq;
                }
            }
        }
    }
    ((0..n).map(|i| a[i][i]).collect(), v)
}

/// Ritz value of λ₁ = ω₁²/g (1/m) of the first antisymmetric mode of `section` with the
/// trial functions up to `degree`: the smallest λ of A a = λ B a, A = ∮ φᵢ ∂φⱼ/∂n ds (the
/// Dirichlet integral), B = ∫_F φᵢ φⱼ dx. A is diagonalised first and its directions with
/// eigenvalues below 10⁻¹³ of the largest (numerically dependent trial functions) dropped.
pub fn first_antisymmetric_ritz(section: &SymmetricSection, degree: usize) -> f64 {
    let n = degree;
    let wetted = boundary_samples(section);
    // lengths scaled by the farthest boundary point from the middle of the surface, so that
    // |z| ≤ 1 and no trial function dwarfs the others
    let c = wetted
        .iter()
        .map(|(p, _, _)| p[0].hypot(p[1] - section.surface))
        .fold(section.half_width, f64::max);
    let z_of = |p: [f64; 2]| Complex64::new(p[0] / c, (p[1] - section.surface) / c);
    let mut a = vec![vec![0.0; n]; n];
    let mut b = vec![vec![0.0; n]; n];
    // the Dirichlet integral as a boundary integral: wetted boundary and free surface (normal
    // +y); B on the free surface
    let surface: Vec<([f64; 2], [f64; 2], f64)> = gauss_legendre(48)
        .into_iter()
        .map(|(s, w)| {
            let hw = section.half_width;
            ([s * hw, section.surface], [0.0, 1.0], w * hw)
        })
        .collect();
    for (p, normal, w) in wetted.iter().chain(&surface) {
        let f: Vec<(f64, [f64; 2])> = (0..n).map(|k| trial(k, z_of(*p))).collect();
        for i in 0..n {
            for j in 0..n {
                // gradients are per unit of z: ∂/∂x = (1/c) ∂/∂(x/c)
                let dn = (f[j].1[0] * normal[0] + f[j].1[1] * normal[1]) / c;
                a[i][j] += w * f[i].0 * dn;
            }
        }
    }
    for (p, _, w) in &surface {
        let f: Vec<f64> = (0..n).map(|k| trial(k, z_of(*p)).0).collect();
        for i in 0..n {
            for j in 0..n {
                b[i][j] += w * f[i] * f[j];
            }
        }
    }
    for i in 1..n {
        // row i and the rows j < i above it
        let (upper, lower) = a.split_at_mut(i);
        for (j, row_j) in upper.iter_mut().enumerate() {
            let m = 0.5 * (lower[0][j] + row_j[i]);
            lower[0][j] = m;
            row_j[i] = m;
        }
    }
    let (d, v) = symmetric_eigen(a);
    let largest = d.iter().cloned().fold(0.0, f64::max);
    let keep: Vec<usize> = (0..n).filter(|&k| d[k] > 1e-13 * largest).collect();
    // T = V_keep D^(−1/2); M = Tᵀ B T; λ₁ = 1/μ_max(M)
    let t: Vec<Vec<f64>> = (0..n)
        .map(|i| keep.iter().map(|&k| v[i][k] / d[k].sqrt()).collect())
        .collect();
    let m = keep.len();
    let bt: Vec<Vec<f64>> = (0..n)
        .map(|i| {
            (0..m)
                .map(|q| (0..n).map(|k| b[i][k] * t[k][q]).sum())
                .collect()
        })
        .collect();
    let mm: Vec<Vec<f64>> = (0..m)
        .map(|p| {
            (0..m)
                .map(|q| (0..n).map(|i| t[i][p] * bt[i][q]).sum())
                .collect()
        })
        .collect();
    let (mu, _) = symmetric_eigen(mm);
    1.0 / mu.iter().cloned().fold(0.0, f64::max)
}

/// First antisymmetric sloshing eigenvalue ω₁²R/g of a horizontal circular tank of radius R
/// holding `depth_over_radius` · R of liquid (0 < h/R < 2): the Ritz value of degree 24
/// ([`first_antisymmetric_ritz`]). 1.3557 at half full (Budiansky 1960; McIver 1989).
pub fn circle_eigenvalue(depth_over_radius: f64) -> f64 {
    first_antisymmetric_ritz(&SymmetricSection::circle(1.0, depth_over_radius), 24)
}

/// First-mode period (s) of a horizontal circular tank of `radius` (m) holding `depth` (m)
/// of liquid under `gravity` (m/s²): T₁ = 2π/√(λ₁ g/R), λ₁ = [`circle_eigenvalue`].
pub fn circle_period(radius: f64, depth: f64, gravity: f64) -> f64 {
    2.0 * std::f64::consts::PI / (circle_eigenvalue(depth / radius) * gravity / radius).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn rectangle_matches_the_exact_eigenvalue() {
        // ω²/g = (π/L) tanh(πH/L); polynomials converge fast on the rectangle: 1e-6
        for (w, h) in [(1.0, 0.5), (2.0, 0.4), (1.0, 1.0)] {
            let exact = PI / w * (PI * h / w).tanh();
            let ritz = first_antisymmetric_ritz(&SymmetricSection::rectangle(w, h), 20);
            assert!(
                (ritz / exact - 1.0).abs() < 1e-6,
                "{w}×{h}: {ritz} vs {exact}"
            );
        }
    }

    #[test]
    fn wedge_is_exact_and_half_circle_is_budiansky() {
        // the 90° wedge's mode x(y + H) lies in the trial space: exact to roundoff
        let wedge = first_antisymmetric_ritz(&SymmetricSection::wedge_90(0.7), 8);
        assert!((wedge * 0.7 - 1.0).abs() < 1e-9, "{wedge}");
        // half full: 1.3557 (Budiansky 1960; McIver 1989), to its 4 decimals
        let half = circle_eigenvalue(1.0);
        assert!((half - 1.3557).abs() < 5e-5, "{half}");
    }

    #[test]
    fn circle_above_half_full_is_converged_and_rises_with_the_fill() {
        // the overhanging roof stiffens the mode: λ₁ grows with the fill (to ∞ as h → 2R)
        let mut last = 0.0;
        for h in [0.5, 1.0, 1.25, 1.5, 1.75] {
            let section = SymmetricSection::circle(1.0, h);
            let (coarse, fine) = (
                first_antisymmetric_ritz(&section, 16),
                first_antisymmetric_ritz(&section, 24),
            );
            // Ritz upper bounds, falling with the degree, converged to 1e-4
            assert!(fine <= coarse * (1.0 + 1e-9), "h = {h}: {coarse} {fine}");
            assert!((coarse - fine) / fine < 1e-4, "h = {h}: {coarse} {fine}");
            assert!(fine > last, "h = {h}: {fine} after {last}");
            last = fine;
        }
    }
}
