//! The tank's frame when the ground also rotates it: the body force the liquid feels in a
//! frame fixed to a tank that turns about a fixed axis through a pivot.
//!
//! The liquid is integrated in the tank's frame, where the walls stand still. A tank turned by
//! the angle θ(t) about the unit axis **n** through the pivot **p** (fixed in the tank), whose
//! pivot the ground also accelerates by **a**_g (world frame), gives each liquid particle at
//! **r** with velocity **v** (both in the tank's frame) the body force per unit mass
//!
//! **f** = Rᵀ(**g** − **a**_g) − **α** × (**r** − **p**) − **Ω** × (**Ω** × (**r** − **p**))
//! − 2 **Ω** × **v**,
//!
//! with **Ω** = θ̇ **n** and **α** = θ̈ **n** (the axis is fixed, so these are the same in both
//! frames) and R the rotation by θ about **n** (Rodrigues' formula): gravity turning with the
//! frame, the ground's translation, and the Euler, centrifugal and Coriolis forces of a
//! rotating frame (Goldstein, Poole & Safko, *Classical Mechanics*, 3rd ed., §4.10).
//!
//! A 2D tank is the x–z section of a 3D one: it turns about the y axis, with the right-hand
//! rule, so a positive angle lowers its +x wall.

use crate::sim::Vector;

/// The tank's rotation at one instant: a fixed axis through a pivot fixed in the tank, the
/// angle and its first two time derivatives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TankRotation {
    /// Unit axis `[x, y, z]`; a 2D tank turns about `[0, 1, 0]`.
    pub axis: [f64; 3],
    /// The pivot, in the tank's coordinates `[x, y, z]` (m); a 2D tank uses x and z.
    pub pivot: [f64; 3],
    /// Angle θ (rad), right-hand rule about `axis`.
    pub angle: f64,
    /// Angular velocity θ̇ (rad/s).
    pub rate: f64,
    /// Angular acceleration θ̈ (rad/s²).
    pub acceleration: f64,
}

impl TankRotation {
    /// True when every number is finite and the axis is a unit vector (to 1e-9).
    pub fn is_valid(&self) -> bool {
        let finite = self
            .axis
            .iter()
            .chain(self.pivot.iter())
            .chain([self.angle, self.rate, self.acceleration].iter())
            .all(|v| v.is_finite());
        let norm: f64 = self.axis.iter().map(|a| a * a).sum::<f64>().sqrt();
        finite && (norm - 1.0).abs() < 1e-9
    }

    /// A world-frame vector `w` written in the tank's frame: Rᵀ w, the rotation by −θ about
    /// the axis (Rodrigues' formula).
    pub fn world_to_tank(&self, w: [f64; 3]) -> [f64; 3] {
        rotate(self.axis, -self.angle, w)
    }

    /// A tank-frame vector written in the world frame: R v.
    pub fn tank_to_world(&self, v: [f64; 3]) -> [f64; 3] {
        rotate(self.axis, self.angle, v)
    }
}

/// Rotates `v` by `angle` about the unit axis `n` (Rodrigues' formula).
fn rotate(n: [f64; 3], angle: f64, v: [f64; 3]) -> [f64; 3] {
    let (s, c) = angle.sin_cos();
    let n_dot_v = n[0] * v[0] + n[1] * v[1] + n[2] * v[2];
    let n_cross_v = cross(n, v);
    std::array::from_fn(|k| v[k] * c + n_cross_v[k] * s + n[k] * n_dot_v * (1.0 - c))
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// A solver vector as `[x, y, z]`: a 2D vector `(x, z)` is `[x, 0, z]`.
pub(crate) fn to_3<const D: usize>(v: &Vector<D>) -> [f64; 3] {
    if D == 2 {
        [v[0], 0.0, v[1]]
    } else {
        [v[0], v[1], v[2]]
    }
}

/// `[x, y, z]` as a solver vector: a 2D vector keeps x and z.
pub(crate) fn from_3<const D: usize>(v: [f64; 3]) -> Vector<D> {
    let mut out = Vector::<D>::zeros();
    if D == 2 {
        out[0] = v[0];
        out[1] = v[2];
    } else {
        out[0] = v[0];
        out[1] = v[1];
        out[2] = v[2];
    }
    out
}

/// The body force of one step: the part the same at every point (gravity and the ground's
/// translation, in the tank's frame) and, while the tank rotates, the parts that follow the
/// position and the velocity.
#[derive(Clone, Copy, Debug)]
pub struct BodyForce<const D: usize> {
    /// Rᵀ(g − a_g) (m/s²).
    pub uniform: Vector<D>,
    /// The rotation's terms, absent when the tank only translates.
    pub(crate) rotating: Option<RotatingFrame<D>>,
}

/// The terms of a rotating frame, in the solver's coordinates.
#[derive(Clone, Copy, Debug)]
pub struct RotatingFrame<const D: usize> {
    /// The pivot (m).
    pivot: [f64; 3],
    /// Ω = θ̇ n (rad/s).
    omega: [f64; 3],
    /// α = θ̈ n (rad/s²).
    alpha: [f64; 3],
    /// The world's upward unit vector in the tank's frame, Rᵀ ẑ.
    up: [f64; 3],
}

impl<const D: usize> BodyForce<D> {
    /// A body force the same everywhere (m/s²): a tank that does not turn.
    pub fn uniform(force: Vector<D>) -> Self {
        BodyForce {
            uniform: force,
            rotating: None,
        }
    }

    /// Gravity `g` (m/s², downward) and the ground acceleration `ground` (world frame), the
    /// tank turned as `rotation` says (or not at all).
    pub fn new(gravity: f64, ground: Vector<D>, rotation: Option<&TankRotation>) -> Self {
        let mut world = to_3(&(-ground));
        world[2] -= gravity;
        match rotation {
            None => BodyForce {
                uniform: from_3(world),
                rotating: None,
            },
            Some(r) => BodyForce {
                uniform: from_3(r.world_to_tank(world)),
                rotating: Some(RotatingFrame {
                    pivot: r.pivot,
                    omega: r.axis.map(|n| n * r.rate),
                    alpha: r.axis.map(|n| n * r.acceleration),
                    up: r.world_to_tank([0.0, 0.0, 1.0]),
                }),
            },
        }
    }

    /// The body force at rest in the tank's frame at `x` (the walls' points): the uniform part
    /// plus the Euler and centrifugal forces there (m/s²).
    #[inline]
    pub fn at(&self, x: &Vector<D>) -> Vector<D> {
        match &self.rotating {
            None => self.uniform,
            Some(f) => self.uniform + f.position_terms(x),
        }
    }

    /// The height of `x` above the pivot along the world's vertical (m): the depth coordinate
    /// of the hydrostatic density; x's own vertical coordinate when the tank does not turn.
    #[inline]
    pub fn height(&self, x: &Vector<D>) -> f64 {
        match &self.rotating {
            None => x[D - 1],
            Some(f) => {
                let r = to_3(x);
                f.pivot[2] + (0..3).map(|k| f.up[k] * (r[k] - f.pivot[k])).sum::<f64>()
            }
        }
    }
}

impl<const D: usize> RotatingFrame<D> {
    /// −α × (x − p) − Ω × (Ω × (x − p)) (m/s²).
    #[inline]
    pub fn position_terms(&self, x: &Vector<D>) -> Vector<D> {
        let p = self.pivot;
        let r3 = to_3(x);
        let r = [r3[0] - p[0], r3[1] - p[1], r3[2] - p[2]];
        let euler = cross(self.alpha, r);
        let centripetal = cross(self.omega, cross(self.omega, r));
        from_3(std::array::from_fn(|k| -euler[k] - centripetal[k]))
    }

    /// The position terms plus the Coriolis force −2 Ω × v (m/s²).
    #[inline]
    pub fn moving_terms(&self, x: &Vector<D>, v: &Vector<D>) -> Vector<D> {
        let coriolis = cross(self.omega, to_3(v));
        self.position_terms(x) - from_3::<D>(coriolis.map(|c| 2.0 * c))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rot(axis: [f64; 3], angle: f64, rate: f64, accel: f64) -> TankRotation {
        TankRotation {
            axis,
            pivot: [0.0; 3],
            angle,
            rate,
            acceleration: accel,
        }
    }

    /// A positive turn about y lowers the +x end: gravity gains a +x component g sin θ in the
    /// tank's frame (the 2D sign convention of the module docs).
    #[test]
    fn gravity_turns_with_the_frame() {
        let th = 0.1f64;
        let b = BodyForce::<2>::new(
            9.81,
            Vector::<2>::zeros(),
            Some(&rot([0.0, 1.0, 0.0], th, 0.0, 0.0)),
        );
        assert!((b.uniform[0] - 9.81 * th.sin()).abs() < 1e-12);
        assert!((b.uniform[1] + 9.81 * th.cos()).abs() < 1e-12);
        // Rᵀ R is the identity.
        let r = rot([0.6, 0.0, 0.8], 0.7, 0.0, 0.0);
        let v = [0.3, -1.2, 2.0];
        let back = r.world_to_tank(r.tank_to_world(v));
        for k in 0..3 {
            assert!((back[k] - v[k]).abs() < 1e-14);
        }
    }

    /// Uniform rotation Ω about z through the origin: the centrifugal force Ω² r outward;
    /// Coriolis −2 Ω × v; Euler −α × r (closed forms of the rotating frame).
    #[test]
    fn fictitious_forces_have_their_closed_forms() {
        let f = BodyForce::<3>::new(
            0.0,
            Vector::<3>::zeros(),
            Some(&rot([0.0, 0.0, 1.0], 0.0, 2.0, 0.0)),
        );
        let x = Vector::<3>::new(0.5, 0.0, 0.0);
        let a = f.at(&x);
        assert!((a[0] - 4.0 * 0.5).abs() < 1e-12 && a[1].abs() < 1e-12);
        let v = Vector::<3>::new(1.0, 0.0, 0.0);
        let m = f.rotating.unwrap().moving_terms(&x, &v);
        // −2 Ω ẑ × x̂ = −2 Ω ŷ.
        assert!((m[1] + 4.0).abs() < 1e-12 && (m[0] - 2.0).abs() < 1e-12);
        let e = BodyForce::<3>::new(
            0.0,
            Vector::<3>::zeros(),
            Some(&rot([0.0, 0.0, 1.0], 0.0, 0.0, 3.0)),
        );
        // −α ẑ × (0.5 x̂) = −1.5 ŷ.
        let a = e.at(&x);
        assert!((a[1] + 1.5).abs() < 1e-12 && a[0].abs() < 1e-12);
    }

    /// In 2D, a turn about y with angular acceleration α gives −α ŷ × r: (−α z, α x) in (x, z).
    #[test]
    fn two_d_euler_force_is_in_plane() {
        let f = BodyForce::<2>::new(
            0.0,
            Vector::<2>::zeros(),
            Some(&rot([0.0, 1.0, 0.0], 0.0, 0.0, 2.0)),
        );
        let a = f.at(&Vector::<2>::new(0.3, 0.5));
        assert!((a[0] + 2.0 * 0.5).abs() < 1e-12 && (a[1] - 2.0 * 0.3).abs() < 1e-12);
    }
}
