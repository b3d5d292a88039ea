//! A search order over bounding boxes that rarely all change: sorted by lower x bound.
//!
//! A query box [lo, hi] can only meet boxes whose lower x lies in [lo.x − widest, hi.x],
//! found by binary search, where `widest` is the widest box along x. A few very wide
//! boxes (infinite planes, long walls) would make that window everything, so boxes more
//! than [`WIDE_FACTOR`] times the median width sit in a short list every query tests.
//! The fixed set keeps one over its entries (the awake colliders, which all move, are in
//! a tree instead: [`AwakeTree`](super::AwakeTree)).

use bevy::prelude::*;

/// Boxes wider along x than this many median widths go in the always-tested list.
pub(crate) const WIDE_FACTOR: f32 = 8.0;

#[derive(Default, Debug, Clone)]
pub(crate) struct BoundsIndex {
    /// Indices of the ordinary boxes, by lower x bound.
    sorted: Vec<u32>,
    /// Indices of the very wide boxes.
    wide: Vec<u32>,
    /// Widest ordinary box along x, m.
    widest: f32,
    /// The union of the finite boxes (empty: lo > hi), m.
    extent: (Vec3, Vec3),
    /// Scratch for the median width, kept so a rebuild does not allocate.
    widths: Vec<f32>,
}

impl BoundsIndex {
    /// Rebuilds the order over boxes `0..n`, `aabb(i)` giving box i.
    pub fn rebuild(&mut self, n: usize, aabb: impl Fn(u32) -> (Vec3, Vec3)) {
        let width = |i: u32| {
            let (lo, hi) = aabb(i);
            hi.x - lo.x
        };
        self.widths.clear();
        self.widths.extend((0..n as u32).map(width));
        let mid = self.widths.len() / 2;
        let median = if self.widths.is_empty() {
            0.0
        } else {
            *self.widths.select_nth_unstable_by(mid, f32::total_cmp).1
        };
        let limit = WIDE_FACTOR * median;
        self.sorted.clear();
        self.wide.clear();
        self.widest = 0.0;
        self.extent = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        for i in 0..n as u32 {
            let w = width(i);
            let (lo, hi) = aabb(i);
            if lo.is_finite() && hi.is_finite() {
                self.extent = (self.extent.0.min(lo), self.extent.1.max(hi));
            }
            if w.is_finite() && w <= limit {
                self.sorted.push(i);
                self.widest = self.widest.max(w);
            } else {
                self.wide.push(i);
            }
        }
        self.sorted
            .sort_by(|&a, &b| aabb(a).0.x.total_cmp(&aabb(b).0.x));
    }

    /// Calls `found` with every box that overlaps [lo, hi] (`aabb` as at the rebuild).
    #[inline]
    pub fn overlapping(
        &self,
        aabb: impl Fn(u32) -> (Vec3, Vec3),
        lo: Vec3,
        hi: Vec3,
        mut found: impl FnMut(u32),
    ) {
        let overlaps = |i: u32| {
            let (a, b) = aabb(i);
            a.cmple(hi).all() && lo.cmple(b).all()
        };
        let key = |i: &u32| aabb(*i).0.x;
        let start = self.sorted.partition_point(|i| key(i) < lo.x - self.widest);
        for &i in &self.sorted[start..] {
            if key(&i) > hi.x {
                break;
            }
            if overlaps(i) {
                found(i);
            }
        }
        for &i in &self.wide {
            if overlaps(i) {
                found(i);
            }
        }
    }

    /// The union of the finite boxes, m (lo > hi when there are none): infinite ones
    /// (an infinite plane) are left out.
    pub fn extent(&self) -> (Vec3, Vec3) {
        self.extent
    }
}
