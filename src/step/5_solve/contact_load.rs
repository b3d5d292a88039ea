//! A contact's softness and the passes it asks for, from its masses and its load
//! ([`contact_softness`] and the load rule of `Builder::header`): one contact at a time
//! ([`Load::soften`], the reference) and eight at a time ([`LoadLanes::soften`], for a
//! batch's contacts). The lanes do the scalar code's operations in its order, its
//! branches as selects, so each lane is bit for bit the scalar answer
//! (`prepare_tests.rs` compares every contact built both ways).

use crate::math::Softness;
use crate::math::lanes::{F8, Lane, eq, gt, le, lt, max, select};
use crate::world::ContactParams;

use super::stiffness::{STACK_LOAD, contact_softness, load_ratio};

/// The mass ratio (heavier over lighter, or the heaviest body pressing on a contact over
/// its lighter body) from which an impact's impulse counts as a load for the passes: the
/// ratio at which the passes' rule (`iterations_for`) asks for a second pass. Below it,
/// impacts between like masses are not counted: the spheres in a box (1 and 8 kg balls,
/// bouncing) went from 1.98 to 1.02 solve passes a substep, rain (2,000 bodies falling
/// on each other) from 2.47 to 1.60.
pub const SQUEEZE_RATIO: f32 = 10.0;

/// What a contact's softness and load ratio depend on.
#[derive(Clone, Copy, Debug)]
pub(super) struct Load {
    /// The two sides' inverse masses, 1/kg.
    pub inv_mass: [f32; 2],
    /// Last step's normal impulse on the contact (at least `weight`), N·s.
    pub load: f32,
    /// The heaviest body touching either side, kg, and its weight over a substep, N·s.
    pub heaviest: f32,
    pub weight: f32,
    /// The size that sets the allowed sag (`pair_size`), m.
    pub size: f32,
    /// The pair closes or parts slower than gravity changes speed in two steps.
    pub resting: bool,
    /// `Manifold::previous_load`, N·s.
    pub previous_load: f32,
    pub restitution: f32,
}

/// A contact's softness, its load ratio r (what sets the solve passes) and the ratio
/// that sets the relax passes.
pub(super) struct Softened {
    pub softness: Softness,
    pub ratio: f32,
    pub relax: f32,
}

impl Load {
    /// The contact's softness and ratios. An impact's impulse between bodies of like
    /// mass is no load: a pair closing or parting fast counts only its mass ratio and
    /// the heaviest body pressing on it, and a resting pair the smaller of its last two
    /// steps' loads (a body struck from above passes the blow on to the floor for one
    /// step). Unless that ratio is a squeeze's ([`SQUEEZE_RATIO`]): a heavy body landing
    /// on a light one squeezes it, and the squeeze needs the passes its impulse asks for
    /// (tests/regress_squeezed_box_restitution.rs).
    pub(super) fn soften(&self, p: &ContactParams) -> Softened {
        let [ia, ib] = self.inv_mass;
        let (softness, r) = contact_softness(p, ia, ib, self.load, self.weight, self.size);
        let (lo, hi) = (ia.min(ib), ia.max(ib));
        let mass_ratio = if lo > 0.0 { hi / lo } else { 1.0 };
        let pressing = mass_ratio.max(self.heaviest * hi).max(1.0);
        let ratio = if pressing >= SQUEEZE_RATIO {
            r
        } else if self.resting {
            // A load that stays: the smaller of the last two steps' (an impact's
            // impulse lasts one).
            let steady = self.load.min(self.previous_load.max(self.weight));
            load_ratio(p, lo, hi, steady)
        } else {
            pressing
        };
        Softened {
            softness,
            ratio,
            relax: if self.restitution > 0.0 {
                ratio
            } else {
                mass_ratio
            },
        }
    }
}

/// Eight contacts' [`Load`]s, lane by lane (`resting` all-ones where set).
#[derive(Clone, Copy, Default)]
pub(super) struct LoadLanes {
    inv_mass: [F8; 2],
    load: F8,
    heaviest: F8,
    weight: F8,
    size: F8,
    resting: F8,
    previous_load: F8,
    restitution: F8,
}

/// [`LoadLanes::soften`]'s answer, as stored.
pub(super) struct SoftenedLanes {
    pub bias_rate: F8,
    pub mass_scale: F8,
    pub impulse_scale: F8,
    pub ratio: F8,
    pub relax: F8,
}

/// `f32::min` per lane: `b` where it is less or `a` is NaN, else `a`.
#[inline(always)]
fn min<L: Lane>(a: L, b: L) -> L {
    select(eq(a, a), select(lt(b, a), b, a), b)
}

/// `stiffness::load_ratio` per lane (`lo`, `hi`: the pair's inverse masses).
#[inline(always)]
fn load_ratio_lanes<L: Lane>(p: &ContactParams, lo: L, hi: L, impulse: L) -> L {
    let one = L::splat(1.0);
    let light = one / hi;
    let heavy = select(gt(lo, L::splat(0.0)), one / lo, light);
    let carried = if p.gravity > 0.0 {
        impulse / L::splat(p.gravity * p.h)
    } else {
        L::splat(0.0)
    };
    max(max(heavy, carried) / light, one)
}

impl LoadLanes {
    /// Lane `l` set to `x`.
    #[inline(always)]
    pub(super) fn set(&mut self, l: usize, x: &Load) {
        let lane = |v: &mut F8, x: f32| v.as_array_mut()[l] = x;
        lane(&mut self.inv_mass[0], x.inv_mass[0]);
        lane(&mut self.inv_mass[1], x.inv_mass[1]);
        lane(&mut self.load, x.load);
        lane(&mut self.heaviest, x.heaviest);
        lane(&mut self.weight, x.weight);
        lane(&mut self.size, x.size);
        let all = f32::from_bits(u32::MAX);
        lane(&mut self.resting, if x.resting { all } else { 0.0 });
        lane(&mut self.previous_load, x.previous_load);
        lane(&mut self.restitution, x.restitution);
    }

    /// [`Load::soften`] of each lane, with `contact_softness` (and the `wanted_hertz`,
    /// `sag_omega_squared`, `hertz_of` and `Softness::new` under it) written out in
    /// lanes. Lanes whose inverse masses are both zero get what the scalar code gives
    /// them; empty lanes compute garbage the caller masks.
    #[inline(always)]
    pub(super) fn soften<L: Lane>(&self, p: &ContactParams) -> SoftenedLanes {
        let (zero, one) = (L::splat(0.0), L::splat(1.0));
        let (ia, ib) = (L::load(self.inv_mass[0]), L::load(self.inv_mass[1]));
        let (lo, hi) = (min(ia, ib), max(ia, ib));
        let (load, weight, size) = (L::load(self.load), L::load(self.weight), L::load(self.size));
        // wanted_hertz(.., resting: true): the load rule and the sag rule.
        let r = load_ratio_lanes(p, lo, hi, load);
        let base = select(eq(lo, zero), L::splat(2.0 * p.hertz), L::splat(p.hertz));
        let (light, heavy) = (one / hi, select(gt(lo, zero), one / lo, one / hi));
        let shown = min(r, L::splat(STACK_LOAD));
        let resting_load = max(heavy / light, shown);
        let omega_squared = resting_load * L::splat(p.gravity) / (L::splat(p.max_sag) * size);
        let needed = omega_squared.sqrt() / L::splat(std::f32::consts::TAU);
        let needed = select(needed.is_finite(), needed, zero);
        let hertz = max(base * r.sqrt(), needed);
        let no_mass = eq(hi, zero);
        let (hertz, r) = (select(no_mass, zero, hertz), select(no_mass, one, r));
        // contact_softness: the damping ratio grows as √ of the heaviest pressing body's
        // ratio; Softness::new.
        let zeta = L::splat(p.damping_ratio) * load_ratio_lanes(p, lo, hi, weight).sqrt();
        let hertz = min(hertz, L::splat(p.max_hertz));
        let h = L::splat(p.h);
        let omega = L::splat(std::f32::consts::TAU) * hertz;
        let a1 = L::splat(2.0) * zeta + h * omega;
        let a2 = h * omega * a1;
        let a3 = one / (one + a2);
        let soft = gt(hertz, zero);
        // The load rule of the passes.
        let mass_ratio = select(gt(lo, zero), hi / lo, one);
        let pressing = max(max(mass_ratio, L::load(self.heaviest) * hi), one);
        let steady = min(load, max(L::load(self.previous_load), weight));
        let resting = load_ratio_lanes(p, lo, hi, steady);
        let squeezed = le(L::splat(SQUEEZE_RATIO), pressing);
        let ratio = select(
            squeezed,
            r,
            select(L::load(self.resting), resting, pressing),
        );
        let bounces = gt(L::load(self.restitution), zero);
        SoftenedLanes {
            bias_rate: select(soft, omega / a1, zero).store(),
            mass_scale: select(soft, a2 * a3, one).store(),
            impulse_scale: select(soft, a3, zero).store(),
            ratio: ratio.store(),
            relax: select(bounces, ratio, mass_ratio).store(),
        }
    }
}
