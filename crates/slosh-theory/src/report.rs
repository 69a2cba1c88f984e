//! One-call closed-form report for a tank: natural periods, code convective period, masses
//! and heights (exact theory, Housner, code), base shear, wave heights and freeboard.
//! Called by `slosh theory`; printed with `Display` or serialised with serde (RON).

use crate::codes::{self, Ec8GroundType, FreeboardCheck};
use crate::cylinder::{self, CylindricalTank};
use crate::housner;
use crate::linear::RectangularTank;
use crate::modal::{sine_response, ModalTank};
use crate::natural;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;
use std::fmt;

/// Plan shape of the tank.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum TankShape {
    /// 2D rectangular tank of full inside width (m) along the excitation; results per metre.
    Rectangular {
        /// Full width L (m).
        width: f64,
    },
    /// Upright circular cylinder of inside radius (m).
    Cylindrical {
        /// Radius R (m).
        radius: f64,
    },
}

/// A harmonic ground motion: ground displacement amplitude A (m) at circular frequency Ω
/// (rad/s), acting for `duration` (s) from rest. Body force on the liquid f = −AΩ² sin Ωt
/// (the paper's convention, a = −AΩ² sin ωt applied to the particles).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SineExcitation {
    /// Ground displacement amplitude A (m).
    pub amplitude: f64,
    /// Circular frequency Ω (rad/s).
    pub omega: f64,
    /// Duration (s) over which the linear peak response is taken.
    pub duration: f64,
}

/// Input of [`tank_report`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct TankInput {
    /// Plan shape and size.
    pub shape: TankShape,
    /// Still liquid depth H (m).
    pub depth: f64,
    /// Height of the fixed roof above the bottom (m), if any (freeboard = height − depth).
    pub tank_height: Option<f64>,
    /// Liquid density ρ (kg/m³).
    pub density: f64,
    /// Gravity g (m/s²).
    pub gravity: f64,
    /// Peak ground acceleration (m/s²) for the impulsive base shear.
    pub peak_ground_accel: Option<f64>,
    /// Convective spectral acceleration S_a(T_c) at 0.5 % damping, in g (A_f of API 650).
    /// If absent but a PGA is given, it is taken from the EC8 type-1 ground-A spectrum with
    /// a_g = PGA and ξ = 0.5 % (stated in the report).
    pub spectral_accel_g: Option<f64>,
    /// Harmonic excitation for a linear-theory time response, if any.
    pub sine: Option<SineExcitation>,
}

impl TankInput {
    /// Rectangular water tank (ρ = 1000 kg/m³, g = 9.81 m/s²), no roof, no excitation.
    pub fn rectangular(width: f64, depth: f64) -> Self {
        Self::with_shape(TankShape::Rectangular { width }, depth)
    }

    /// Cylindrical water tank (ρ = 1000 kg/m³, g = 9.81 m/s²), no roof, no excitation.
    pub fn cylindrical(radius: f64, depth: f64) -> Self {
        Self::with_shape(TankShape::Cylindrical { radius }, depth)
    }

    fn with_shape(shape: TankShape, depth: f64) -> Self {
        Self {
            shape,
            depth,
            tank_height: None,
            density: 1000.0,
            gravity: natural::STANDARD_GRAVITY,
            peak_ground_accel: None,
            spectral_accel_g: None,
            sine: None,
        }
    }

    /// Checks that the input describes a real tank and excitation: positive finite sizes,
    /// density, gravity and sine, a roof above the liquid, non-negative finite accelerations.
    /// The error lists every value that is wrong, by name, with its unit and value.
    pub fn check(&self) -> Result<(), String> {
        let mut problems = Vec::new();
        let mut positive = |name: &str, unit: &str, value: f64| {
            if !(value.is_finite() && value > 0.0) {
                problems.push(format!(
                    "{name} must be a positive finite number of {unit}, got {value}"
                ));
            }
        };
        match self.shape {
            TankShape::Rectangular { width } => positive("width", "m", width),
            TankShape::Cylindrical { radius } => positive("radius", "m", radius),
        }
        positive("depth", "m", self.depth);
        positive("density", "kg/m³", self.density);
        positive("gravity", "m/s²", self.gravity);
        if let Some(height) = self.tank_height {
            positive("tank_height", "m", height);
        }
        if let Some(sine) = self.sine {
            positive("amplitude", "m", sine.amplitude);
            positive("omega", "rad/s", sine.omega);
            positive("sine duration", "s", sine.duration);
        }
        for (name, unit, value) in [
            ("pga", "m/s²", self.peak_ground_accel),
            ("sa", "g", self.spectral_accel_g),
        ] {
            if let Some(v) = value.filter(|v| !(v.is_finite() && *v >= 0.0)) {
                problems.push(format!(
                    "{name} must be a non-negative finite number of {unit}, got {v}"
                ));
            }
        }
        if let Some(height) = self
            .tank_height
            .filter(|h| h.is_finite() && self.depth.is_finite())
        {
            if height <= self.depth {
                problems.push(format!(
                    "the roof (tank_height {height} m) must be above the liquid (depth {} m)",
                    self.depth
                ));
            }
        }
        if problems.is_empty() {
            Ok(())
        } else {
            Err(problems.join("; "))
        }
    }
}

/// One natural mode.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ModeEntry {
    /// Mode label: "n=1" (rectangular) or "(m=1,n=1)" (cylinder).
    pub mode: String,
    /// Circular frequency ω (rad/s).
    pub omega: f64,
    /// Period T (s).
    pub period: f64,
    /// Whether a horizontal ground motion excites this mode.
    pub excited: bool,
}

/// Impulsive and convective masses (kg, or kg/m for 2D) and heights above the bottom (m,
/// bottom pressure excluded) from one source.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MassEntry {
    /// Where the numbers come from.
    pub source: String,
    /// Impulsive mass m_i.
    pub impulsive_mass: f64,
    /// Impulsive height h_i (m).
    pub impulsive_height: f64,
    /// First convective mass m_c.
    pub convective_mass: f64,
    /// Convective height h_c (m).
    pub convective_height: f64,
    /// First convective period (s) used with this model.
    pub convective_period: f64,
}

/// A named wave height (m).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct WaveHeightEntry {
    /// Formula name.
    pub source: String,
    /// Wave height above the still level at the wall (m).
    pub height: f64,
}

/// Linear-theory response to the sine excitation.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SineResponse {
    /// Peak ground acceleration AΩ² (m/s²).
    pub peak_ground_accel: f64,
    /// Largest crest at the −x (left) wall over the duration (m).
    pub max_wall_elevation: f64,
    /// Time of that crest (s).
    pub time_of_max: f64,
    /// Largest |base shear| (N or N/m).
    pub max_abs_base_shear: f64,
}

/// The report.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TankReport {
    /// "rectangular" or "cylindrical".
    pub shape: String,
    /// Full width L (rectangular) or diameter D (cylinder) (m).
    pub plan_size: f64,
    /// Liquid depth H (m).
    pub depth: f64,
    /// Gravity (m/s²).
    pub gravity: f64,
    /// Density (kg/m³).
    pub density: f64,
    /// "kg/m" (2D, per metre) or "kg".
    pub mass_unit: String,
    /// "N/m" or "N".
    pub force_unit: String,
    /// Liquid mass (kg or kg/m).
    pub liquid_mass: f64,
    /// First three natural modes (rectangular n = 1, 2, 3; cylinder (1,1), (1,2), (1,3)).
    pub modes: Vec<ModeEntry>,
    /// Code convective period (s): ACI 350.3 (rectangular) or API 650 / ACI 350.3 (circular).
    pub code_convective_period: f64,
    /// API 650 SI form 1.8 K_s √D (s), cylinders only.
    pub api650_convective_period: Option<f64>,
    /// Masses and heights: exact potential theory, Housner, code.
    pub masses: Vec<MassEntry>,
    /// Peak ground acceleration used (m/s²).
    pub peak_ground_accel: Option<f64>,
    /// Convective spectral acceleration used (g), with its origin.
    pub spectral_accel_g: Option<f64>,
    /// Where `spectral_accel_g` came from.
    pub spectral_accel_source: Option<String>,
    /// Housner impulsive base shear m_i · PGA (N or N/m).
    pub base_shear_impulsive: Option<f64>,
    /// Housner convective base shear m_c · S_a(T_c) (N or N/m).
    pub base_shear_convective: Option<f64>,
    /// SRSS combination (N or N/m) (API 650 E.6.1 / ACI 350.3 Eq. 9-1 style).
    pub base_shear_srss: Option<f64>,
    /// Code wave heights (m).
    pub wave_heights: Vec<WaveHeightEntry>,
    /// Linear-theory sine response, if a sine was given.
    pub sine_response: Option<SineResponse>,
    /// Freeboard: available (roof height − depth), required (largest wave height), verdict.
    pub freeboard: FreeboardCheck,
}

/// Build the report for a tank (pure; see [`TankReport`] for the content).
/// Validity: rigid tank, linear sloshing; code formulas as documented in [`crate::codes`].
pub fn tank_report(input: &TankInput) -> TankReport {
    let (g, rho, h) = (input.gravity, input.density, input.depth);
    let mut masses = Vec::new();
    let modes: Vec<ModeEntry>;
    let code_period;
    let mut api_period = None;
    let (shape, plan_size, mass_unit, force_unit, liquid_mass);
    match input.shape {
        TankShape::Rectangular { width } => {
            shape = "rectangular";
            plan_size = width;
            mass_unit = "kg/m";
            force_unit = "N/m";
            let tank = RectangularTank {
                width,
                depth: h,
                density: rho,
                gravity: g,
            };
            liquid_mass = tank.liquid_mass();
            modes = (1..=3)
                .map(|n| {
                    let w = natural::rectangular_omega(width, h, g, n);
                    ModeEntry {
                        mode: format!("n={n}"),
                        omega: w,
                        period: 2.0 * PI / w,
                        excited: n % 2 == 1,
                    }
                })
                .collect();
            code_period = codes::rectangular_convective_period(width, h, g);
            masses.push(MassEntry {
                source: "potential theory (exact)".into(),
                impulsive_mass: tank.impulsive_mass(),
                impulsive_height: tank.impulsive_height(),
                convective_mass: tank.convective_mass(0),
                convective_height: tank.convective_height(0),
                convective_period: 2.0 * PI / tank.modal_omega(0),
            });
            let l = 0.5 * width;
            let (hi, hc) = housner::heights(l, h);
            masses.push(MassEntry {
                source: "Housner 1957".into(),
                impulsive_mass: housner::impulsive_mass(rho, l, h),
                impulsive_height: hi,
                convective_mass: housner::convective_mass(rho, l, h),
                convective_height: hc,
                convective_period: 2.0 * PI / housner::convective_omega(l, h, g),
            });
            let c = codes::aci350_rectangular_masses(width, h);
            masses.push(code_masses_entry(
                "ACI 350.3-06",
                c,
                liquid_mass,
                h,
                code_period,
            ));
        }
        TankShape::Cylindrical { radius } => {
            shape = "cylindrical";
            plan_size = 2.0 * radius;
            mass_unit = "kg";
            force_unit = "N";
            let tank = CylindricalTank::new(radius, h, rho, g);
            liquid_mass = tank.liquid_mass();
            modes = (0..3)
                .map(|j| {
                    let w = tank.modal_omega(j);
                    ModeEntry {
                        mode: format!("(m=1,n={})", j + 1),
                        omega: w,
                        period: 2.0 * PI / w,
                        excited: true,
                    }
                })
                .collect();
            code_period = codes::circular_convective_period(2.0 * radius, h, g);
            api_period = Some(codes::api650_convective_period_si(2.0 * radius, h));
            masses.push(MassEntry {
                source: "potential theory (Veletsos)".into(),
                impulsive_mass: tank.impulsive_mass(),
                impulsive_height: tank.impulsive_height(),
                convective_mass: tank.convective_mass(0),
                convective_height: tank.convective_height(0),
                convective_period: 2.0 * PI / tank.modal_omega(0),
            });
            let (hi, hc) = cylinder::housner_cylinder_heights(radius, h);
            masses.push(MassEntry {
                source: "Housner 1963".into(),
                impulsive_mass: liquid_mass
                    * cylinder::housner_cylinder_impulsive_mass_ratio(radius, h),
                impulsive_height: hi,
                convective_mass: liquid_mass
                    * cylinder::housner_cylinder_convective_mass_ratio(radius, h),
                convective_height: hc,
                convective_period: 2.0 * PI
                    / cylinder::housner_cylinder_convective_omega(radius, h, g),
            });
            let c = codes::api650_circular_masses(2.0 * radius, h);
            masses.push(code_masses_entry(
                "API 650 Annex E",
                c,
                liquid_mass,
                h,
                code_period,
            ));
        }
    }

    // Excitation
    let sine_pga = input.sine.map(|s| s.amplitude * s.omega * s.omega);
    let pga = input.peak_ground_accel.or(sine_pga);
    let (spectral, spectral_source) = match (input.spectral_accel_g, pga) {
        (Some(sa), _) => (Some(sa), Some("given".to_string())),
        (None, Some(a)) => {
            let se =
                codes::ec8_elastic_spectrum(code_period, a, Ec8GroundType::A.type1_shape(), 0.005);
            (
                Some(se / g),
                Some("EC8 type 1, ground A, a_g = PGA, 0.5 % damping".to_string()),
            )
        }
        _ => (None, None),
    };
    // Housner (rectangular) / Housner 1963 (cylinder) masses for the base shear
    let housner_entry = &masses[1];
    let v_i = pga.map(|a| housner_entry.impulsive_mass * a);
    let v_c = spectral.map(|sa| housner_entry.convective_mass * sa * g);
    let v_srss = match (v_i, v_c) {
        (Some(a), Some(b)) => Some((a * a + b * b).sqrt()),
        (Some(a), None) => Some(a.abs()),
        _ => None,
    };

    let mut wave_heights = Vec::new();
    if let Some(sa) = spectral {
        match input.shape {
            TankShape::Rectangular { width } => {
                wave_heights.push(WaveHeightEntry {
                    source: "ACI 350.3 (L/2) A_f".into(),
                    height: codes::aci350_rectangular_wave_height(width, sa),
                });
                wave_heights.push(WaveHeightEntry {
                    source: "EC8-4 0.5 L S_e/g".into(),
                    height: codes::ec8_rectangular_wave_height(width, sa),
                });
            }
            TankShape::Cylindrical { radius } => {
                wave_heights.push(WaveHeightEntry {
                    source: "API 650 / ASCE 7 0.42 D A_f".into(),
                    height: codes::api650_wave_height(2.0 * radius, sa),
                });
                wave_heights.push(WaveHeightEntry {
                    source: "EC8-4 0.84 R S_e/g".into(),
                    height: codes::ec8_circular_wave_height(radius, sa),
                });
            }
        }
    }

    let sine_response = input.sine.map(|s| linear_sine_peak(input, s));
    if let Some(sr) = &sine_response {
        wave_heights.push(WaveHeightEntry {
            source: "linear theory, sine".into(),
            height: sr.max_wall_elevation,
        });
    }
    let required = wave_heights
        .iter()
        .map(|w| w.height)
        .fold(None, |acc: Option<f64>, x| {
            Some(acc.map_or(x, |a| a.max(x)))
        });
    let available = input.tank_height.map(|t| t - h);

    TankReport {
        shape: shape.into(),
        plan_size,
        depth: h,
        gravity: g,
        density: rho,
        mass_unit: mass_unit.into(),
        force_unit: force_unit.into(),
        liquid_mass,
        modes,
        code_convective_period: code_period,
        api650_convective_period: api_period,
        masses,
        peak_ground_accel: pga,
        spectral_accel_g: spectral,
        spectral_accel_source: spectral_source,
        base_shear_impulsive: v_i,
        base_shear_convective: v_c,
        base_shear_srss: v_srss,
        wave_heights,
        sine_response,
        freeboard: codes::freeboard_check(available, required),
    }
}

fn code_masses_entry(
    source: &str,
    c: codes::CodeMasses,
    mass: f64,
    depth: f64,
    period: f64,
) -> MassEntry {
    MassEntry {
        source: source.into(),
        impulsive_mass: c.impulsive_mass_ratio * mass,
        impulsive_height: c.impulsive_height_ratio * depth,
        convective_mass: c.convective_mass_ratio * mass,
        convective_height: c.convective_height_ratio * depth,
        convective_period: period,
    }
}

/// Peak left-wall crest and base shear of the linear solution (10 modes), sampled at T₁/400.
fn linear_sine_peak(input: &TankInput, s: SineExcitation) -> SineResponse {
    let force = -s.amplitude * s.omega * s.omega;
    let (g, rho, h) = (input.gravity, input.density, input.depth);
    let n_modes = 10;
    let mut best = (f64::MIN, 0.0);
    let mut max_shear = 0.0f64;
    let mut scan = |w1: f64, eval: &dyn Fn(f64) -> (f64, f64)| {
        let dt = 2.0 * PI / w1.max(s.omega) / 400.0;
        let steps = (s.duration / dt).ceil() as usize;
        for k in 0..=steps {
            let t = (k as f64 * dt).min(s.duration);
            let (eta, shear) = eval(t);
            if eta > best.0 {
                best = (eta, t);
            }
            max_shear = max_shear.max(shear.abs());
        }
    };
    match input.shape {
        TankShape::Rectangular { width } => {
            let tank = RectangularTank {
                width,
                depth: h,
                density: rho,
                gravity: g,
            };
            scan(tank.modal_omega(0), &|t| {
                let st = sine_response(&tank, force, s.omega, t, n_modes);
                (tank.elevation(&st, 0.0), tank.base_shear(&st))
            });
        }
        TankShape::Cylindrical { radius } => {
            let tank = CylindricalTank::new(radius, h, rho, g);
            scan(tank.modal_omega(0), &|t| {
                let st = sine_response(&tank, force, s.omega, t, n_modes);
                // the −x wall (θ = π) rises when the +x wall falls
                (-tank.wall_elevation(&st), tank.base_shear(&st))
            });
        }
    }
    SineResponse {
        peak_ground_accel: s.amplitude * s.omega * s.omega,
        max_wall_elevation: best.0,
        time_of_max: best.1,
        max_abs_base_shear: max_shear,
    }
}

fn opt(v: Option<f64>, prec: usize) -> String {
    v.map_or_else(|| "-".to_string(), |x| sig(x, prec))
}

/// Fixed-point with `prec` decimals, or 5-digit scientific notation for large/small values.
fn sig(x: f64, prec: usize) -> String {
    if x != 0.0 && (x.abs() >= 1e5 || x.abs() < 1e-3) {
        format!("{x:.4e}")
    } else {
        format!("{x:.prec$}")
    }
}

impl fmt::Display for TankReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let size_name = if self.shape == "rectangular" {
            "width L"
        } else {
            "diameter D"
        };
        writeln!(
            f,
            "Tank: {} ({size_name} = {:.4} m, depth H = {:.4} m)",
            self.shape, self.plan_size, self.depth
        )?;
        writeln!(
            f,
            "  density {:.1} kg/m3, g = {:.4} m/s2, liquid mass {:.4e} {}{}",
            self.density,
            self.gravity,
            self.liquid_mass,
            self.mass_unit,
            if self.shape == "rectangular" {
                "  (2D: per metre of tank length)"
            } else {
                ""
            }
        )?;
        writeln!(f)?;
        writeln!(f, "Natural sloshing modes (linear potential theory)")?;
        writeln!(
            f,
            "  {:<12} {:>14} {:>12} {:>8}",
            "mode", "omega [rad/s]", "period [s]", "excited"
        )?;
        for m in &self.modes {
            writeln!(
                f,
                "  {:<12} {:>14.3} {:>12.3} {:>8}",
                m.mode,
                m.omega,
                m.period,
                if m.excited { "yes" } else { "no" }
            )?;
        }
        writeln!(
            f,
            "  code convective period T_c            {:>10.3} s",
            self.code_convective_period
        )?;
        if let Some(t) = self.api650_convective_period {
            writeln!(f, "  API 650 T_c = 1.8 K_s sqrt(D) (SI)      {:>10.3} s", t)?;
        }
        writeln!(f)?;
        let mu = &self.mass_unit;
        writeln!(
            f,
            "Impulsive / convective model (heights above bottom, base pressure excluded)"
        )?;
        writeln!(
            f,
            "  {:<28} {:>14} {:>9} {:>14} {:>9} {:>9}",
            "source",
            format!("m_i [{mu}]"),
            "h_i [m]",
            format!("m_c [{mu}]"),
            "h_c [m]",
            "T_c [s]"
        )?;
        for m in &self.masses {
            writeln!(
                f,
                "  {:<28} {:>14.4e} {:>9.4} {:>14.4e} {:>9.4} {:>9.3}",
                m.source,
                m.impulsive_mass,
                m.impulsive_height,
                m.convective_mass,
                m.convective_height,
                m.convective_period
            )?;
        }
        writeln!(f)?;
        let fu = &self.force_unit;
        writeln!(f, "Excitation and loads (Housner masses)")?;
        writeln!(
            f,
            "  peak ground acceleration          {:>14} m/s2",
            opt(self.peak_ground_accel, 4)
        )?;
        writeln!(
            f,
            "  convective spectral accel S_a(T_c) {:>13} g{}",
            opt(self.spectral_accel_g, 4),
            self.spectral_accel_source
                .as_ref()
                .map_or(String::new(), |s| format!("  ({s})"))
        )?;
        writeln!(
            f,
            "  base shear, impulsive             {:>14} {fu}",
            opt(self.base_shear_impulsive, 2)
        )?;
        writeln!(
            f,
            "  base shear, convective            {:>14} {fu}",
            opt(self.base_shear_convective, 2)
        )?;
        writeln!(
            f,
            "  base shear, SRSS                  {:>14} {fu}",
            opt(self.base_shear_srss, 2)
        )?;
        if let Some(s) = &self.sine_response {
            writeln!(f)?;
            writeln!(f, "Linear theory, sine excitation (10 modes, from rest)")?;
            writeln!(
                f,
                "  peak ground acceleration A W^2    {:>14.4} m/s2",
                s.peak_ground_accel
            )?;
            writeln!(
                f,
                "  max crest at -x wall              {:>14.4} m   at t = {:.3} s",
                s.max_wall_elevation, s.time_of_max
            )?;
            writeln!(
                f,
                "  max |base shear|                  {:>14} {fu}",
                sig(s.max_abs_base_shear, 2)
            )?;
        }
        writeln!(f)?;
        writeln!(f, "Sloshing wave height")?;
        if self.wave_heights.is_empty() {
            writeln!(f, "  (no excitation given)")?;
        }
        for w in &self.wave_heights {
            writeln!(f, "  {:<33} {:>14.4} m", w.source, w.height)?;
        }
        writeln!(f)?;
        writeln!(f, "Freeboard")?;
        writeln!(
            f,
            "  available (roof height - depth)   {:>14} m",
            opt(self.freeboard.available, 4)
        )?;
        writeln!(
            f,
            "  required (largest wave height)    {:>14} m",
            opt(self.freeboard.required, 4)
        )?;
        writeln!(
            f,
            "  verdict                           {:>14}",
            self.freeboard.verdict.to_string()
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cli_acceptance_rectangular() {
        // Acceptance: width 1.0, depth 0.5, g = 9.81 shows ω₁ = 5.317 rad/s, T₁ = 1.182 s
        // (hand values in natural.rs); the text must contain them at 3 decimals.
        let r = tank_report(&TankInput::rectangular(1.0, 0.5));
        assert!((r.modes[0].omega - 5.3166).abs() < 1e-4);
        let text = r.to_string();
        assert!(text.contains("5.317") && text.contains("1.182"), "{text}");
        assert_eq!(r.freeboard.verdict, codes::FreeboardVerdict::NotEvaluated);
        // ρLH = 500 kg/m
        assert!((r.liquid_mass - 500.0).abs() < 1e-9);
    }

    #[test]
    fn cli_acceptance_cylinder() {
        // radius 0.5, depth 0.5 → ω₁ ≈ 5.861 rad/s (hand value 5.8609, natural.rs)
        let r = tank_report(&TankInput::cylindrical(0.5, 0.5));
        assert!((r.modes[0].omega - 5.861).abs() < 1e-3);
        assert!(r.to_string().contains("5.861"));
    }

    #[test]
    fn paper_sine_case_and_freeboard() {
        // Paper §3.1 tank with a 1.0 m roof, sine A = 0.0093 m, Ω = 5.311, 10 s: the crest
        // (≈ 0.289 m at 10.05 s, see linear.rs) is below the 0.5 m freeboard → OK;
        // with the 0.6 m roof of §3.2 (H′ = 0.1 m) → INSUFFICIENT. PGA = AΩ² = 0.262322 m/s².
        let mut input = TankInput::rectangular(1.0, 0.5);
        input.tank_height = Some(1.0);
        input.sine = Some(SineExcitation {
            amplitude: 0.0093,
            omega: 5.311,
            duration: 10.1,
        });
        let r = tank_report(&input);
        let s = r.sine_response.as_ref().unwrap();
        assert!((s.peak_ground_accel - 0.262322).abs() < 1e-6);
        assert!(
            (s.max_wall_elevation - 0.289).abs() < 0.01,
            "{}",
            s.max_wall_elevation
        );
        assert_eq!(r.freeboard.verdict, codes::FreeboardVerdict::Ok);
        // Housner impulsive base shear m_i·PGA = 71.1293 N/m (housner.rs hand value)
        assert!((r.base_shear_impulsive.unwrap() - 71.1293).abs() < 1e-3);
        input.tank_height = Some(0.6);
        assert_eq!(
            tank_report(&input).freeboard.verdict,
            codes::FreeboardVerdict::Insufficient
        );
    }

    #[test]
    fn spectral_wave_heights_cylinder() {
        // D = 30 m, H = 15 m, A_f = 0.1 g: API δ_s = 1.26 m, EC8 0.84·15·0.1 = 1.26 m;
        // roof 2 m above the liquid → OK.
        let mut input = TankInput::cylindrical(15.0, 15.0);
        input.spectral_accel_g = Some(0.1);
        input.tank_height = Some(17.0);
        let r = tank_report(&input);
        assert_eq!(r.wave_heights.len(), 2);
        assert!(r
            .wave_heights
            .iter()
            .all(|w| (w.height - 1.26).abs() < 1e-9));
        assert_eq!(r.freeboard.verdict, codes::FreeboardVerdict::Ok);
        assert!((r.freeboard.required.unwrap() - 1.26).abs() < 1e-9);
    }
}
