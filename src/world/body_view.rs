//! How the contact kernels reach the bodies: a [`BodyView`], either the plain slice or,
//! while two threads split a level of batches, [`SharedBodies`], the same array by raw
//! pointer (no thread holds a reference the other's writes alias).

use bevy::prelude::*;

use super::constraint::STATIC_BODY;
use super::{STATIC, SolverBody};

/// Read a body (the shared static one for [`STATIC`]); write a body's velocities.
pub(crate) trait BodyView {
    fn get(&self, i: u32) -> SolverBody;
    fn set_velocity(&mut self, i: u32, v: Vec3, w: Vec3);
}

impl BodyView for [SolverBody] {
    #[inline(always)]
    fn get(&self, i: u32) -> SolverBody {
        if i == STATIC {
            STATIC_BODY
        } else {
            self[i as usize]
        }
    }

    #[inline(always)]
    fn set_velocity(&mut self, i: u32, v: Vec3, w: Vec3) {
        let b = &mut self[i as usize];
        (b.v, b.w) = (v, w);
    }
}

/// The bodies of one solve shared between the threads that split a level: the contacts
/// of a level move disjoint bodies (`ContactBatches`), and a thread writes only the
/// bodies its own batches move, so no two threads touch one body's velocities while
/// either writes them. Positions and masses are read only.
#[derive(Clone, Copy)]
pub(crate) struct SharedBodies {
    ptr: *mut SolverBody,
    len: usize,
}

// SAFETY: see the type's documentation; the split driver (`5_solve/split.rs`) keeps
// threads to disjoint moved bodies and orders levels with acquire/release atomics.
unsafe impl Send for SharedBodies {}
unsafe impl Sync for SharedBodies {}

impl SharedBodies {
    pub(crate) fn new(bodies: &mut [SolverBody]) -> Self {
        Self {
            ptr: bodies.as_mut_ptr(),
            len: bodies.len(),
        }
    }

    /// The whole slice, for work the calling thread does alone.
    ///
    /// # Safety
    /// No other thread may touch the bodies while the slice lives.
    pub(crate) unsafe fn slice(&mut self) -> &mut [SolverBody] {
        // SAFETY: the caller's promise; `ptr` and `len` come from a live slice.
        unsafe { std::slice::from_raw_parts_mut(self.ptr, self.len) }
    }
}

impl BodyView for SharedBodies {
    #[inline(always)]
    fn get(&self, i: u32) -> SolverBody {
        if i == STATIC {
            return STATIC_BODY;
        }
        assert!((i as usize) < self.len, "body index out of range");
        // SAFETY: in bounds; no other thread writes a body this thread's batch reads
        // (see the type's documentation).
        unsafe { self.ptr.add(i as usize).read() }
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
