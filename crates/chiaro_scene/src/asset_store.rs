//! The store behind [`crate::Meshes`], [`crate::Materials`] and [`crate::Textures`]: each asset
//! kept once, addressed by a small typed id that instances and materials refer to.

use std::fmt;
use std::marker::PhantomData;

use bevy_ecs::prelude::*;

/// A typed index into an [`AssetStore`].
pub trait AssetId: Copy + Send + Sync + 'static {
    /// The id of the asset at `index`.
    fn from_index(index: u32) -> Self;
    /// The index this id stands for.
    fn index(self) -> usize;
}

/// Assets of type `T` addressed by ids of type `I`, in the order they were added.
#[derive(Resource)]
pub struct AssetStore<I: AssetId, T: Send + Sync + 'static> {
    items: Vec<T>,
    id: PhantomData<I>,
}

impl<I: AssetId, T: Send + Sync + 'static> Default for AssetStore<I, T> {
    fn default() -> Self {
        Self {
            items: Vec::new(),
            id: PhantomData,
        }
    }
}

impl<I: AssetId, T: Send + Sync + fmt::Debug + 'static> fmt::Debug for AssetStore<I, T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(&self.items).finish()
    }
}

impl<I: AssetId, T: Send + Sync + 'static> AssetStore<I, T> {
    /// Adds an asset and returns its id.
    pub fn add(&mut self, item: T) -> I {
        self.items.push(item);
        I::from_index(self.items.len() as u32 - 1)
    }

    /// The asset with this id, if any.
    pub fn get(&self, id: I) -> Option<&T> {
        self.items.get(id.index())
    }

    /// The asset with this id for editing, if any.
    pub fn get_mut(&mut self, id: I) -> Option<&mut T> {
        self.items.get_mut(id.index())
    }

    /// Every asset with its id.
    pub fn iter(&self) -> impl Iterator<Item = (I, &T)> {
        self.items
            .iter()
            .enumerate()
            .map(|(i, item)| (I::from_index(i as u32), item))
    }

    /// Number of assets.
    pub fn len(&self) -> usize {
        self.items.len()
    }

    /// True when there are none.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }
}
