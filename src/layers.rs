//! Collision layers and sensors: which colliders touch, and which only report overlaps.
//!
//! A collider is a member of some of 32 layers and filters for some of them. Two colliders
//! interact only when each is a member of a layer the other filters for. Without
//! [`CollisionLayers`] a collider is a member of layer 0 and filters for every layer
//! (avian3d's default too), so everything touches everything.
//!
//! Filtered pairs are dropped before their manifold is computed: they cost the broad
//! phase's bounds test and one mask test, no more. The same filter serves the spatial
//! queries.
//!
//! Name layers with constants (`const PLAYER: LayerMask = LayerMask::layer(1);`) or with
//! an enum through [`physics_layers!`](crate::physics_layers):
//!
//! ```
//! use tumble::prelude::*;
//! tumble::physics_layers! {
//!     /// The game's layers.
//!     pub enum Layer { Default, Player, Enemy, Bullet }
//! }
//! // Bullets hit enemies and the world, not players or other bullets.
//! let bullet = CollisionLayers::new(Layer::Bullet, [Layer::Default, Layer::Enemy]);
//! let player = CollisionLayers::new(Layer::Player, LayerMask::ALL);
//! assert!(!bullet.interacts_with(player));
//! ```

use std::ops::{BitAnd, BitOr, Not};

use bevy::prelude::*;

/// A set of the 32 collision layers, one bit each.
#[derive(Reflect, Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct LayerMask(pub u32);

impl LayerMask {
    /// No layer.
    pub const NONE: Self = Self(0);
    /// Every layer.
    pub const ALL: Self = Self(u32::MAX);
    /// Layer 0, the one every collider is a member of by default.
    pub const DEFAULT: Self = Self(1);

    /// The mask of the single layer `index` (0–31). Usable in constants; an index of 32
    /// or more fails to compile in a constant and panics elsewhere.
    pub const fn layer(index: u32) -> Self {
        assert!(index < 32, "collision layers are numbered 0 to 31");
        Self(1 << index)
    }

    /// Both sets' layers.
    pub const fn union(self, other: Self) -> Self {
        Self(self.0 | other.0)
    }

    /// Whether the two sets share a layer.
    pub const fn intersects(self, other: Self) -> bool {
        self.0 & other.0 != 0
    }

    /// Whether every layer of `other` is in this set.
    pub const fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }
}

impl BitOr for LayerMask {
    type Output = Self;
    fn bitor(self, rhs: Self) -> Self {
        self.union(rhs)
    }
}

impl BitAnd for LayerMask {
    type Output = Self;
    fn bitand(self, rhs: Self) -> Self {
        Self(self.0 & rhs.0)
    }
}

impl Not for LayerMask {
    type Output = Self;
    fn not(self) -> Self {
        Self(!self.0)
    }
}

impl From<u32> for LayerMask {
    fn from(bits: u32) -> Self {
        Self(bits)
    }
}

/// A game's named layer: usually an enum made by [`physics_layers!`](crate::physics_layers).
pub trait PhysicsLayer: Copy {
    /// The layer's index, 0–31.
    fn index(self) -> u32;
}

impl<L: PhysicsLayer> From<L> for LayerMask {
    fn from(layer: L) -> Self {
        Self::layer(layer.index())
    }
}

impl<L: PhysicsLayer, const N: usize> From<[L; N]> for LayerMask {
    fn from(layers: [L; N]) -> Self {
        layers
            .into_iter()
            .fold(Self::NONE, |mask, l| mask | Self::from(l))
    }
}

/// Declares an enum of named collision layers: its variants are layers 0, 1, 2, … in
/// order (at most 32), and it converts into a [`LayerMask`], alone or in arrays.
#[macro_export]
macro_rules! physics_layers {
    ($(#[$meta:meta])* $vis:vis enum $name:ident { $($(#[$vmeta:meta])* $variant:ident),+ $(,)? }) => {
        $(#[$meta])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        #[repr(u32)]
        $vis enum $name { $($(#[$vmeta])* $variant),+ }

        impl $crate::layers::PhysicsLayer for $name {
            fn index(self) -> u32 {
                const _: () = assert!([$($name::$variant),+].len() <= 32, "at most 32 layers");
                self as u32
            }
        }
    };
}

/// The layers a collider is a member of, and the layers it touches. Two colliders touch
/// only when each one's `memberships` meets the other's `filters`. Changing it acts from
/// the next step (a sleeper on a floor that stops filtering for it wakes and falls).
#[derive(Component, Reflect, Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[reflect(Component)]
pub struct CollisionLayers {
    /// The layers the collider is a member of. Default layer 0.
    pub memberships: LayerMask,
    /// The layers whose members the collider touches. Default every layer.
    pub filters: LayerMask,
}

impl CollisionLayers {
    /// Member of layer 0, touches every layer: what a collider without the component has.
    pub const DEFAULT: Self = Self::from_bits(LayerMask::DEFAULT.0, LayerMask::ALL.0);
    /// Member of every layer, touches every layer.
    pub const ALL: Self = Self::from_bits(u32::MAX, u32::MAX);
    /// Member of no layer, touches nothing.
    pub const NONE: Self = Self::from_bits(0, 0);

    /// Layers from anything that converts into masks: a [`LayerMask`], a layer enum
    /// value, an array of them, or raw bits.
    pub fn new(memberships: impl Into<LayerMask>, filters: impl Into<LayerMask>) -> Self {
        Self {
            memberships: memberships.into(),
            filters: filters.into(),
        }
    }

    /// Layers from raw bits, for constants.
    pub const fn from_bits(memberships: u32, filters: u32) -> Self {
        Self {
            memberships: LayerMask(memberships),
            filters: LayerMask(filters),
        }
    }

    /// Whether colliders with these layers and `other` may touch.
    pub const fn interacts_with(self, other: Self) -> bool {
        self.memberships.intersects(other.filters) && other.memberships.intersects(self.filters)
    }
}

impl Default for CollisionLayers {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Makes a collider a sensor (a trigger volume): it reports overlaps as collision events
/// (with [`CollisionEventsEnabled`](crate::events::CollisionEventsEnabled)) but never
/// pushes or is pushed. Works on static colliders and on kinematic and dynamic bodies (a
/// dynamic sensor falls through everything). A sensor never wakes a sleeping body, and a
/// body touching a sleeping sensor body does not wake it; two sensors don't report each
/// other.
#[derive(Component, Reflect, Clone, Copy, Debug, Default, PartialEq, Eq)]
#[reflect(Component)]
pub struct Sensor;

#[cfg(test)]
mod tests {
    use super::*;

    crate::physics_layers! {
        enum Layer { Ground, Player, Enemy }
    }

    #[test]
    fn each_must_be_in_the_others_filter() {
        let ground = CollisionLayers::new(Layer::Ground, LayerMask::ALL);
        let player = CollisionLayers::new(Layer::Player, [Layer::Ground, Layer::Enemy]);
        let ghost = CollisionLayers::new(Layer::Enemy, Layer::Ground);
        assert!(ground.interacts_with(player) && player.interacts_with(ground));
        // The ghost filters the player out; the player's filter alone does not decide.
        assert!(!player.interacts_with(ghost) && !ghost.interacts_with(player));
        assert!(ghost.interacts_with(ground));
        assert!(!CollisionLayers::NONE.interacts_with(CollisionLayers::ALL));
        assert_eq!(
            LayerMask::from([Layer::Ground, Layer::Enemy]),
            LayerMask(0b101)
        );
        assert!(LayerMask(0b111).contains(LayerMask::layer(2)));
        assert_eq!(!LayerMask::ALL, LayerMask::NONE);
    }

    #[test]
    fn the_default_touches_everything_that_filters_for_layer_0() {
        let d = CollisionLayers::default();
        assert!(d.interacts_with(CollisionLayers::ALL));
        assert!(d.interacts_with(d));
        assert!(!d.interacts_with(CollisionLayers::from_bits(1, 0b10)));
    }
}
