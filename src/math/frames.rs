//! Poses between frames.

use bevy::prelude::*;

/// A world pose `(pos, rot)` in the frame of a parent at `parent` (uniform scale): the
/// local `Transform`'s translation and rotation.
pub fn to_parent_frame(parent: &Transform, pos: Vec3, rot: Quat) -> (Vec3, Quat) {
    let inv = parent.rotation.inverse();
    let local = inv * (pos - parent.translation) / parent.scale.x;
    (local, (inv * rot).normalize())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_parent_frame_undoes_the_parents_transform() {
        let parent = Transform::from_xyz(1.0, -2.0, 3.0)
            .with_rotation(Quat::from_rotation_y(0.7))
            .with_scale(Vec3::splat(2.0));
        let local = Transform::from_xyz(0.5, 0.25, -1.0).with_rotation(Quat::from_rotation_x(0.3));
        let world = parent.mul_transform(local);
        let (p, q) = to_parent_frame(&parent, world.translation, world.rotation);
        assert!(p.distance(local.translation) < 1e-6, "{p}");
        assert!(q.angle_between(local.rotation) < 1e-6);
    }
}
