//! The asset loader for `*.scene.ron` files. A malformed file fails to load with the
//! file, line and column in the error; whoever holds the last good scene keeps it.

use bevy::asset::io::Reader;
use bevy::asset::{AssetLoader, LoadContext};
use bevy::prelude::*;

use super::{SceneDesc, SceneError};

/// Loads `.scene.ron` files as [`SceneDesc`] assets, checked field by field.
#[derive(Default, TypePath)]
pub struct SceneLoader;

impl AssetLoader for SceneLoader {
    type Asset = SceneDesc;
    type Settings = ();
    type Error = SceneError;

    async fn load(
        &self,
        reader: &mut dyn Reader,
        _: &(),
        ctx: &mut LoadContext<'_>,
    ) -> Result<SceneDesc, SceneError> {
        let mut bytes = Vec::new();
        reader.read_to_end(&mut bytes).await?;
        let text = String::from_utf8_lossy(&bytes);
        SceneDesc::from_ron(&text, &ctx.path().to_string())
    }

    fn extensions(&self) -> &[&str] {
        &["scene.ron"]
    }
}
