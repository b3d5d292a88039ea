//! The render side, behind the `viz` feature: reusable plugins a game can add one by one,
//! and the demo built from them.
//!
//! - [`BodyMeshPlugin`]: meshes for bodies that have none, coloured by mass.
//! - [`DragBodiesPlugin`]: click to select, drag to pull, release to throw.
//! - [`DebugRenderPlugin`]: gizmos for contacts, bounding boxes and velocities.
//! - [`CapturePlugin`]: frame-counted screenshots for headless runs.
//! - [`demo::DemoPlugin`]: the demo application (scenes, keys, egui panel).

mod capture;
mod debug_render;
pub mod demo;
mod drag;
mod meshes;

pub use capture::{CapturePlugin, CaptureRequest};
pub use debug_render::{DebugRenderPlugin, DebugRenderSettings};
pub use drag::{DragBodiesPlugin, Dragged, Selected};
pub use meshes::{BodyMeshPlugin, MassColors, mass_color};
