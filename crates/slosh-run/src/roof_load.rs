//! Roof loads in the forms a roof is designed with, defined so that they can converge with
//! resolution (`docs/roof-loads.md`):
//!
//! - the **impulse** ∫ F dt of the upward roof force, from the wall pressures of every step
//!   (not the ±N-step window of paper §2.6, so no design output depends on N);
//! - the **pressure on a sensor** of finite area (a disc in 3D, a segment in 2D), the
//!   area-weighted mean of the roof load points on it, as a transducer reads it;
//! - the **roof's response**: each load through a single-degree-of-freedom oscillator of
//!   natural period T_r and damping ratio ζ_r, whose peak spring force k·max|u| is the
//!   equivalent static load F_eq(T_r) (Chopra, *Dynamics of Structures*, §6.2); over T_r it is
//!   the roof load spectrum, and F_eq / max|F| the dynamic load factor;
//! - **impacts** as contact episodes of the roof force with thresholds relative to the tank's
//!   freeboard head ρ g H′ over the roof's plan area and a merge rule tied to the sloshing
//!   period, so that one particle touching the roof is not an impact; an episode too small for
//!   the whole roof is still an impact when a sensor on the roof takes the same impulse per
//!   area (a local impact on an instrumented panel);
//! - **statistics** of the impacts (median, 84th percentile, maximum).

use serde::{Deserialize, Serialize};
use slosh_core::Simulation;

/// Default damping ratio ζ_r of the roof oscillator: 2 % of critical, a welded steel roof
/// (ASCE 4-16 Table 3-2 gives 2–4 % for welded steel at and below yield).
pub const DEFAULT_ROOF_DAMPING: f64 = 0.02;

/// Default roof periods T_r (s) at which `summary.ron` gives F_eq: a stiff to a flexible
/// roof panel.
pub const DEFAULT_ROOF_PERIODS: [f64; 4] = [0.02, 0.05, 0.1, 0.2];

/// The roof load spectrum's periods: `SPECTRUM_POINTS` log-spaced from `SPECTRUM_RANGE.0` to
/// `SPECTRUM_RANGE.1` (s), 20 per decade.
pub const SPECTRUM_RANGE: (f64, f64) = (0.005, 2.0);
/// Points of the roof load spectrum.
pub const SPECTRUM_POINTS: usize = 53;

/// How far below the roof the roof load starts, in particle spacings dx: the liquid's highest
/// particle is ≈ 2–2.8 dx below the roof face at the first roof force, and raising the roof by
/// 1 dx at dx = 0.02 and 0.01 m gives the first impact and the kinetic energy of the run at
/// dx = 0.005 m (2D resonant sloshing, modern preset, h = 2 dx; `docs/roof-loads.md`, *Why the
/// roof load moves with resolution*). The roof is felt through the kernel's support before
/// the liquid reaches it, so the clearance the roof load sees is short by about this much.
pub const ROOF_REACH_SPACINGS: f64 = 2.0;

/// Particle spacings the roof clearance needs for the roof's reach
/// ([`ROOF_REACH_SPACINGS`]) to shorten it by at most 5 %.
pub const CLEARANCE_SPACINGS_FOR_ROOF_LOADS: f64 = ROOF_REACH_SPACINGS / 0.05;

/// The warning of a roofed run whose clearance `freeboard` H′ (m, at the wall) holds fewer
/// than [`CLEARANCE_SPACINGS_FOR_ROOF_LOADS`] particle spacings `dx` (m): its roof loads see a
/// clearance short by ≈ 2 dx, 5 % of it at dx = H′/40.
pub fn clearance_resolution_warning(freeboard: f64, dx: f64) -> Option<String> {
    let spacings = freeboard / dx;
    (freeboard > 0.0 && dx > 0.0 && spacings < CLEARANCE_SPACINGS_FOR_ROOF_LOADS).then(|| {
        format!(
            "the roof clearance H′ = {freeboard:.4} m holds {spacings:.1} particle spacings \
             (dx = {dx} m): the roof load starts ≈ {ROOF_REACH_SPACINGS} dx = {:.4} m before \
             the liquid reaches the roof (the kernel's reach), so the clearance the roof load \
             sees is ≈ {:.0} % short and the roof loads move with dx; the shortfall is 5 % at \
             dx = H′/{CLEARANCE_SPACINGS_FOR_ROOF_LOADS:.0} = {:.4} m (docs/roof-loads.md; \
             check with slosh converge)",
            ROOF_REACH_SPACINGS * dx,
            100.0 * ROOF_REACH_SPACINGS * dx / freeboard,
            freeboard / CLEARANCE_SPACINGS_FOR_ROOF_LOADS,
        )
    })
}

/// An impact starts when the roof force, averaged over an output interval, exceeds this
/// fraction of the freeboard force F_ref = ρ g H′ A_roof, and ends when it falls below
/// [`IMPACT_OFF`]: a crest one freeboard high pressing on 2 % of the roof, far above what a
/// single particle's pressure gives (its share of F_ref is of order dx²/(H′ L)).
pub const IMPACT_ON: f64 = 0.02;
/// End of an impact, as a fraction of F_ref (hysteresis: half of [`IMPACT_ON`]).
pub const IMPACT_OFF: f64 = 0.01;
/// Contact episodes closer than this fraction of the first sloshing period are one impact
/// (a crest that bounces on the roof); crests at opposite walls come half a period apart.
pub const IMPACT_MERGE: f64 = 0.25;
/// Episodes whose impulse is below this fraction of F_ref·T₁ are splashes, not impacts (a
/// crest one freeboard high pressing on the whole roof for 1 % of a period), unless a sensor
/// on the roof takes that impulse per area, ρ g H′ T₁ / 100 (a local impact on the panel it
/// instruments).
pub const IMPACT_MIN_IMPULSE: f64 = 0.01;
/// Largest step of the oscillator's integration as a fraction of its period over 2π
/// (ω·h ≤ 0.1): the trapezoidal rule's period error is (ωh)²/12 ≤ 0.08 %.
const MAX_OMEGA_STEP: f64 = 0.1;

/// A pressure transducer of finite face, as an experiment's: a disc (3D) or a segment (2D)
/// flush with the roof or with a wall, reading the area-weighted mean pressure of the load
/// points on its face.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PressureSensor {
    /// Name (series column `p_<name>`).
    pub name: String,
    /// Horizontal position of its centre (x in 2D; x, y in 3D) (m).
    pub horizontal: Vec<f64>,
    /// Diameter (3D) or length (2D) (m).
    pub diameter: f64,
    /// Height of its centre (m) for a sensor on a wall: its face is centred on the wall
    /// point (`horizontal`, `height`) and lies in that wall. `None`: on the roof, centred
    /// above `horizontal`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<f64>,
}

impl PressureSensor {
    /// The sensor's kind as scripts name it: `roof_sensor` or `wall_sensor`.
    pub fn kind(&self) -> &'static str {
        if self.height.is_some() {
            "wall_sensor"
        } else {
            "roof_sensor"
        }
    }
}

/// What a run measures of the roof load beyond the part totals.
#[derive(Clone, Debug, PartialEq)]
pub struct RoofLoadPlan {
    /// Pressure sensors on the roof and on walls.
    pub sensors: Vec<PressureSensor>,
    /// Damping ratio ζ_r of the roof oscillator (1).
    pub damping_ratio: f64,
    /// Roof periods T_r at which F_eq is reported (s).
    pub design_periods: Vec<f64>,
}

impl Default for RoofLoadPlan {
    fn default() -> Self {
        RoofLoadPlan {
            sensors: Vec::new(),
            damping_ratio: DEFAULT_ROOF_DAMPING,
            design_periods: DEFAULT_ROOF_PERIODS.to_vec(),
        }
    }
}

/// The periods of the roof load spectrum (s), ascending.
pub fn spectrum_periods() -> Vec<f64> {
    let (lo, hi) = SPECTRUM_RANGE;
    (0..SPECTRUM_POINTS)
        .map(|i| lo * (hi / lo).powf(i as f64 / (SPECTRUM_POINTS - 1) as f64))
        .collect()
}

/// Single-degree-of-freedom oscillators of unit mass, ü + 2ζω u̇ + ω² u = f(t), one per
/// period, driven by one load sampled at the solver's steps and taken linear between them.
/// Integrated by the trapezoidal rule (Newmark's average acceleration: no numerical damping)
/// with sub-steps of ω·h ≤ 0.1. The equivalent static load is ω²·max|u| (the load's unit).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct OscillatorBank {
    omega: Vec<f64>,
    zeta: f64,
    u: Vec<f64>,
    v: Vec<f64>,
    max_abs_u: Vec<f64>,
    /// max|u| since the last [`Self::take_interval`].
    interval_max_abs_u: Vec<f64>,
    /// The last sample (time, load).
    last: Option<(f64, f64)>,
}

impl OscillatorBank {
    /// Oscillators of natural periods `periods` (s) and damping ratio `zeta`, at rest.
    pub fn new(periods: &[f64], zeta: f64) -> Self {
        let n = periods.len();
        OscillatorBank {
            omega: periods
                .iter()
                .map(|t| 2.0 * std::f64::consts::PI / t)
                .collect(),
            zeta,
            u: vec![0.0; n],
            v: vec![0.0; n],
            max_abs_u: vec![0.0; n],
            interval_max_abs_u: vec![0.0; n],
            last: None,
        }
    }

    /// Advances every oscillator to time `t` (s) where the load is `f`. The first sample sets
    /// the load's start (the oscillators are at rest until then).
    pub fn push(&mut self, t: f64, f: f64) {
        if !f.is_finite() {
            // A non-finite load (a blown-up step) is skipped: the run reports its failure.
            return;
        }
        let Some((t0, f0)) = self.last.replace((t, f)) else {
            return;
        };
        let dt = t - t0;
        if dt <= 0.0 {
            return;
        }
        let zeta = self.zeta;
        for i in 0..self.omega.len() {
            let w = self.omega[i];
            let subs = ((w * dt) / MAX_OMEGA_STEP).ceil().max(1.0);
            let h = dt / subs;
            // Trapezoidal rule on x' = A x + b f, A = [[0, 1], [−ω², −2ζω]], b = [0, 1]:
            // (I − hA/2) x₁ = (I + hA/2) x₀ + h/2 (f₀ + f₁) b.
            let det = 1.0 + h * zeta * w + 0.25 * h * h * w * w;
            let (mut u, mut v) = (self.u[i], self.v[i]);
            let mut max: f64 = 0.0;
            for s in 0..subs as usize {
                let fa = f0 + (f - f0) * (s as f64 / subs);
                let fb = f0 + (f - f0) * ((s + 1) as f64 / subs);
                let ru = u + 0.5 * h * v;
                let rv = -0.5 * h * w * w * u + (1.0 - h * zeta * w) * v + 0.5 * h * (fa + fb);
                u = ((1.0 + h * zeta * w) * ru + 0.5 * h * rv) / det;
                v = (-0.5 * h * w * w * ru + rv) / det;
                max = max.max(u.abs());
            }
            self.u[i] = u;
            self.v[i] = v;
            self.max_abs_u[i] = self.max_abs_u[i].max(max);
            self.interval_max_abs_u[i] = self.interval_max_abs_u[i].max(max);
        }
    }

    /// The equivalent static load ω²·max|u| of each oscillator so far.
    pub fn equivalent_static(&self) -> Vec<f64> {
        self.omega
            .iter()
            .zip(&self.max_abs_u)
            .map(|(w, u)| w * w * u)
            .collect()
    }

    /// The largest |ω²u| of the oscillators `from..` since the previous call; restarts the
    /// maxima of all.
    fn take_interval(&mut self, from: usize) -> Vec<f64> {
        let out = (from..self.omega.len())
            .map(|i| self.omega[i] * self.omega[i] * self.interval_max_abs_u[i])
            .collect();
        self.interval_max_abs_u.iter_mut().for_each(|m| *m = 0.0);
        out
    }
}

/// One measured load of the roof: the upward roof force or a sensor's mean pressure.
#[derive(Clone, Debug, Serialize, Deserialize)]
struct Channel {
    /// Oscillators at the spectrum's periods, then at the design periods.
    bank: OscillatorBank,
    /// ∫ max(f, 0) dt so far.
    impulse: f64,
    /// Largest load so far and its time.
    peak: f64,
    t_peak: f64,
    /// Largest load since the last output row.
    interval_peak: f64,
}

/// What the monitor keeps at every output row: the cumulative impulse, the largest load and
/// the largest design-period F_eq since the previous row, for each channel.
#[derive(Clone, Debug, Serialize, Deserialize)]
struct RowCut {
    time: f64,
    impulse: Vec<f64>,
    peak: Vec<f64>,
    f_eq: Vec<Vec<f64>>,
}

/// Measures the roof load of every step: the roof force's and each sensor's impulse, peak and
/// oscillator response, cut at every output row for the impacts.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct RoofLoadMonitor {
    /// Load-point index and A·n_z of each roof point (the upward force is Σ p A n_z).
    roof: Vec<(usize, f64)>,
    /// Each sensor's load points and their area weights (summing to 1).
    sensors: Vec<Vec<(usize, f64)>>,
    /// Sensor areas (m²; 2D m).
    sensor_area: Vec<f64>,
    /// Whether each sensor's face lies on the roof (a roof panel the impacts are also found
    /// on). Not in checkpoints (their encoding is positional, and it follows from the tank
    /// and the plan): [`Self::resumed`] takes it from the monitor built for the run.
    #[serde(skip)]
    sensor_on_roof: Vec<bool>,
    /// Roof plan area Σ A |n_z| (m²; 2D m).
    plan_area: f64,
    channels: Vec<Channel>,
    rows: Vec<RowCut>,
    /// Steps of the load evaluator already taken in.
    seen: u64,
    design_periods: Vec<f64>,
    damping_ratio: f64,
}

/// The part index of the roof in a simulation's parts, if it has one.
fn roof_part<const D: usize>(sim: &Simulation<D>) -> Option<u16> {
    sim.part_names()
        .iter()
        .position(|n| n == "roof")
        .map(|k| k as u16)
}

/// The roof load points on a roof sensor's face and their areas (m²; 2D m): 2D, each roof
/// point stands for a patch of the roof whose horizontal extent is its length times |n_z|, and
/// counts with the part of that patch on the sensor's segment, so that the sensor covers the
/// same length at every resolution; 3D, a point whose centre is on the disc counts with its
/// whole area, and a disc narrower than the spacing reads the nearest roof point within one
/// spacing of its centre.
fn roof_sensor_points<const D: usize>(
    sim: &Simulation<D>,
    roof: &[(usize, f64)],
    s: &PressureSensor,
) -> Result<Vec<(usize, f64)>, String> {
    let loads = sim.loads();
    let radius = 0.5 * s.diameter;
    let mut on: Vec<(usize, f64)> = roof
        .iter()
        .filter_map(|&(k, _)| {
            let p = loads.positions()[k];
            let area = loads.areas()[k];
            if D == 2 {
                let half = 0.5 * area * loads.normals()[k][D - 1].abs();
                let segment = (s.horizontal[0] - radius, s.horizontal[0] + radius);
                segment_overlap(area, p[0], half, segment).map(|a| (k, a))
            } else {
                let d2: f64 = (0..D - 1).map(|a| (p[a] - s.horizontal[a]).powi(2)).sum();
                (d2.sqrt() <= radius).then_some((k, area))
            }
        })
        .collect();
    if on.is_empty() && D == 3 {
        let distance = |k: usize| -> f64 {
            let p = loads.positions()[k];
            (0..D - 1)
                .map(|a| (p[a] - s.horizontal[a]).powi(2))
                .sum::<f64>()
                .sqrt()
        };
        if let Some(k) = roof
            .iter()
            .map(|&(k, _)| k)
            .min_by(|&a, &b| distance(a).total_cmp(&distance(b)))
            .filter(|&k| distance(k) <= sim.spacing())
        {
            on.push((k, loads.areas()[k]));
        }
    }
    if on.is_empty() {
        return Err(if roof.is_empty() {
            format!(
                "roof_sensor \"{}\": the tank has no roof to put it on",
                s.name
            )
        } else {
            format!(
                "roof_sensor \"{}\" at {:?} (diameter {} m) covers no point of the roof: put \
                 its centre below the roof, inside the tank",
                s.name, s.horizontal, s.diameter
            )
        });
    }
    Ok(on)
}

/// The area of a load point of area `area` standing for the patch [c − half, c + half] of a
/// 2D wall that lies on the segment [from, to] (m), `None` when they do not overlap.
fn segment_overlap(area: f64, c: f64, half: f64, (from, to): (f64, f64)) -> Option<f64> {
    let lo = (c - half).max(from);
    let hi = (c + half).min(to);
    (hi > lo && half > 0.0).then(|| area * (hi - lo) / (2.0 * half))
}

/// Largest distance (in particle spacings) from a wall sensor's centre to the nearest wall
/// face: a centre off the wall by more is a mistake in the script, not a sensor.
const WALL_SENSOR_REACH_SPACINGS: f64 = 1.0;

/// The load points on a wall sensor's face and their areas (m²; 2D m). The face is the wall
/// of the load point nearest to the sensor's centre (`horizontal`, `height`): the load points
/// whose wall faces (half a spacing inside their particles, along −n) lie in that wall's
/// plane within half a spacing and whose normals are within 25° of its normal. 2D, each counts
/// with the part of its length on the sensor's segment along the wall (as a roof sensor's);
/// 3D, a point whose face centre is on the disc counts with its whole area, and a disc
/// narrower than the spacing reads the nearest point. Any part (walls, bottom, roof, solids)
/// can carry one.
fn wall_sensor_points<const D: usize>(
    sim: &Simulation<D>,
    s: &PressureSensor,
    height: f64,
) -> Result<Vec<(usize, f64)>, String> {
    let loads = sim.loads();
    let spacing = sim.spacing();
    let mut centre = slosh_core::Vector::<D>::zeros();
    for (a, x) in s.horizontal.iter().enumerate() {
        centre[a] = *x;
    }
    centre[D - 1] = height;
    let face = |k: usize| loads.positions()[k] - loads.normals()[k] * (0.5 * spacing);
    let Some((nearest, distance)) = (0..loads.len())
        .map(|k| (k, (face(k) - centre).norm()))
        .min_by(|a, b| a.1.total_cmp(&b.1))
    else {
        return Err(format!("wall_sensor \"{}\": the tank has no walls", s.name));
    };
    if distance > WALL_SENSOR_REACH_SPACINGS * spacing {
        let f = face(nearest);
        return Err(format!(
            "wall_sensor \"{}\" at {:?} is {distance:.4} m from the nearest wall face (at \
             {:?}, part {}): put its centre on a wall of the tank, within one particle spacing \
             ({spacing} m)",
            s.name,
            centre.as_slice(),
            f.as_slice(),
            sim.part_names()
                .get(loads.parts()[nearest] as usize)
                .map_or("?", String::as_str),
        ));
    }
    let n0 = loads.normals()[nearest];
    // The centre taken onto the plane of the nearest face (a centre off the wall by up to a
    // spacing, as a tank fitted to the lattice moves its walls by up to half one).
    let on_face = centre - n0 * (centre - face(nearest)).dot(&n0);
    let radius = 0.5 * s.diameter;
    let same_face = |k: usize| {
        loads.normals()[k].dot(&n0) > 25f64.to_radians().cos()
            && (face(k) - on_face).dot(&n0).abs() <= 0.5 * spacing
    };
    let on: Vec<(usize, f64)> = (0..loads.len())
        .filter(|&k| same_face(k))
        .filter_map(|k| {
            let d = face(k) - on_face;
            let area = loads.areas()[k];
            if D == 2 {
                // Along the wall: the tangent (n_z, −n_x) of the section.
                let along = d[0] * n0[D - 1] - d[D - 1] * n0[0];
                segment_overlap(area, along, 0.5 * area, (-radius, radius)).map(|a| (k, a))
            } else {
                let in_plane = d - n0 * d.dot(&n0);
                (in_plane.norm() <= radius).then_some((k, area))
            }
        })
        .collect();
    if on.is_empty() {
        // A disc narrower than the spacing reads the nearest point.
        return Ok(vec![(nearest, loads.areas()[nearest])]);
    }
    // A face that runs off its wall (past a corner or the wall's end) is refused: in 2D the
    // segment's overlap is exact, so under half of it on the wall is the wall's end; in 3D
    // the disc's points are a lattice's, whose area on an unbroken wall is at least a third
    // of the disc's, so under a quarter is the wall's end.
    let (nominal, least) = if D == 2 {
        (s.diameter, 0.5)
    } else {
        (std::f64::consts::PI * radius * radius, 0.25)
    };
    let area: f64 = on.iter().map(|(_, a)| a).sum();
    if area < least * nominal {
        return Err(format!(
            "wall_sensor \"{}\" at {:?}: only {:.0} % of its face (diameter {} m) lies on \
             the wall it is on (part {}); the wall ends within its radius: move it away from \
             the corner or the wall's end, or make it smaller",
            s.name,
            centre.as_slice(),
            100.0 * area / nominal,
            s.diameter,
            sim.part_names()
                .get(loads.parts()[nearest] as usize)
                .map_or("?", String::as_str),
        ));
    }
    Ok(on)
}

impl RoofLoadMonitor {
    /// The roof points of `sim` and the sensors of `plan`. A sensor that covers no roof load
    /// point, or is declared in a tank without a roof, is an error (its message names it).
    pub fn new<const D: usize>(sim: &Simulation<D>, plan: &RoofLoadPlan) -> Result<Self, String> {
        let loads = sim.loads();
        let roof_id = roof_part(sim);
        let roof: Vec<(usize, f64)> = (0..loads.len())
            .filter(|&k| Some(loads.parts()[k]) == roof_id)
            .map(|k| (k, loads.areas()[k] * loads.normals()[k][D - 1]))
            .collect();
        // Folded from +0: an open tank's plan area is 0, not the −0 of an empty f64 sum.
        let plan_area = roof
            .iter()
            .map(|&(k, _)| loads.areas()[k] * loads.normals()[k][D - 1].abs())
            .fold(0.0, |a, x| a + x);
        let mut sensors = Vec::new();
        let mut sensor_area = Vec::new();
        let mut sensor_on_roof = Vec::new();
        for s in &plan.sensors {
            let kind = s.kind();
            let coordinates = s.horizontal.len() + usize::from(s.height.is_some());
            let wanted = if s.height.is_some() { D } else { D - 1 };
            if coordinates != wanted {
                return Err(format!(
                    "{kind} \"{}\" gives {coordinates} coordinate(s) for a {D}D tank (wants {wanted})",
                    s.name
                ));
            }
            if !(s.diameter.is_finite() && s.diameter > 0.0) {
                return Err(format!(
                    "{kind} \"{}\": the diameter must be > 0 m (got {})",
                    s.name, s.diameter
                ));
            }
            let on = match s.height {
                None => roof_sensor_points(sim, &roof, s)?,
                Some(height) => wall_sensor_points(sim, s, height)?,
            };
            let area: f64 = on.iter().map(|(_, a)| a).sum();
            sensor_on_roof.push(on.iter().all(|&(k, _)| Some(loads.parts()[k]) == roof_id));
            sensor_area.push(area);
            sensors.push(on.into_iter().map(|(k, a)| (k, a / area)).collect());
        }
        let mut periods = spectrum_periods();
        periods.extend_from_slice(&plan.design_periods);
        let channels = (0..=plan.sensors.len())
            .map(|_| Channel {
                bank: OscillatorBank::new(&periods, plan.damping_ratio),
                impulse: 0.0,
                peak: 0.0,
                t_peak: 0.0,
                interval_peak: 0.0,
            })
            .collect();
        Ok(RoofLoadMonitor {
            roof,
            sensors,
            sensor_area,
            sensor_on_roof,
            plan_area,
            channels,
            rows: Vec::new(),
            seen: 0,
            design_periods: plan.design_periods.clone(),
            damping_ratio: plan.damping_ratio,
        })
    }

    /// The monitor of a checkpoint, `saved`, continued in the run this monitor was built for:
    /// the saved measurements with what follows from the tank and the plan alone.
    pub fn resumed(self, saved: RoofLoadMonitor) -> RoofLoadMonitor {
        RoofLoadMonitor {
            sensor_on_roof: self.sensor_on_roof,
            ..saved
        }
    }

    /// True when the tank has a roof with load points.
    pub fn has_roof(&self) -> bool {
        !self.roof.is_empty()
    }

    /// True when the monitor measures anything: a roof, or pressure sensors (a wall sensor
    /// works in an open tank too).
    pub fn measures(&self) -> bool {
        self.has_roof() || !self.sensors.is_empty()
    }

    /// The sensors' areas (m²; 2D m), in declaration order.
    pub fn sensor_areas(&self) -> &[f64] {
        &self.sensor_area
    }

    /// The mean pressure on sensor `i` from load-point pressures `pressure` (Pa).
    pub fn sensor_pressure(&self, i: usize, pressure: &[f64]) -> f64 {
        self.sensors[i].iter().map(|&(k, w)| w * pressure[k]).sum()
    }

    /// Number of sensors.
    pub fn sensor_count(&self) -> usize {
        self.sensors.len()
    }

    /// Takes in the wall pressures of the solver's latest step, once per step.
    pub fn after_step<const D: usize>(&mut self, sim: &Simulation<D>) {
        let loads = sim.loads();
        let (recorded, time) = (loads.recorded_steps(), loads.latest_time());
        if !self.measures() || recorded == self.seen {
            return;
        }
        self.seen = recorded;
        let Some(t) = time else { return };
        let p = loads.instantaneous_pressure();
        for i in 0..self.channels.len() {
            let f = if i == 0 {
                self.roof.iter().map(|&(k, an)| p[k] * an).sum()
            } else {
                self.sensor_pressure(i - 1, p)
            };
            let c = &mut self.channels[i];
            if let Some((t0, f0)) = c.bank.last {
                if t > t0 {
                    c.impulse += 0.5 * (f0.max(0.0) + f.max(0.0)) * (t - t0);
                }
            }
            c.bank.push(t, f);
            if f > c.peak {
                c.peak = f;
                c.t_peak = t;
            }
            c.interval_peak = c.interval_peak.max(f);
        }
    }

    /// The roof impulse ∫ max(F, 0) dt from the start of the run to output row `row` (N·s;
    /// 2D N·s/m): the `roof_impulse` column, whose difference between two rows is the
    /// impulse of that window.
    pub fn row_impulse(&self, row: usize) -> f64 {
        self.rows.get(row).map_or(f64::NAN, |r| r.impulse[0])
    }

    /// Closes an output row at time `time` (s): keeps the cumulative impulse and the largest
    /// load and design-period F_eq since the previous row.
    pub fn cut_row(&mut self, time: f64) {
        if !self.measures() {
            return;
        }
        let mut cut = RowCut {
            time,
            impulse: Vec::with_capacity(self.channels.len()),
            peak: Vec::with_capacity(self.channels.len()),
            f_eq: Vec::with_capacity(self.channels.len()),
        };
        let n_spec = SPECTRUM_POINTS;
        for c in &mut self.channels {
            cut.impulse.push(c.impulse);
            cut.peak.push(std::mem::take(&mut c.interval_peak));
            cut.f_eq.push(c.bank.take_interval(n_spec));
        }
        self.rows.push(cut);
    }

    /// The roof load of the run: spectra, impulses, impacts and their statistics. `tank`
    /// gives the freeboard head and the sloshing period the impact rule is scaled with;
    /// `sensors` names the channels.
    pub fn result(
        &self,
        tank: &crate::roof::RoofTank,
        spacing: f64,
        sensors: &[PressureSensor],
    ) -> RoofLoadResult {
        let periods = spectrum_periods();
        let n_spec = periods.len();
        let period_1 = 2.0 * std::f64::consts::PI / tank.omega;
        let reference_force =
            tank.density * tank.gravity * tank.freeboard.max(spacing) * self.plan_area;
        let load = |c: &Channel| {
            let all = c.bank.equivalent_static();
            let peak = c.peak;
            let dlf = |f: f64| if peak > 0.0 { f / peak } else { f64::NAN };
            ChannelLoad {
                peak,
                t_peak: c.t_peak,
                impulse: c.impulse,
                spectrum: all[..n_spec].to_vec(),
                design: all[n_spec..].to_vec(),
                dlf: all[n_spec..].iter().map(|&f| dlf(f)).collect(),
            }
        };
        let roof = self.has_roof().then(|| load(&self.channels[0]));
        let sensor_loads: Vec<SensorLoad> = sensors
            .iter()
            .zip(self.channels.iter().skip(1))
            .zip(&self.sensor_area)
            .map(|((s, c), &area)| SensorLoad {
                sensor: s.clone(),
                area,
                load: load(c),
            })
            .collect();
        let episodes = self.episodes(reference_force, period_1);
        RoofLoadResult {
            damping_ratio: self.damping_ratio,
            design_periods: self.design_periods.clone(),
            spectrum_periods: periods,
            reference_force,
            plan_area: self.plan_area,
            period_1,
            roof,
            sensors: sensor_loads,
            episodes,
        }
    }

    /// The roof's contact episodes (see the module docs): row ranges with their loads.
    fn episodes(&self, reference_force: f64, period_1: f64) -> Vec<Episode> {
        let rows = &self.rows;
        if rows.len() < 2 || reference_force <= 0.0 {
            return Vec::new();
        }
        // Mean roof force over each output interval, from the step impulse.
        let mean = |r: usize| {
            let dt = rows[r].time - rows[r - 1].time;
            if dt > 0.0 {
                (rows[r].impulse[0] - rows[r - 1].impulse[0]) / dt
            } else {
                0.0
            }
        };
        let (on, off) = (IMPACT_ON * reference_force, IMPACT_OFF * reference_force);
        let mut spans: Vec<(usize, usize)> = Vec::new();
        let mut r = 1;
        while r < rows.len() {
            if mean(r) > on {
                let start = r;
                while r < rows.len() && mean(r) > off {
                    r += 1;
                }
                match spans.last_mut() {
                    Some(last)
                        if rows[start - 1].time - rows[last.1 - 1].time
                            < IMPACT_MERGE * period_1 =>
                    {
                        last.1 = r
                    }
                    _ => spans.push((start, r)),
                }
            } else {
                r += 1;
            }
        }
        let min_impulse = IMPACT_MIN_IMPULSE * reference_force * period_1;
        // The same rule per area on a roof panel a sensor instruments: the freeboard head on
        // its face for 1 % of a period (a local impact the whole roof's force calls a splash).
        let min_panel_impulse = if self.plan_area > 0.0 {
            min_impulse / self.plan_area
        } else {
            f64::INFINITY
        };
        let roof_sensor_channels: Vec<usize> = (0..self.sensor_on_roof.len())
            .filter(|&s| self.sensor_on_roof[s])
            .map(|s| s + 1)
            .collect();
        let n_channels = self.channels.len();
        let mut episodes: Vec<Episode> = spans
            .iter()
            .map(|&(a, b)| Episode {
                t_start: rows[a - 1].time,
                t_end: rows[b - 1].time,
                impulse: (0..n_channels)
                    .map(|c| rows[b - 1].impulse[c] - rows[a - 1].impulse[c])
                    .collect(),
                peak: (0..n_channels)
                    .map(|c| rows[a..b].iter().map(|row| row.peak[c]).fold(0.0, f64::max))
                    .collect(),
                f_eq: Vec::new(),
                rows: (a, b),
            })
            .filter(|e| {
                e.impulse[0] >= min_impulse
                    || roof_sensor_channels
                        .iter()
                        .any(|&c| e.impulse[c] >= min_panel_impulse)
            })
            .collect();
        // The roof rings on after the contact: its F_eq is the largest response from the
        // start of the episode to the start of the next one (or the end of the run).
        for i in 0..episodes.len() {
            let from = episodes[i].rows.0;
            let to = episodes.get(i + 1).map_or(rows.len(), |e| e.rows.0);
            episodes[i].f_eq = (0..n_channels)
                .map(|c| {
                    (0..self.design_periods.len())
                        .map(|k| {
                            rows[from..to]
                                .iter()
                                .map(|row| row.f_eq[c][k])
                                .fold(0.0, f64::max)
                        })
                        .collect()
                })
                .collect();
        }
        episodes
    }
}

/// One contact episode of the roof (an impact).
#[derive(Clone, Debug)]
pub struct Episode {
    /// Start and end (s): the output rows around the contact.
    pub t_start: f64,
    /// End (s).
    pub t_end: f64,
    /// ∫ max(F, 0) dt of each channel over the episode (the roof force first, then each
    /// sensor's pressure): N·s (2D N·s/m), Pa·s.
    pub impulse: Vec<f64>,
    /// Largest value of each channel over the episode (per step).
    pub peak: Vec<f64>,
    /// F_eq at the design periods of each channel, from the episode's start to the next one.
    pub f_eq: Vec<Vec<f64>>,
    rows: (usize, usize),
}

/// The load of one channel over a run.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct ChannelLoad {
    /// Largest value over every step (N, 2D N/m; or Pa).
    pub peak: f64,
    /// Its time (s).
    pub t_peak: f64,
    /// ∫ max(F, 0) dt over the run (N·s, 2D N·s/m; or Pa·s).
    pub impulse: f64,
    /// The load spectrum: F_eq at each of [`spectrum_periods`] (written to
    /// `roof_spectrum.csv`, left out of `summary.ron`).
    #[serde(default, skip_serializing)]
    pub spectrum: Vec<f64>,
    /// F_eq at the design periods.
    pub design: Vec<f64>,
    /// Dynamic load factor F_eq / peak at the design periods.
    pub dlf: Vec<f64>,
}

/// A sensor with its load.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct SensorLoad {
    /// The sensor as declared.
    pub sensor: PressureSensor,
    /// The area of the roof points on it (m²; 2D m).
    pub area: f64,
    /// Its mean pressure's peak, impulse and response.
    pub load: ChannelLoad,
}

/// The roof load of a run.
#[derive(Clone, Debug)]
pub struct RoofLoadResult {
    /// ζ_r.
    pub damping_ratio: f64,
    /// Design periods T_r (s).
    pub design_periods: Vec<f64>,
    /// Periods of the spectrum (s).
    pub spectrum_periods: Vec<f64>,
    /// F_ref = ρ g H′ A_roof (N; 2D N/m), the scale of the impact thresholds.
    pub reference_force: f64,
    /// Roof plan area (m²; 2D m).
    pub plan_area: f64,
    /// First sloshing period T₁ (s), the scale of the merge rule.
    pub period_1: f64,
    /// The upward roof force's load; `None` without a roof.
    pub roof: Option<ChannelLoad>,
    /// Each sensor's.
    pub sensors: Vec<SensorLoad>,
    /// The impacts.
    pub episodes: Vec<Episode>,
}

/// Median, 84th percentile and maximum of a sample (the percentile interpolated linearly
/// between order statistics, Hyndman & Fan 1996 type 7); NaN for an empty sample.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct Spread {
    /// Median.
    pub median: f64,
    /// 84th percentile (the median plus one standard deviation of a normal sample).
    pub p84: f64,
    /// Largest.
    pub max: f64,
}

impl Spread {
    /// The spread of `values` (finite ones).
    pub fn of(values: &[f64]) -> Spread {
        let mut v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
        if v.is_empty() {
            return Spread {
                median: f64::NAN,
                p84: f64::NAN,
                max: f64::NAN,
            };
        }
        v.sort_by(f64::total_cmp);
        let q = |p: f64| {
            let x = p * (v.len() - 1) as f64;
            let (i, f) = (x.floor() as usize, x - x.floor());
            if i + 1 < v.len() {
                v[i] + f * (v[i + 1] - v[i])
            } else {
                v[i]
            }
        };
        Spread {
            median: q(0.5),
            p84: q(0.84),
            max: v[v.len() - 1],
        }
    }
}

#[cfg(test)]
mod tests {

    #[test]
    fn a_clearance_of_few_spacings_is_warned_with_the_shortfall() {
        // 0.1 m at dx = 0.02 m: 5 spacings, the reach of 2 dx is 40 % of the clearance.
        let w = clearance_resolution_warning(0.1, 0.02).expect("a warning");
        assert!(
            w.contains("5.0 particle spacings") && w.contains("≈ 40 % short"),
            "{w}"
        );
        assert!(w.contains("dx = H′/40 = 0.0025 m"), "{w}");
        // 40 spacings and more: no warning; no roof (no clearance): none.
        assert!(clearance_resolution_warning(0.1, 0.0025).is_none());
        assert!(clearance_resolution_warning(0.0, 0.02).is_none());
    }
    use super::*;
    use std::f64::consts::PI;

    /// Drives one oscillator with `f(t)` sampled every `dt` to `end` and returns F_eq.
    fn response(period: f64, zeta: f64, dt: f64, end: f64, f: impl Fn(f64) -> f64) -> f64 {
        let mut bank = OscillatorBank::new(&[period], zeta);
        let n = (end / dt).round() as usize;
        for i in 0..=n {
            let t = i as f64 * dt;
            bank.push(t, f(t));
        }
        bank.equivalent_static()[0]
    }

    /// A load applied suddenly and held: the dynamic load factor is 1 + exp(−πζ/√(1−ζ²))
    /// (Chopra, Dynamics of Structures, §4.3). The load rises over one sample of 1/200 of
    /// the period, which lowers the factor by under 0.1 %; tolerance 0.3 %.
    #[test]
    fn suddenly_applied_load_doubles_the_static_load() {
        for zeta in [0.0, 0.02, 0.1] {
            let (period, dt) = (0.1, 0.1 / 200.0);
            let feq = response(period, zeta, dt, 3.0 * period, |t| {
                if t > 0.0 {
                    1.0
                } else {
                    0.0
                }
            });
            let dlf = 1.0 + (-PI * zeta / (1.0 - zeta * zeta).sqrt()).exp();
            assert!(
                (feq / dlf - 1.0).abs() < 3e-3,
                "ζ {zeta}: {feq} against {dlf}"
            );
        }
    }

    /// A short pulse of impulse I on an oscillator of period much longer than the pulse gives
    /// u_max = I/(mω) (undamped), F_eq = ω I (Chopra §4.11). A half-sine of duration
    /// t_d = T_r/50: the pulse's own length changes F_eq by (πt_d/T_r)²/… < 0.2 %; tolerance
    /// 0.5 %.
    #[test]
    fn short_pulse_gives_omega_times_impulse() {
        let (period, td) = (1.0, 0.02);
        let amplitude = 100.0;
        let impulse = amplitude * 2.0 * td / PI;
        let pulse = |t: f64| {
            if t < td {
                amplitude * (PI * t / td).sin()
            } else {
                0.0
            }
        };
        let feq = response(period, 0.0, td / 100.0, 2.0, pulse);
        let expected = 2.0 * PI / period * impulse;
        assert!(
            (feq / expected - 1.0).abs() < 5e-3,
            "{feq} against {expected}"
        );
    }

    /// A slow load on a stiff roof is static: DLF → 1 for a load rising over 50 T_r.
    /// Tolerance 2 %: the ramp's own overshoot is T_r/(π·t_rise) ≈ 0.6 % (Chopra §4.5).
    #[test]
    fn slow_load_is_static() {
        let period = 0.01;
        let feq = response(period, 0.02, 1e-4, 1.0, |t| (t / 0.5).min(1.0));
        assert!((feq - 1.0).abs() < 0.02, "{feq}");
    }

    /// Steady resonance of a damped oscillator: the amplitude is 1/(2ζ) times the static
    /// one. The load is sampled 10 times per period and taken linear between samples, which
    /// scales its fundamental by sinc²(π/10) = 0.9675 (the Fourier series of a linear
    /// interpolant); the sub-steps (ω dt = 0.63 → 7 of them) keep the trapezoidal rule's
    /// period error ≤ 0.08 %, which detunes by ≪ ζ. Tolerance 1 %.
    #[test]
    fn resonance_amplitude_is_one_over_two_zeta() {
        let (period, zeta) = (0.05, 0.05);
        let w = 2.0 * PI / period;
        let feq = response(period, zeta, period / 10.0, 40.0 * period / zeta, |t| {
            (w * t).sin()
        });
        let x = PI / 10.0;
        let expected = (x.sin() / x).powi(2) / (2.0 * zeta);
        assert!(
            (feq / expected - 1.0).abs() < 0.01,
            "{feq} against {expected}"
        );
    }

    /// A monitor of a roof of plan area 1 m² and one sensor, whose output rows (every 10 ms)
    /// hold the cumulative impulses of a roof force `force`(t) (N) and a sensor pressure
    /// `pressure`(t) (Pa), constant over each row.
    fn monitor_with_rows(
        sensor_on_roof: bool,
        force: impl Fn(f64) -> f64,
        pressure: impl Fn(f64) -> f64,
    ) -> RoofLoadMonitor {
        let channel = || Channel {
            bank: OscillatorBank::new(&[], DEFAULT_ROOF_DAMPING),
            impulse: 0.0,
            peak: 0.0,
            t_peak: 0.0,
            interval_peak: 0.0,
        };
        let mut m = RoofLoadMonitor {
            roof: Vec::new(),
            sensors: vec![Vec::new()],
            sensor_area: vec![0.05],
            sensor_on_roof: vec![sensor_on_roof],
            plan_area: 1.0,
            channels: vec![channel(), channel()],
            rows: Vec::new(),
            seen: 0,
            design_periods: Vec::new(),
            damping_ratio: DEFAULT_ROOF_DAMPING,
        };
        let (mut impulse_f, mut impulse_p) = (0.0, 0.0);
        for r in 0..=300 {
            let t = r as f64 * 0.01;
            if r > 0 {
                impulse_f += force(t) * 0.01;
                impulse_p += pressure(t) * 0.01;
            }
            m.rows.push(RowCut {
                time: t,
                impulse: vec![impulse_f, impulse_p],
                peak: vec![force(t), pressure(t)],
                f_eq: vec![Vec::new(), Vec::new()],
            });
        }
        m
    }

    /// With F_ref = 100 N and T₁ = 1 s: a contact of 5 N for 0.1 s (0.5 N·s, under the 1 N·s
    /// of 1 % F_ref T₁) is a splash for the whole roof, but an impact when a sensor on the roof
    /// takes 50 Pa over it (5 Pa·s, over the 1 Pa·s of 1 % ρ g H′ T₁ per area); a sensor on a
    /// wall does not count; a contact of 50 N for 0.1 s is an impact with no sensor.
    #[test]
    fn a_local_impact_on_an_instrumented_roof_panel_is_an_impact() {
        let window = |t: f64| (1.0..1.1).contains(&(t - 1e-9));
        let small = |t: f64| if window(t) { 5.0 } else { 0.0 };
        let local = |t: f64| if window(t) { 50.0 } else { 0.0 };
        let on_roof = monitor_with_rows(true, small, local);
        let episodes = on_roof.episodes(100.0, 1.0);
        assert_eq!(episodes.len(), 1, "the panel's impact");
        assert!(
            (episodes[0].t_start - 1.0).abs() < 1e-9 && (episodes[0].impulse[1] - 5.0).abs() < 1e-9
        );
        assert!(monitor_with_rows(false, small, local)
            .episodes(100.0, 1.0)
            .is_empty());
        assert!(monitor_with_rows(true, small, |_| 0.5)
            .episodes(100.0, 1.0)
            .is_empty());
        let large = |t: f64| if window(t) { 50.0 } else { 0.0 };
        assert_eq!(
            monitor_with_rows(false, large, |_| 0.0)
                .episodes(100.0, 1.0)
                .len(),
            1
        );
    }

    /// An open tank's summary (no roof plan area) gives its wall sensors' numbers and no roof
    /// entries (zero by construction, not measured) or impact spreads; a roofed one gives both.
    #[test]
    fn an_open_tank_has_sensor_scalars_and_no_roof_scalars() {
        let sensor = SensorLoad {
            sensor: PressureSensor {
                name: "s1".into(),
                horizontal: vec![0.0],
                diameter: 0.005,
                height: Some(0.093),
            },
            area: 0.005,
            load: ChannelLoad {
                peak: 3700.0,
                design: vec![1.0; 4],
                ..ChannelLoad::default()
            },
        };
        let open = RoofLoadSummary {
            periods: DEFAULT_ROOF_PERIODS.to_vec(),
            sensors: vec![sensor.clone()],
            impact_sensor_peak: vec![Spread::of(&[])],
            ..RoofLoadSummary::default()
        };
        let names: Vec<String> = open.scalars().into_iter().map(|(n, _)| n).collect();
        assert!(names.contains(&"p_s1_peak".to_string()), "{names:?}");
        assert!(names.contains(&"p_s1_eq_50ms".to_string()), "{names:?}");
        assert!(
            !names
                .iter()
                .any(|n| n.starts_with("roof_") || n.contains("impact")),
            "{names:?}"
        );
        let roofed = RoofLoadSummary {
            plan_area: 0.9,
            ..open
        };
        let names: Vec<String> = roofed.scalars().into_iter().map(|(n, _)| n).collect();
        assert!(
            names.contains(&"roof_impulse".to_string())
                && names.contains(&"p_s1_impact_peak_p84".to_string())
        );
    }

    /// The type-7 percentile of 1..=11 is 1 + 0.84·10 = 9.4; median 6.
    #[test]
    fn spread_of_a_sample() {
        let v: Vec<f64> = (1..=11).map(|i| i as f64).rev().collect();
        let s = Spread::of(&v);
        assert_eq!((s.median, s.max), (6.0, 11.0));
        assert!((s.p84 - 9.4).abs() < 1e-12);
        assert!(Spread::of(&[]).median.is_nan());
    }
}

/// The roof load of a run as `summary.ron` gives it (`docs/formats.md`).
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct RoofLoadSummary {
    /// Damping ratio ζ_r of the roof oscillator.
    pub damping_ratio: f64,
    /// Roof periods T_r of `f_eq`, `dlf` and the sensors' `design` (s).
    pub periods: Vec<f64>,
    /// F_ref = ρ g H′ A_roof (N; 2D N/m), the scale of the impact thresholds.
    pub reference_force: f64,
    /// Roof plan area (m²; 2D m).
    pub plan_area: f64,
    /// The upward roof force (N; 2D N/m): its per-step peak, impulse over the run, F_eq and
    /// dynamic load factor at `periods`.
    pub roof: ChannelLoad,
    /// Each sensor's mean pressure (Pa): peak, impulse (Pa·s), F_eq as a pressure, DLF.
    pub sensors: Vec<SensorLoad>,
    /// Number of impacts.
    pub impacts: usize,
    /// Spread of the impacts' roof impulse (N·s; 2D N·s/m).
    pub impact_impulse: Spread,
    /// Spread of the impacts' F_eq at each of `periods` (N; 2D N/m).
    pub impact_f_eq: Vec<Spread>,
    /// Spread of the impacts' peak pressure on each sensor (Pa).
    pub impact_sensor_peak: Vec<Spread>,
}

/// A roof period as a column-name tag: milliseconds, `50ms`, `12p5ms`.
pub fn period_tag(period: f64) -> String {
    let ms = period * 1000.0;
    if (ms - ms.round()).abs() < 1e-9 * ms.max(1.0) {
        format!("{}ms", ms.round() as i64)
    } else {
        format!("{ms}ms").replace('.', "p")
    }
}

impl RoofLoadSummary {
    /// The summary of a run's roof load.
    pub fn of(result: &RoofLoadResult) -> RoofLoadSummary {
        let n_periods = result.design_periods.len();
        let e = &result.episodes;
        RoofLoadSummary {
            damping_ratio: result.damping_ratio,
            periods: result.design_periods.clone(),
            reference_force: result.reference_force,
            plan_area: result.plan_area,
            roof: result.roof.clone().unwrap_or_default(),
            sensors: result.sensors.clone(),
            impacts: e.len(),
            impact_impulse: Spread::of(&e.iter().map(|e| e.impulse[0]).collect::<Vec<_>>()),
            impact_f_eq: (0..n_periods)
                .map(|k| Spread::of(&e.iter().map(|e| e.f_eq[0][k]).collect::<Vec<_>>()))
                .collect(),
            impact_sensor_peak: (0..result.sensors.len())
                .map(|s| Spread::of(&e.iter().map(|e| e.peak[s + 1]).collect::<Vec<_>>()))
                .collect(),
        }
    }

    /// The summary's numbers as named scalars (the columns of `sweep.csv` and the rows of
    /// `slosh converge`): `roof_impulse`, `roof_f_eq_<T>`, `roof_dlf_<T>`,
    /// `roof_impact_impulse_{median,p84,max}`, `roof_impact_f_eq_<T>_{…}`, and per sensor
    /// `p_<name>_{peak,impulse}`, `p_<name>_eq_<T>`, `p_<name>_impact_peak_{…}`, where `<T>` is
    /// the roof period in ms ([`period_tag`]). An open tank (wall sensors only) has the
    /// sensors' peak, impulse and F_eq alone.
    pub fn scalars(&self) -> Vec<(String, f64)> {
        // An open tank with wall sensors has no roof entries (its roof load is zero by
        // construction, not measured) and no impacts.
        let roofed = self.plan_area > 0.0;
        let mut out = Vec::new();
        if roofed {
            out.push(("roof_impulse".to_string(), self.roof.impulse));
            out.push(("roof_peak_force".to_string(), self.roof.peak));
            out.push(("roof_impacts".to_string(), self.impacts as f64));
        }
        let spread = |out: &mut Vec<(String, f64)>, name: String, s: &Spread| {
            out.push((format!("{name}_median"), s.median));
            out.push((format!("{name}_p84"), s.p84));
            out.push((format!("{name}_max"), s.max));
        };
        let at = |v: &[f64], k: usize| v.get(k).copied().unwrap_or(f64::NAN);
        if roofed {
            for (k, &t) in self.periods.iter().enumerate() {
                let tag = period_tag(t);
                out.push((format!("roof_f_eq_{tag}"), at(&self.roof.design, k)));
                out.push((format!("roof_dlf_{tag}"), at(&self.roof.dlf, k)));
            }
            spread(&mut out, "roof_impact_impulse".into(), &self.impact_impulse);
            for (k, &t) in self.periods.iter().enumerate() {
                if let Some(s) = self.impact_f_eq.get(k) {
                    spread(&mut out, format!("roof_impact_f_eq_{}", period_tag(t)), s);
                }
            }
        }
        for (i, s) in self.sensors.iter().enumerate() {
            let name = format!("p_{}", s.sensor.name);
            out.push((format!("{name}_peak"), s.load.peak));
            out.push((format!("{name}_impulse"), s.load.impulse));
            for (k, &t) in self.periods.iter().enumerate() {
                out.push((
                    format!("{name}_eq_{}", period_tag(t)),
                    at(&s.load.design, k),
                ));
            }
            if let Some(sp) = self.impact_sensor_peak.get(i).filter(|_| roofed) {
                spread(&mut out, format!("{name}_impact_peak"), sp);
            }
        }
        out
    }
}
