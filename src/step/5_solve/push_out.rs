//! How fast one contact may push overlapping bodies apart: a body buried in several
//! others shares its push-out among them.

/// Overlap at spawn: a body buried in k others is pushed out by k contacts at once. If
/// each could push at the full `max_push_out`, their pushes would add up along chains of
/// bodies (300 boxes spawned at one point flew apart at 73 m/s). So each body's push-out
/// is shared among its overlapping contacts: a contact may push at most
/// `max_push_out / k^0.6` for the larger k of its two bodies. Measured on 300 boxes at
/// one point in zero g, five different spawn orders: k^0.6 peaks at 2.1–2.7 m/s for a
/// 3 m/s limit and parts the pile in 2.9 s; √k peaked at 3.8–4.0 m/s (chains of pushes
/// still add up); 1/k was still parting it after 10 s. Resting contacts are barely
/// overlapping and push far slower than any share, so they don't notice.
pub const PUSH_OUT_SHARE_EXPONENT: f32 = 0.6;

/// The fastest push-out one contact may drive, given how many overlapping contacts each
/// of its bodies has (see [`PUSH_OUT_SHARE_EXPONENT`]).
pub(crate) fn push_out_share(max_push_out: f32, overlaps_a: u32, overlaps_b: u32) -> f32 {
    let k = overlaps_a.max(overlaps_b);
    if k <= 1 {
        // 1^0.6 is exactly 1: the same bits without the `powf` (most contacts).
        return max_push_out;
    }
    max_push_out / (k as f32).powf(PUSH_OUT_SHARE_EXPONENT)
}

/// [`push_out_share`] for the counts a step meets most, worked out once a run: each
/// overlapping contact of a resting pile has a count of a few, and a `powf` per contact
/// was 1 % of the 385-cube pyramid's samples. The same calls, so the same bits.
pub(super) struct PushOutShares {
    max_push_out: f32,
    /// `push_out_share(max_push_out, k, 0)` for k below [`Self::TABLED`].
    table: [f32; Self::TABLED as usize],
}

impl PushOutShares {
    /// The counts tabled: 0 to 15 (beyond, the `powf` is paid).
    const TABLED: u32 = 16;

    pub(super) fn new(max_push_out: f32) -> Self {
        let mut table = [0.0; Self::TABLED as usize];
        for (k, share) in (0..).zip(table.iter_mut()) {
            *share = push_out_share(max_push_out, k, 0);
        }
        Self {
            max_push_out,
            table,
        }
    }

    /// [`push_out_share`]`(max_push_out, overlaps_a, overlaps_b)`.
    #[inline]
    pub(super) fn get(&self, overlaps_a: u32, overlaps_b: u32) -> f32 {
        let k = overlaps_a.max(overlaps_b);
        match self.table.get(k as usize) {
            Some(&share) => share,
            None => push_out_share(self.max_push_out, k, 0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_gives_what_the_rule_gives() {
        let shares = PushOutShares::new(3.0);
        for a in 0..40 {
            for b in [0, 1, 7, a, 39] {
                assert_eq!(
                    shares.get(a, b).to_bits(),
                    push_out_share(3.0, a, b).to_bits(),
                    "counts {a}, {b}"
                );
            }
        }
        // The rule itself: k^0.6 shares, none for one overlap or none.
        assert_eq!(shares.get(0, 1), 3.0);
        let four = 3.0 / 4f32.powf(0.6);
        assert!((shares.get(4, 2) - four).abs() <= 1e-6 * four);
    }
}
