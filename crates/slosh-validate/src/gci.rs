//! The discretisation uncertainty of a result computed at three or more resolutions: the
//! observed order, the Richardson-extrapolated value and the grid convergence index of the
//! finest level, by the procedure of Celik, Ghia, Roache, Freitas, Coleman & Raad (2008),
//! "Procedure for estimation and reporting of uncertainty due to discretization in CFD
//! applications", J. Fluids Eng. 130, 078001, as ASME V&V 20 uses it. `slosh converge` and the
//! validation suite's resolution studies read it.

/// How the finest three levels behave, from R = ε₂₁/ε₃₂ (Stern, Wilson, Coleman & Paterson
/// 2001, J. Fluids Eng. 123, 793).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Behaviour {
    /// 0 ≤ R < 1: the changes shrink with one sign.
    Monotone,
    /// −1 < R < 0: the changes shrink and alternate in sign; the uncertainty is half the
    /// levels' range (no order, no extrapolation).
    Oscillatory,
    /// |R| ≥ 1: the changes do not shrink; no order or GCI.
    Divergent,
    /// All levels equal.
    Unchanged,
    /// Two levels only: the change, no order.
    TwoLevels,
    /// A level has no finite value.
    Missing,
}

impl Behaviour {
    /// The word of `convergence.csv`.
    pub fn word(self) -> &'static str {
        match self {
            Behaviour::Monotone => "monotone",
            Behaviour::Oscillatory => "oscillatory",
            Behaviour::Divergent => "divergent",
            Behaviour::Unchanged => "unchanged",
            Behaviour::TwoLevels => "two levels",
            Behaviour::Missing => "missing",
        }
    }
}

/// The discretisation uncertainty of one quantity (Celik et al. 2008, §2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Uncertainty {
    /// Behaviour of the finest three levels.
    pub behaviour: Behaviour,
    /// Observed order p (Eq. 3–5; NaN when not computed).
    pub order: f64,
    /// Richardson-extrapolated value φ_ext²¹ (Eq. 6).
    pub extrapolated: f64,
    /// Approximate relative error of the finest level, e_a²¹ = |(φ₁ − φ₂)/φ₁| (Eq. 7).
    pub relative_change: f64,
    /// Extrapolated relative error e_ext²¹ = |(φ_ext − φ₁)/φ_ext| (Eq. 8).
    pub extrapolated_error: f64,
    /// Fine-grid convergence index GCI²¹ = 1.25 e_a²¹/(r₂₁^p − 1) (Eq. 9), a fraction.
    pub gci_fine: f64,
    /// The GCI in the quantity's unit: 1.25 |φ₁ − φ₂|/(r₂₁^p − 1).
    pub band: f64,
}

/// The uncertainty of the finest level from `values` (coarsest first) at spacings `h`.
pub fn uncertainty(values: &[f64], h: &[f64]) -> Uncertainty {
    let nan = f64::NAN;
    let mut u = Uncertainty {
        behaviour: Behaviour::Missing,
        order: nan,
        extrapolated: nan,
        relative_change: nan,
        extrapolated_error: nan,
        gci_fine: nan,
        band: nan,
    };
    let n = values.len();
    // Only the finest three levels enter the procedure.
    if n < 2 || h.len() != n || values[n.saturating_sub(3)..].iter().any(|v| !v.is_finite()) {
        return u;
    }
    let (phi1, phi2) = (values[n - 1], values[n - 2]);
    let e21 = phi2 - phi1;
    u.relative_change = if phi1 != 0.0 {
        (e21 / phi1).abs()
    } else if e21 == 0.0 {
        0.0
    } else {
        nan
    };
    if n == 2 {
        u.behaviour = if e21 == 0.0 {
            Behaviour::Unchanged
        } else {
            Behaviour::TwoLevels
        };
        return u;
    }
    let phi3 = values[n - 3];
    let e32 = phi3 - phi2;
    let (r21, r32) = (h[n - 2] / h[n - 1], h[n - 3] / h[n - 2]);
    if e21 == 0.0 && e32 == 0.0 {
        u.behaviour = Behaviour::Unchanged;
        u.extrapolated = phi1;
        u.extrapolated_error = 0.0;
        u.gci_fine = 0.0;
        u.band = 0.0;
        return u;
    }
    if e21 == 0.0 {
        // The finest two agree: converged at the finest level to the values' precision.
        u.behaviour = Behaviour::Monotone;
        u.extrapolated = phi1;
        u.extrapolated_error = 0.0;
        u.gci_fine = 0.0;
        u.band = 0.0;
        return u;
    }
    let ratio = e21 / e32;
    u.behaviour = if e32 == 0.0 || ratio.abs() >= 1.0 {
        Behaviour::Divergent
    } else if ratio > 0.0 {
        Behaviour::Monotone
    } else {
        Behaviour::Oscillatory
    };
    if u.behaviour == Behaviour::Divergent {
        return u;
    }
    if u.behaviour == Behaviour::Oscillatory {
        // Richardson extrapolation assumes changes of one sign; for oscillatory convergence
        // the uncertainty is half the range of the levels (Stern, Wilson, Coleman & Paterson
        // 2001, J. Fluids Eng. 123, 793, §4): no order, no extrapolated value.
        let (lo, hi) = (phi1.min(phi2).min(phi3), phi1.max(phi2).max(phi3));
        u.band = 0.5 * (hi - lo);
        u.gci_fine = if phi1 != 0.0 {
            u.band / phi1.abs()
        } else {
            nan
        };
        return u;
    }
    // Eq. 3–5: p = |ln|ε₃₂/ε₂₁| + q(p)| / ln r₂₁, q(p) = ln((r₂₁^p − s)/(r₃₂^p − s)),
    // s = sign(ε₃₂/ε₂₁), solved by fixed-point iteration.
    let s = (e32 / e21).signum();
    let ln_ratio = (e32 / e21).abs().ln();
    let mut p = ln_ratio.abs() / r21.ln();
    for _ in 0..200 {
        let arg = (r21.powf(p) - s) / (r32.powf(p) - s);
        if arg.is_nan() || arg <= 0.0 {
            p = nan;
            break;
        }
        let next = (ln_ratio + arg.ln()).abs() / r21.ln();
        if (next - p).abs() < 1e-12 * next.max(1.0) {
            p = next;
            break;
        }
        p = next;
    }
    if !(p.is_finite() && p > 0.0) {
        return u;
    }
    let rp = r21.powf(p);
    u.order = p;
    u.extrapolated = (rp * phi1 - phi2) / (rp - 1.0);
    u.extrapolated_error = if u.extrapolated != 0.0 {
        ((u.extrapolated - phi1) / u.extrapolated).abs()
    } else {
        nan
    };
    u.band = 1.25 * e21.abs() / (rp - 1.0);
    u.gci_fine = if phi1 != 0.0 {
        u.band / phi1.abs()
    } else {
        nan
    };
    u
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Celik et al. (2008), Table 1, first column: N = 18000, 8000, 4500 cells in 2D
    /// (h ∝ N^−1/2), φ = 6.063, 5.972, 5.863 → p = 1.53, φ_ext = 6.1685, e_a = 1.5 %,
    /// e_ext = 1.7 %, GCI_fine = 2.2 % (the paper's rounding sets the tolerances).
    #[test]
    fn celik_worked_example() {
        let h: Vec<f64> = [4500.0f64, 8000.0, 18000.0]
            .iter()
            .map(|n| n.powf(-0.5))
            .collect();
        let u = uncertainty(&[5.863, 5.972, 6.063], &h);
        assert_eq!(u.behaviour, Behaviour::Monotone);
        assert!((u.order - 1.53).abs() < 0.01, "p = {}", u.order);
        assert!(
            (u.extrapolated - 6.1685).abs() < 0.001,
            "φext = {}",
            u.extrapolated
        );
        assert!((u.relative_change - 0.015).abs() < 0.0005);
        assert!((u.extrapolated_error - 0.017).abs() < 0.0005);
        assert!((u.gci_fine - 0.022).abs() < 0.0005, "GCI = {}", u.gci_fine);
    }

    /// A quantity with a known second-order error, φ(h) = 1 + h², at h = 0.4, 0.2, 0.1:
    /// p = 2 and φ_ext = 1 exactly.
    #[test]
    fn second_order_is_recovered() {
        let h = [0.4, 0.2, 0.1];
        let v: Vec<f64> = h.iter().map(|x| 1.0 + x * x).collect();
        let u = uncertainty(&v, &h);
        assert!((u.order - 2.0).abs() < 1e-9);
        assert!((u.extrapolated - 1.0).abs() < 1e-12);
        // GCI = 1.25 |φ₁ − φ₂|/(r^p − 1)/φ₁ = 1.25·0.03/3/1.01.
        assert!((u.gci_fine - 1.25 * 0.03 / 3.0 / 1.01).abs() < 1e-12);
        let osc = uncertainty(&[1.0, 1.2, 1.1], &h);
        assert_eq!(osc.behaviour, Behaviour::Oscillatory);
        // Half the range of the levels over the finest value (Stern et al. 2001).
        assert!((osc.gci_fine - 0.1 / 1.1).abs() < 1e-12 && osc.order.is_nan());
        let div = uncertainty(&[1.0, 1.1, 1.3], &h);
        assert_eq!(div.behaviour, Behaviour::Divergent);
        assert!(div.gci_fine.is_nan());
    }
}
