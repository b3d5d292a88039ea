//! How the contact kernels reach the bodies: a [`BodyView`], either the plain slice or,
//! while two threads split a level of batches, [`SharedBodies`], the same array by raw
//! pointer (no thread holds a reference the other's writes alias).

use std::ops::Range;

use bevy::prelude::*;

use super::constraint::STATIC_BODY;
use super::{STATIC, SolverBody};

/// Read a body (the shared static one for [`STATIC`]); write a body's velocities.
pub(crate) trait BodyView {
    /// Body `i`, in place: a kernel that reads a few fields loads only those (a copy of
    /// the whole 92-byte body, static or not, cost the batched pass a sixth of its
    /// instructions).
    fn at(&self, i: u32) -> &SolverBody;
    fn set_velocity(&mut self, i: u32, v: Vec3, w: Vec3);
}

/// The static body as a place to point at.
static STATIC_PLACE: SolverBody = STATIC_BODY;

impl BodyView for [SolverBody] {
    #[inline(always)]
    fn at(&self, i: u32) -> &SolverBody {
        if i == STATIC {
            &STATIC_PLACE
        } else {
            &self[i as usize]
        }
    }

    #[inline(always)]
    fn set_velocity(&mut self, i: u32, v: Vec3, w: Vec3) {
        let b = &mut self[i as usize];
        (b.v, b.w) = (v, w);
    }
}

/// A slice shared by raw pointer between the threads of a split pass, each touching only
/// its own part of it while another thread may write.
#[derive(Clone, Copy)]
pub(crate) struct Shared<T> {
    ptr: *mut T,
    len: usize,
}

// SAFETY: threads take disjoint parts (`slice`'s and `BodyView`'s contracts below); the
// split driver (`5_solve/split.rs`) orders levels with acquire/release atomics.
unsafe impl<T: Send> Send for Shared<T> {}
unsafe impl<T: Send> Sync for Shared<T> {}

impl<T> Shared<T> {
    pub(crate) fn new(items: &mut [T]) -> Self {
        Self {
            ptr: items.as_mut_ptr(),
            len: items.len(),
        }
    }

    /// The items of `range`.
    ///
    /// # Safety
    /// No other thread may touch them while the slice lives.
    #[allow(clippy::mut_from_ref)]
    pub(crate) unsafe fn slice(&self, range: Range<usize>) -> &mut [T] {
        assert!(range.start <= range.end && range.end <= self.len);
        // SAFETY: in bounds; exclusive by the caller's promise.
        unsafe { std::slice::from_raw_parts_mut(self.ptr.add(range.start), range.len()) }
    }

    /// All the items.
    ///
    /// # Safety
    /// As [`slice`](Self::slice): no other thread may touch any of them meanwhile.
    #[allow(clippy::mut_from_ref)]
    pub(crate) unsafe fn whole(&self) -> &mut [T] {
        // SAFETY: the caller's promise.
        unsafe { self.slice(0..self.len) }
    }
}

/// The bodies of one solve, shared between the threads that split a level: the contacts
/// of a level move disjoint bodies (`ContactBatches`), and a thread writes only the
/// bodies its own batches move, so no two threads touch one body's velocities while
/// either writes them. Positions and masses are read only.
pub(crate) type SharedBodies = Shared<SolverBody>;

impl BodyView for SharedBodies {
    #[inline(always)]
    fn at(&self, i: u32) -> &SolverBody {
        if i == STATIC {
            return &STATIC_PLACE;
        }
        assert!((i as usize) < self.len, "body index out of range");
        // SAFETY: in bounds; no other thread writes a body this thread's batch reads
        // while the reference lives (the kernels read a body before they write it).
        unsafe { &*self.ptr.add(i as usize) }
    }

    #[inline(always)]
    fn set_velocity(&mut self, i: u32, v: Vec3, w: Vec3) {
        assert!((i as usize) < self.len, "body index out of range");
        // SAFETY: in bounds; only this thread touches a body its batch moves.
        unsafe {
            let b = self.ptr.add(i as usize);
            (*b).v = v;
            (*b).w = w;
        }
    }
}
