//! The arithmetic of a batch's eight contacts at once: each manifold's points (lever
//! arms, normal rows and their masses, twist arms, approach speeds), the couplings
//! between them and the friction anchor, lane by lane, computed into the lanes the
//! batch is solved in (`super::prepare_contacts`). What a contact's header needs (its
//! flags, friction, push-out share) branches per manifold and stays scalar
//! (`Builder::header`; its softness goes in lanes too, `super::contact_load`); this part
//! is the same arithmetic for every manifold, about 700 flops of one with four points.
//!
//! Each lane does glam's operations in glam's order with no fused multiply-add (see
//! [`crate::math::lanes`]) and the scalar code's branches as selects, so a contact
//! built here is bit for bit the one `prepare_points` (the scalar reference, kept to
//! test this path) builds: `prepare_tests.rs` compares them on real scenes' manifolds.

use bevy::prelude::*;

use crate::math::Softness;
use crate::math::lanes::{F8, Lane, V3, gt, select};
use crate::world::{
    AnchorLanes, AngularRow, ConstraintPoint, ContactBatch, ContactConstraint, FrictionAnchor,
    FrictionLanes, MAX_POINTS, Manifold, PointLanes, SolverBody, coupling_index,
};

/// One side of eight contacts: what the arithmetic reads of its body.
#[derive(Clone, Copy, Default)]
struct SideLanes {
    /// The body's centre of mass (a static collider's position), m.
    centre: V3,
    /// 1/kg.
    inv_mass: F8,
    /// The world inverse inertia's columns, 1/(kg·m²).
    inv_inertia: [V3; 3],
    /// m/s, rad/s.
    v: V3,
    w: V3,
    /// All-ones lanes where the body turns here (`ContactConstraint::spin`).
    spin: F8,
}

/// Eight manifolds' inputs, lane by lane; lanes past the last manifold hold zeros and
/// are never read back.
#[derive(Clone, Copy, Default)]
pub(super) struct ManifoldLanes {
    normal: V3,
    tangent: [V3; 2],
    side: [SideLanes; 2],
    point: [V3; MAX_POINTS],
    /// m.
    separation: [F8; MAX_POINTS],
    /// Last step's normal impulses, N·s.
    normal_impulse: [F8; MAX_POINTS],
    /// Last step's friction shares at the points, N·s and N·m·s.
    tangent_impulse: [V3; MAX_POINTS],
    twist_impulse: [F8; MAX_POINTS],
    /// All-ones lanes whose manifold has more than k points, per k.
    has: [F8; MAX_POINTS],
    /// The points, at least one.
    count: F8,
    /// All-ones lanes whose manifold has a twist row (more than one point).
    many: F8,
}

/// Lanes `l` of the three columns of `m`.
#[inline(always)]
fn set_columns(columns: &mut [V3; 3], l: usize, m: &Mat3) {
    columns[0].set(l, m.x_axis);
    columns[1].set(l, m.y_axis);
    columns[2].set(l, m.z_axis);
}

const ALL: f32 = f32::from_bits(u32::MAX);

impl ManifoldLanes {
    /// Lane `l` set to manifold `m`, whose constraint's header `c` is built, between
    /// bodies `sides` with centres `centres`.
    #[inline(always)]
    pub(super) fn set(
        &mut self,
        l: usize,
        m: &Manifold,
        c: &ContactConstraint,
        sides: [&SolverBody; 2],
        centres: [Vec3; 2],
    ) {
        self.normal.set(l, m.normal);
        self.tangent[0].set(l, c.tangent1);
        self.tangent[1].set(l, c.tangent2);
        for (k, s) in self.side.iter_mut().enumerate() {
            let b = sides[k];
            s.centre.set(l, centres[k]);
            s.inv_mass.as_array_mut()[l] = b.inv_mass;
            set_columns(&mut s.inv_inertia, l, &b.inv_inertia);
            s.v.set(l, b.v);
            s.w.set(l, b.w);
            s.spin.as_array_mut()[l] = if c.spin[k] { ALL } else { 0.0 };
        }
        // Only the points it has (a sphere's one of four): the lanes of the others are
        // masked out where they would count (`has`).
        for (k, p) in m.points().iter().enumerate() {
            self.point[k].set(l, p.point);
            self.separation[k].as_array_mut()[l] = p.separation;
            self.normal_impulse[k].as_array_mut()[l] = p.normal_impulse;
            self.tangent_impulse[k].set(l, p.tangent_impulse);
            self.twist_impulse[k].as_array_mut()[l] = p.twist_impulse;
        }
        for (k, has) in self.has.iter_mut().enumerate() {
            has.as_array_mut()[l] = if k < m.len { ALL } else { 0.0 };
        }
        self.count.as_array_mut()[l] = m.len.max(1) as f32;
        self.many.as_array_mut()[l] = if m.len > 1 { ALL } else { 0.0 };
    }

    /// All-ones lanes that hold a contact.
    #[inline(always)]
    pub(super) fn any(&self) -> F8 {
        self.has[0]
    }

    /// Lane `l` empty: no points (what it computes is zero).
    #[inline(always)]
    pub(super) fn clear(&mut self, l: usize) {
        for has in &mut self.has {
            has.as_array_mut()[l] = 0.0;
        }
        self.many.as_array_mut()[l] = 0.0;
    }
}

/// What a contact's constraint holds beyond its batch's lanes (the rows' images under
/// the inverse inertias, the friction anchor), lane by lane: read back only for the
/// contacts kept as constraints.
#[derive(Clone, Copy, Default)]
pub(super) struct ConstraintExtras {
    /// Ia⁻¹ (ra × n), Ib⁻¹ (rb × n) of each point's normal row.
    normal_images: [[V3; 2]; MAX_POINTS],
    /// The friction anchor from each body's centre, m.
    anchor: [V3; 2],
    /// The tangent rows' images, per tangent.
    tangent_images: [[V3; 2]; 2],
    /// Ia⁻¹ n, Ib⁻¹ n.
    twist_images: [V3; 2],
}

/// Where a batch's lanes go: the batch (its header lanes set), its points and anchors
/// (as many as its longest contact has), its friction impulses, and the rest of its
/// constraints (`extras`, filled only when some lane's constraint is kept).
pub(super) struct BatchOut<'a> {
    pub batch: &'a mut ContactBatch,
    pub point: &'a mut [PointLanes],
    pub anchor: &'a mut [AnchorLanes],
    pub rubbing: &'a mut FrictionLanes,
    pub extras: Option<&'a mut ConstraintExtras>,
}

/// `m * v` for a matrix of columns `m`, in glam's order ((x·vx + y·vy) + z·vz).
#[inline(always)]
fn mat_mul<L: Lane>(m: &[V3; 3], v: V3<L>) -> V3<L> {
    let (x, y, z) = (m[0].get::<L>(), m[1].get::<L>(), m[2].get::<L>());
    x.scale(v.x).add(y.scale(v.y)).add(z.scale(v.z))
}

/// `mass_of`: 1/k, 0 where k ≤ 0.
#[inline(always)]
fn mass_of<L: Lane>(k: L) -> L {
    select(gt(k, L::splat(0.0)), L::splat(1.0) / k, L::splat(0.0))
}

/// `AngularRow::new`: [r_a × d, r_b × d, Ia⁻¹ (r_a × d), Ib⁻¹ (r_b × d)].
#[inline(always)]
fn angular_row<L: Lane>(sides: &[SideLanes; 2], ra: V3<L>, rb: V3<L>, d: V3<L>) -> [V3<L>; 4] {
    let (ra, rb) = (ra.cross(d), rb.cross(d));
    [
        ra,
        rb,
        mat_mul(&sides[0].inv_inertia, ra),
        mat_mul(&sides[1].inv_inertia, rb),
    ]
}

/// `AngularRow::inv_mass`: the row's angular share of the inverse effective mass.
#[inline(always)]
fn row_inv_mass<L: Lane>(row: &[V3<L>; 4], spin: [L; 2]) -> L {
    let zero = L::splat(0.0);
    select(spin[0], row[0].dot(row[2]), zero) + select(spin[1], row[1].dot(row[3]), zero)
}

/// `v` where `m` is set, else zero, as stored.
#[inline(always)]
fn keep<L: Lane>(m: L, v: L) -> F8 {
    select(m, v, L::splat(0.0)).store()
}

/// [`keep`] of a vector.
#[inline(always)]
fn keep3<L: Lane>(m: L, v: V3<L>) -> V3 {
    V3::select(m, v, V3::zero()).put()
}

/// The arithmetic of `prepare_points` on a batch's eight manifolds `m`, into `out`.
/// (No closures here: they would not inherit the AVX copy's features, and its
/// intrinsics would be called, not inlined.)
#[inline(always)]
pub(super) fn compute<L: Lane>(m: &ManifoldLanes, out: BatchOut) {
    let BatchOut {
        batch,
        point,
        anchor,
        rubbing,
        mut extras,
    } = out;
    debug_assert_eq!(point.len(), batch.points as usize, "the batch's points");
    debug_assert_eq!(anchor.len(), point.len(), "an anchor a point");
    let zero = L::splat(0.0);
    let [a, b] = &m.side;
    let n = m.normal.get::<L>();
    let (ca, cb) = (a.centre.get::<L>(), b.centre.get::<L>());
    let spin = [L::load(a.spin), L::load(b.spin)];
    let linear = L::load(a.inv_mass) + L::load(b.inv_mass);
    let dv = b.v.get::<L>().sub(a.v.get::<L>());
    let (wa, wb) = (a.w.get::<L>(), b.w.get::<L>());
    // The points' centre: glam's sum from zero, absent points adding -0 (x + (-0) is
    // x, bit for bit). Points past the batch's most are absent in every lane.
    let most = point.len();
    let absent = V3::<L> {
        x: L::splat(-0.0),
        y: L::splat(-0.0),
        z: L::splat(-0.0),
    };
    let mut sum = V3::<L>::zero();
    for k in 0..most {
        let has = L::load(m.has[k]);
        sum = sum.add(V3::select(has, m.point[k].get::<L>(), absent));
    }
    let count = L::load(m.count);
    let mid = V3 {
        x: sum.x / count,
        y: sum.y / count,
        z: sum.z / count,
    };
    batch.has = m.has;
    let mut rows = [[V3::<L>::zero(); 4]; MAX_POINTS];
    for (k, (o, an)) in point.iter_mut().zip(anchor.iter_mut()).enumerate() {
        let has = L::load(m.has[k]);
        let p = m.point[k].get::<L>();
        let (ra, rb) = (p.sub(ca), p.sub(cb));
        let row = angular_row(&m.side, ra, rb, n);
        let d = p.sub(mid);
        let plane = d.sub(n.scale(n.dot(d)));
        let mut v = n.dot(dv);
        v = select(spin[0], v - wa.dot(row[0]), v);
        v = select(spin[1], v + wb.dot(row[1]), v);
        let adjusted = L::load(m.separation[k]) - n.dot(rb.sub(ra));
        *o = PointLanes {
            normal_ra: keep3(has, row[0]),
            normal_rb: keep3(has, row[1]),
            normal_mass: keep(has, mass_of(linear + row_inv_mass(&row, spin))),
            normal_impulse: keep(has, L::load(m.normal_impulse[k])),
            twist_arm: keep(has, plane.dot(plane).sqrt()),
            max_normal_impulse: F8::ZERO,
            relative_velocity: keep(has, v),
            separation: F8::ZERO,
        };
        *an = AnchorLanes {
            ra: keep3(has, ra),
            rb: keep3(has, rb),
            adjusted_separation: keep(has, adjusted),
        };
        if let Some(x) = extras.as_deref_mut() {
            x.normal_images[k] = [keep3(has, row[2]), keep3(has, row[3])];
        }
        rows[k] = row;
    }
    // (Couplings past the batch's most points stay the zeros the batch was packed with.)
    for j in 1..most {
        let has = L::load(m.has[j]);
        for k in 0..j {
            let ta = select(spin[0], rows[j][0].dot(rows[k][2]), zero);
            let tb = select(spin[1], rows[j][1].dot(rows[k][3]), zero);
            batch.coupling[coupling_index(j, k)] = keep(has, linear + (ta + tb));
        }
    }
    // The friction anchor (`friction_anchor`), at the points' centre.
    let any = L::load(m.has[0]);
    let (fa, fb) = (mid.sub(ca), mid.sub(cb));
    // Last step's friction from the points' shares: glam's Vec3 sum from zero, std's f32
    // sum from -0.
    let mut shares = V3::<L>::zero();
    let mut turn = L::splat(-0.0);
    for k in 0..most {
        let has = L::load(m.has[k]);
        shares = shares.add(V3::select(has, m.tangent_impulse[k].get::<L>(), absent));
        turn = turn + select(has, L::load(m.twist_impulse[k]), L::splat(-0.0));
    }
    let mut tangent_k = [zero; 2];
    let mut images = [[V3::<L>::zero(); 2]; 2];
    for (k, t) in m.tangent.iter().enumerate() {
        let t = t.get::<L>();
        let row = angular_row(&m.side, fa, fb, t);
        tangent_k[k] = linear + row_inv_mass(&row, spin);
        batch.tangent_ra[k] = keep3(any, row[0]);
        batch.tangent_rb[k] = keep3(any, row[1]);
        images[k] = [row[2], row[3]];
        rubbing.tangent_impulse[k] = keep(any, shares.dot(t));
    }
    batch.tangent_mass = keep(any, mass_of(L::splat(0.5) * (tangent_k[0] + tangent_k[1])));
    let (ia, ib) = (mat_mul(&a.inv_inertia, n), mat_mul(&b.inv_inertia, n));
    let twist = select(spin[0], n.dot(ia), zero) + select(spin[1], n.dot(ib), zero);
    let many = L::load(m.many);
    batch.twist_mass = keep(many, mass_of(twist));
    rubbing.twist_impulse = keep(many, turn);
    if let Some(x) = extras {
        x.anchor = [keep3(any, fa), keep3(any, fb)];
        for (o, [i, j]) in x.tangent_images.iter_mut().zip(images) {
            *o = [keep3(any, i), keep3(any, j)];
        }
        x.twist_images = [keep3(any, ia), keep3(any, ib)];
    }
}

impl ConstraintExtras {
    /// Lane `l` of a batch (see [`BatchOut`]) into the constraint `c` of manifold `m`
    /// (its header already built).
    #[inline(always)]
    pub(super) fn write(
        &self,
        l: usize,
        (batch, point, anchor, rubbing): (
            &ContactBatch,
            &[PointLanes],
            &[AnchorLanes],
            &FrictionLanes,
        ),
        m: &Manifold,
        c: &mut ContactConstraint,
    ) {
        let f = |v: &F8| v.as_array_ref()[l];
        let row = |ra: &V3, rb: &V3, [ia, ib]: &[V3; 2]| AngularRow {
            ra: ra.lane(l),
            rb: rb.lane(l),
            ia: ia.lane(l),
            ib: ib.lane(l),
        };
        for (k, cp) in c.points[..m.len].iter_mut().enumerate() {
            let (o, an) = (&point[k], &anchor[k]);
            *cp = ConstraintPoint {
                ra: an.ra.lane(l),
                rb: an.rb.lane(l),
                adjusted_separation: f(&an.adjusted_separation),
                normal_row: row(&o.normal_ra, &o.normal_rb, &self.normal_images[k]),
                normal_mass: f(&o.normal_mass),
                normal_impulse: f(&o.normal_impulse),
                twist_arm: f(&o.twist_arm),
                max_normal_impulse: 0.0,
                relative_velocity: f(&o.relative_velocity),
                separation: 0.0,
            };
        }
        c.softness = Softness {
            bias_rate: f(&batch.bias_rate),
            mass_scale: f(&batch.mass_scale),
            impulse_scale: f(&batch.impulse_scale),
        };
        c.coupling = batch.coupling.map(|k| f(&k));
        let t = &rubbing.tangent_impulse;
        let [t0, t1] = &self.tangent_images;
        c.anchor = FrictionAnchor {
            ra: self.anchor[0].lane(l),
            rb: self.anchor[1].lane(l),
            tangent_rows: [
                row(&batch.tangent_ra[0], &batch.tangent_rb[0], t0),
                row(&batch.tangent_ra[1], &batch.tangent_rb[1], t1),
            ],
            tangent_mass: f(&batch.tangent_mass),
            tangent_impulse: Vec2::new(f(&t[0]), f(&t[1])),
            twist_ia: self.twist_images[0].lane(l),
            twist_ib: self.twist_images[1].lane(l),
            twist_mass: f(&batch.twist_mass),
            twist_impulse: f(&rubbing.twist_impulse),
        };
    }
}
