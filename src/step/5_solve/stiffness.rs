//! How stiff each contact and joint is, and how many substeps that takes.
//!
//! A soft contact is a spring-damper tuned to the pair's effective mass m_eff — about the
//! lighter body's mass. Resting under a load of mass M it sinks by r·g/ω² (r = M/m_eff,
//! ω = 2πf), whatever the bodies' size. Two things follow:
//! - **Heavy loads** (a heavy box on a light one, a light box carrying a stack): the
//!   frequency rises by √r. The damping ratio rises by √ of the heaviest touching body's
//!   mass ratio, which keeps a heavy body's own damping ratio at ζ (without it the load
//!   rides an under-damped spring and bounces); a load carried through a stack of equal
//!   bodies leaves it at ζ (see [`contact_softness`]).
//! - **Small bodies**: a fixed sag is a large fraction of a small body (0.3 mm is 1.5 % of
//!   a 2 cm cube). So each contact also asks for the frequency that holds its sag to
//!   `max_sag` of the smaller body's size: f ≥ √(r·g / (max_sag·L)) / 2π.
//!
//! The soft step stays smooth up to a quarter of the substep rate, so a contact's
//! frequency is capped there — and when a scene's contacts ask for more (a 1000:1 load, a
//! stack of centimetre cubes), the step takes more substeps, up to `max_substeps`. Scenes
//! without such contacts keep the configured substeps and pay nothing.

use std::f32::consts::TAU;

use crate::collider::Shape;

use crate::math::Softness;
use bevy::math::{Mat3, Vec3};

use super::joint::linear_k;
use crate::world::{ContactParams, JointConstraint, STATIC, SolverBody, body};

/// The most load, in multiples of the lighter body, that the sag rule reads from a
/// contact's impulses (its own mass ratio counts in full). A five-high stack of
/// centimetre cubes is within it; a pile of 2,000 half-metre balls, whose bottom
/// contacts carry fifty, is not, and keeps the configured substeps.
pub const STACK_LOAD: f32 = 8.0;

/// The size that sets a contact's allowed sag: the smaller of the two shapes' smallest
/// dimension (a sphere's diameter, a box's thinnest side); a plane has none.
pub fn pair_size(a: &Shape, b: &Shape) -> f32 {
    a.pair_thickness(b)
}

/// What one contact asks of the solver.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wanted {
    /// The frequency it would like, Hz, before the cap: the larger of the load rule
    /// (base·√r) and the sag rule.
    pub hertz: f32,
    /// The frequency its sag needs, Hz: the least the cap may be for it. Only this one
    /// raises the substep count; the load rule's √r is content with the cap.
    pub needed: f32,
    /// The load ratio r.
    pub ratio: f32,
}

/// The load ratio r of a contact and the frequencies it asks for. `load_impulse` is last
/// step's total normal impulse per substep of `p.h`; `resting`: the pair is not closing
/// or parting fast (an impact's impulse is not a load).
pub fn wanted_hertz(
    p: &ContactParams,
    inv_mass_a: f32,
    inv_mass_b: f32,
    load_impulse: f32,
    size: f32,
    resting: bool,
) -> Wanted {
    let (lo, hi) = (inv_mass_a.min(inv_mass_b), inv_mass_a.max(inv_mass_b));
    if hi == 0.0 {
        return Wanted {
            hertz: 0.0,
            needed: 0.0,
            ratio: 1.0,
        };
    }
    let r = load_ratio(p, lo, hi, load_impulse);
    let base = if lo == 0.0 { 2.0 * p.hertz } else { p.hertz };
    let needed = hertz_of(sag_omega_squared(p, (lo, hi), r, size, resting));
    Wanted {
        hertz: (base * r.sqrt()).max(needed),
        needed,
        ratio: r,
    }
}

/// ω² that the sag rule asks of a contact whose load ratio is `r`, (rad/s)² (NaN or ∞
/// where it asks nothing; see [`hertz_of`]). `inv_masses`: the pair's smaller and larger
/// inverse mass, the larger not 0.
fn sag_omega_squared(
    p: &ContactParams,
    inv_masses: (f32, f32),
    r: f32,
    size: f32,
    resting: bool,
) -> f32 {
    let (light, heavy) = pair_masses(inv_masses.0, inv_masses.1);
    // The sag rule reads the load its impulses show only for a resting contact (an
    // impact's impulse looks like a huge load for one step, and would buy substeps for
    // nothing), and only up to STACK_LOAD: deep piles share their load and sag more.
    let shown = if resting { r.min(STACK_LOAD) } else { 1.0 };
    let resting_load = (heavy / light).max(shown);
    resting_load * p.gravity / (p.max_sag * size)
}

/// The frequency of an ω² from [`sag_omega_squared`], Hz; 0 where it is not finite.
/// Non-decreasing in ω², so the largest of many is the frequency of the largest finite
/// ω², one square root instead of one per contact ([`NeededHertz`]).
fn hertz_of(omega_squared: f32) -> f32 {
    let hertz = omega_squared.sqrt() / TAU;
    if hertz.is_finite() { hertz } else { 0.0 }
}

/// Folds contacts' sag needs into the most any of them needs: `Wanted::needed` of the
/// stiffest, in [`Self::hertz`], with one square root at the end.
#[derive(Clone, Copy, Debug, Default)]
pub struct NeededHertz {
    /// The largest finite ω² seen, (rad/s)².
    omega_squared: f32,
}

impl NeededHertz {
    /// Adds a contact, with [`wanted_hertz`]'s arguments.
    #[inline]
    pub fn add(
        &mut self,
        p: &ContactParams,
        (inv_mass_a, inv_mass_b): (f32, f32),
        load_impulse: f32,
        size: f32,
        resting: bool,
    ) {
        let (lo, hi) = (inv_mass_a.min(inv_mass_b), inv_mass_a.max(inv_mass_b));
        if hi == 0.0 {
            return;
        }
        let r = load_ratio(p, lo, hi, load_impulse);
        let w = sag_omega_squared(p, (lo, hi), r, size, resting);
        if w.is_finite() {
            self.omega_squared = self.omega_squared.max(w);
        }
    }

    /// The most any contact added needs, Hz (0 for none).
    pub fn hertz(&self) -> f32 {
        hertz_of(self.omega_squared)
    }
}

/// The lighter and the heavier mass of a pair from the smaller and larger inverse mass
/// (a fixed body counts as heavy as the other).
fn pair_masses(lo: f32, hi: f32) -> (f32, f32) {
    let light = 1.0 / hi;
    (light, if lo > 0.0 { 1.0 / lo } else { light })
}

/// The load ratio r: the heavier of the pair's other mass and the mass that `impulse` (per
/// substep of `p.h`) holds up, over the lighter mass; at least 1.
pub(super) fn load_ratio(p: &ContactParams, lo: f32, hi: f32, impulse: f32) -> f32 {
    let (light, heavy) = pair_masses(lo, hi);
    let carried = if p.gravity > 0.0 {
        impulse / (p.gravity * p.h)
    } else {
        0.0
    };
    (heavy.max(carried) / light).max(1.0)
}

/// The contact's softness (its wanted frequency capped at `max_hertz`) and its load
/// ratio r. `pressing_impulse` is the weight, per substep, of the heaviest body touching
/// either side: the damping ratio grows as √ of that body's mass over the lighter one's,
/// so that a heavy body riding a light one keeps its own damping ratio at ζ. A load
/// carried through a stack of bodies like these does not raise it: each body of the
/// stack is damped by its own contacts, and a bottom contact made nearly rigid by
/// ζ·√r (ζ ≈ 100 under 100 cubes, mass scale 0.997) is one that two Gauss–Seidel passes
/// cannot converge. Measured on the 5,050-cube pyramid: with the carried load in ζ, 3,778
/// cubes still moved faster than 0.1 m/s at step 220 and the top cube was 0.25 m off;
/// without it, none (the fastest 0.04 m/s) and 0.19 m.
pub fn contact_softness(
    p: &ContactParams,
    inv_mass_a: f32,
    inv_mass_b: f32,
    load_impulse: f32,
    pressing_impulse: f32,
    size: f32,
) -> (Softness, f32) {
    let w = wanted_hertz(p, inv_mass_a, inv_mass_b, load_impulse, size, true);
    if w.hertz == 0.0 {
        return (Softness::new(0.0, 0.0, p.h), w.ratio);
    }
    let (lo, hi) = (inv_mass_a.min(inv_mass_b), inv_mass_a.max(inv_mass_b));
    let zeta = p.damping_ratio * load_ratio(p, lo, hi, pressing_impulse).sqrt();
    (Softness::new(w.hertz.min(p.max_hertz), zeta, p.h), w.ratio)
}

/// Substeps for a step of `dt` s whose stiffest contact wants `hertz`: enough that a
/// quarter of the substep rate reaches it, never fewer than `min`, never more than `max`.
pub fn substeps_for(hertz: f32, dt: f32, min: u32, max: u32) -> u32 {
    // A saturating cast: NaN gives 0 (then `min`), ∞ gives u32::MAX (then `max`).
    let wanted = (4.0 * hertz * dt).ceil() as u32;
    wanted.clamp(min, max.max(min))
}

/// The frequency a joint would like and the one it needs, Hz.
///
/// A soft joint is a stiff spring of k = m_eff·ω² across its rows: carrying a load T it
/// opens by T/k (and a turn under a torque likewise, by the inertia). Light bodies
/// holding a heavy one (a chain of 0.1 kg links under a 10 kg ball: m_eff 0.05 kg,
/// T 127 N) open by centimetres at the contacts' frequencies, so each joint asks for the
/// frequency that holds its opening to `max_sag` of its size:
/// ω ≥ √(T / (m_eff · max_sag · size)). That one is *needed*; otherwise a joint wants
/// twice the contact frequency (Box2D v3's choice) or an eighth of the substep rate,
/// whichever is higher: at a fixed 60 Hz, finer substeps let the joint's damping work
/// longer on the compliance it leaves (without the substep-rate term a pendulum's energy
/// drift grows from −9.9e-5 at 16 substeps to −8.0e-4 at 64; with it the drift never
/// grows with the substeps, `tests/joint_pendulum.rs`).
///
/// The rows that hold the joint together take the wanted frequency up to
/// [`HELD_MAX_RATE`] times the substep rate; its limit rows, solved one by one, up to a
/// quarter of it, and a limit that needs more raises the substeps, as a heavy stack's
/// contacts do.
pub fn joint_hertz(j: &JointConstraint, bodies: &[SolverBody], p: &ContactParams) -> (f32, f32) {
    let (a, b) = (body(bodies, j.a), body(bodies, j.b));
    let base = (2.0 * p.hertz).max(0.125 / p.h);
    // The lightest direction: along the offset (where a chain pulls), by the linear
    // masses alone when there is none.
    let n = j.offset.normalize_or(Vec3::Y);
    let k = linear_k(&a, &b, j.ra, j.rb, n);
    let linear = if k > 0.0 && j.load > 0.0 {
        (j.load * k / (p.max_sag * j.size.max(MIN_JOINT_SIZE))).sqrt()
    } else {
        0.0
    };
    // A torque T on a turn of inverse inertia k opens it by T·k/ω² rad; held to max_sag
    // rad (a limit, a weld).
    let t = j.torque_load.length();
    let axis = j.torque_load / t.max(f32::MIN_POSITIVE);
    let k = axis.dot((a.inv_inertia + b.inv_inertia) * axis);
    let angular = if k > 0.0 && t > 0.0 {
        (t * k / p.max_sag).sqrt()
    } else {
        0.0
    };
    let needed = linear.max(angular) / std::f32::consts::TAU;
    let needed = if needed.is_finite() { needed } else { 0.0 };
    (base.max(needed), needed)
}

/// The highest frequency of the rows that hold a joint together, in multiples of the
/// substep rate. Those rows are solved at once and exactly (`joint_direct`), an implicit
/// spring stable at any stiffness, so they are not held to the quarter of the substep
/// rate that Gauss–Seidel rows need; a joint's sag rule (see [`joint_hertz`]) may ask
/// for more. The 30-link chain under a 100:1 ball at 4 substeps stretched 2.86 % at a
/// quarter, 1.65 % at a half, 0.50 % at one and 0.13 % at two (where its sag rule is met);
/// a pendulum, a cradle and a taut plank bridge under a crate keep their energy at two.
pub const HELD_MAX_RATE: f32 = 2.0;

/// The most a jointed body may turn, in radians of its ringing per substep (ω·h), before
/// the substeps are raised: see [`tension_omega`].
pub const MAX_TENSION_TURN: f32 = 1.5;

/// How fast the stiffest jointed body rings about its joints, rad/s.
///
/// A body held at arm r by a joint that pulls with tension T (a link of a taut chain)
/// and turned by θ feels a torque T·|r|·θ back (the pull keeps its direction while its
/// arm turns): with k its inverse inertia across r, ω² = k·Σ T·|r| over its joints. The
/// solve freezes each row's direction over a substep, so it meets that stiffness
/// explicitly and, like a spring under symplectic Euler, stays stable only while ω·h < 2.
/// Measured: a 30-link chain whipping a 100:1 ball down from the horizontal (T up to
/// 560 N, ω ≈ 560 rad/s by this rule) blew apart at 4 substeps (ω·h ≈ 2.3) and held within 0.1 mm at
/// 5; the same chain hanging still (T 127 N, ω·h ≈ 1.1) needs no more than 4. `scratch`
/// is working space.
pub fn tension_omega(
    joints: &[JointConstraint],
    bodies: &[SolverBody],
    scratch: &mut Vec<(u32, f32)>,
) -> f32 {
    scratch.clear();
    for j in joints.iter().filter(|j| j.load > 0.0) {
        for (i, arm) in [(j.a, j.ra), (j.b, j.rb)] {
            if i == STATIC {
                continue;
            }
            let k = inverse_inertia_across(&bodies[i as usize].inv_inertia, arm);
            scratch.push((i, j.load * arm.length() * k));
        }
    }
    scratch.sort_unstable_by_key(|x| x.0);
    let most = scratch
        .chunk_by(|x, y| x.0 == y.0)
        .map(|run| run.iter().map(|x| x.1).sum::<f32>())
        .fold(0.0f32, f32::max);
    let omega = most.sqrt();
    if omega.is_finite() { omega } else { 0.0 }
}

/// The largest inverse inertia about an axis across `arm` (any axis when it is zero).
fn inverse_inertia_across(inv_inertia: &Mat3, arm: Vec3) -> f32 {
    let (t1, t2) = arm.normalize_or(Vec3::X).any_orthonormal_pair();
    let (a, b, c) = (
        t1.dot(*inv_inertia * t1),
        t1.dot(*inv_inertia * t2),
        t2.dot(*inv_inertia * t2),
    );
    0.5 * (a + c) + (0.25 * (a - c) * (a - c) + b * b).sqrt()
}

/// The least size a joint's sag is measured against, m (a joint at both centres of mass
/// has no arms).
pub const MIN_JOINT_SIZE: f32 = 0.05;

/// The damping ratio of the joints' position correction (Box2D v3's default).
pub const JOINT_DAMPING_RATIO: f32 = 2.0;

#[cfg(test)]
mod tests {
    use super::*;

    fn params(h: f32) -> ContactParams {
        ContactParams {
            bounce_threshold: 1.0,
            friction: true,
            hertz: 30.0,
            max_hertz: 0.25 / h,
            gravity: 9.81,
            damping_ratio: 10.0,
            h,
            dt: 1.0 / 60.0,
            max_push_out: 3.0,
            max_sag: 0.005,
        }
    }

    #[test]
    fn the_folded_need_is_the_largest_contacts_need() {
        // NeededHertz (one square root at the end) against the largest `needed` of
        // wanted_hertz contact by contact: the same bits, for random pairs and the odd
        // ones (two fixed sides, a size of 0, an impact).
        let p = params(1.0 / 240.0);
        let mut rng = crate::rng::Rnd(0x05ee_d5a9);
        for trial in 0..200 {
            let mut folded = NeededHertz::default();
            let mut largest = 0.0f32;
            for k in 0..1 + trial % 7 {
                let inv = |rng: &mut crate::rng::Rnd| match rng.unit() {
                    u if u < 0.2 => 0.0,
                    _ => 1.0 / rng.range(0.01, 1000.0),
                };
                let (ia, ib) = (inv(&mut rng), inv(&mut rng));
                let load = rng.range(0.0, 5.0);
                let size = if k == 3 { 0.0 } else { rng.range(0.001, 3.0) };
                let resting = rng.unit() < 0.7;
                folded.add(&p, (ia, ib), load, size, resting);
                largest = largest.max(wanted_hertz(&p, ia, ib, load, size, resting).needed);
            }
            assert_eq!(folded.hertz().to_bits(), largest.to_bits(), "trial {trial}");
        }
        assert_eq!(NeededHertz::default().hertz(), 0.0);
    }

    #[test]
    fn a_one_metre_box_on_the_floor_asks_for_no_more_than_the_default() {
        let p = params(1.0 / 240.0);
        let w = wanted_hertz(&p, 0.0, 1.0, 9.81 / 240.0, 1.0, true);
        assert!((w.ratio - 1.0).abs() < 1e-5);
        // Static contact: twice the base frequency; the sag rule needs 7 Hz.
        assert_eq!(w.hertz, 60.0);
        assert!(w.needed < 16.0, "{}", w.needed);
        assert_eq!(substeps_for(w.needed, 1.0 / 60.0, 4, 16), 4);
    }

    #[test]
    fn a_carried_load_stiffens_a_contact_but_only_a_heavy_body_damps_it_more() {
        // A 1 kg cube on the floor under a stack of 50 more (the load its impulses
        // show), and the same cube under one 50 kg block.
        let (p, h) = (params(1.0 / 240.0), 1.0 / 240.0);
        let (one, fifty) = (9.81 * h, 50.0 * 9.81 * h);
        let (stacked, r) = contact_softness(&p, 0.0, 1.0, fifty, one, 1.0);
        let (pressed, r_pressed) = contact_softness(&p, 0.0, 1.0, fifty, fifty, 1.0);
        assert!((r - 50.0).abs() < 1e-3 && (r_pressed - 50.0).abs() < 1e-3);
        // Both at the cap (60 Hz wanted ×√50); the stack's damping ratio stays at ζ.
        assert_eq!(stacked, Softness::new(p.max_hertz, p.damping_ratio, h));
        let zeta = p.damping_ratio * 50f32.sqrt();
        let expected = Softness::new(p.max_hertz, zeta, h);
        // (r is 50 to f32 round-off.)
        assert!(
            (pressed.bias_rate / expected.bias_rate - 1.0).abs() < 1e-5,
            "{pressed:?}"
        );
        assert!((pressed.impulse_scale / expected.impulse_scale - 1.0).abs() < 1e-5);
        assert!(pressed.mass_scale > stacked.mass_scale);
    }

    #[test]
    fn the_sag_a_contact_is_tuned_for_is_max_sag_of_its_size() {
        // Sag r·g/ω² at the wanted frequency, for a heavy load and for small bodies.
        let p = params(1.0 / 240.0);
        for (inv_a, inv_b, size) in [(1.0, 1e-3, 1.0), (0.0, 1.0 / 8e-3, 0.02)] {
            let w = wanted_hertz(&p, inv_a, inv_b, 0.0, size, true);
            let omega = TAU * w.needed.min(w.hertz);
            let sag = w.ratio * 9.81 / (omega * omega);
            assert!(
                sag <= p.max_sag * size * 1.0001,
                "sag {sag} for size {size}"
            );
        }
    }

    #[test]
    fn a_taut_link_rings_at_the_root_of_its_pull_arm_and_inertia() {
        // A 0.1 kg rod of 0.2 m (I across it m·L²/12), held at both ends (arms 0.1 m)
        // by pulls of 100 and 50 N, the world on the other side: ω² = k·(100 + 50)·0.1,
        // with k its inverse inertia across its length (not the huge one about it).
        use super::super::joint_direct_tests::random_joint;
        use crate::world::JointRows;
        let inertia = 0.1 * 0.2 * 0.2 / 12.0;
        let rod = SolverBody {
            v: Vec3::ZERO,
            w: Vec3::ZERO,
            dp: Vec3::ZERO,
            dq: bevy::math::Quat::IDENTITY,
            inv_mass: 10.0,
            // Thin along y: its spin about y is all but free, and no pull turns it.
            inv_inertia: Mat3::from_diagonal(Vec3::new(1.0 / inertia, 1e6, 1.0 / inertia)),
        };
        let joint = |load: f32, arm: Vec3| {
            let mut j = random_joint(&mut crate::rng::Rnd(1), JointRows::Spherical, STATIC, 0);
            (j.rb, j.load) = (arm, load);
            j
        };
        let joints = [joint(100.0, Vec3::Y * 0.1), joint(50.0, Vec3::Y * -0.1)];
        let omega = tension_omega(&joints, &[rod], &mut Vec::new());
        let expected = (150.0 * 0.1 / inertia).sqrt();
        assert!(
            (omega - expected).abs() < 1e-3 * expected,
            "{omega} against {expected}"
        );
        // Unloaded joints ring at nothing.
        let idle = [joint(0.0, Vec3::Y * 0.1)];
        assert_eq!(tension_omega(&idle, &[rod], &mut Vec::new()), 0.0);
    }

    #[test]
    fn substeps_follow_the_stiffest_contact_within_bounds() {
        let dt = 1.0 / 60.0;
        assert_eq!(substeps_for(0.0, dt, 4, 16), 4);
        assert_eq!(substeps_for(223.0, dt, 4, 16), 15);
        assert_eq!(substeps_for(1e9, dt, 4, 16), 16);
        assert_eq!(substeps_for(f32::NAN, dt, 4, 16), 4);
        assert_eq!(substeps_for(1e9, dt, 8, 4), 8);
    }
}
