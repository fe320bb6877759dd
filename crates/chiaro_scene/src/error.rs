//! Errors and repair reports of scene loading. Every error names its source (a file path or a
//! `builtin:` name), the element at fault when there is one (mesh, accessor, node, ...), and the
//! fault itself.

use std::fmt;

use bevy_ecs::prelude::*;

use crate::mesh_repair::MeshFault;

/// A scene, file or environment that could not be loaded.
#[derive(Debug, thiserror::Error)]
pub struct SceneError {
    /// The file path or `builtin:` name.
    pub source_name: String,
    /// The element at fault, e.g. `mesh 2 ("Cube") primitive 0`, or `None` for the whole source.
    pub element: Option<String>,
    /// What is wrong.
    pub fault: Fault,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.element {
            Some(element) => write!(f, "{}: {element}: {}", self.source_name, self.fault),
            None => write!(f, "{}: {}", self.source_name, self.fault),
        }
    }
}

/// What is wrong with a scene source.
#[derive(Debug, thiserror::Error)]
pub enum Fault {
    /// The file could not be read.
    #[error("cannot read it: {0}")]
    Io(#[from] std::io::Error),
    /// The file is too large to be read whole.
    #[error("it is {size} bytes, more than the {limit} bytes chiaro reads")]
    TooLarge {
        /// Its size.
        size: u64,
        /// The limit.
        limit: u64,
    },
    /// JSON, GLB container or glTF schema errors, as the gltf crate reports them.
    #[error("not valid glTF: {0}")]
    Gltf(String),
    /// A URI the file-access rule refuses, or one that cannot be resolved.
    #[error("{0}")]
    Uri(String),
    /// A buffer's data is shorter than its declared byteLength.
    #[error("declares {declared} bytes but its data holds {actual}")]
    BufferTooShort {
        /// Declared byteLength.
        declared: u64,
        /// Bytes actually present.
        actual: u64,
    },
    /// An accessor, buffer view or sparse block that cannot be read safely.
    #[error("{0}")]
    Accessor(String),
    /// Mesh data refused by validation.
    #[error(transparent)]
    Mesh(#[from] MeshFault),
    /// The node graph is not a forest.
    #[error("{0}")]
    Hierarchy(String),
    /// A transform with a NaN or infinite entry.
    #[error("its transform is not finite: {0}")]
    NonFiniteTransform(String),
    /// A camera whose parameters define no projection.
    #[error("{0}")]
    Camera(String),
    /// A light with unusable parameters.
    #[error("{0}")]
    Light(String),
    /// A skin, or a skinned primitive's joints and weights, that cannot pose the mesh.
    #[error("{0}")]
    Skin(String),
    /// An image that could not be decoded or is out of bounds.
    #[error("{0}")]
    Image(String),
    /// A file type chiaro does not read.
    #[error("unsupported file type (expected {0})")]
    UnsupportedFormat(&'static str),
    /// An unknown built-in scene or a bad parameter for one.
    #[error("{0}")]
    Builtin(String),
}

impl SceneError {
    /// An error about the whole source.
    pub fn whole(source_name: impl Into<String>, fault: impl Into<Fault>) -> Self {
        Self {
            source_name: source_name.into(),
            element: None,
            fault: fault.into(),
        }
    }

    /// An error about one element of the source.
    pub fn at(
        source_name: impl Into<String>,
        element: impl Into<String>,
        fault: impl Into<Fault>,
    ) -> Self {
        Self {
            source_name: source_name.into(),
            element: Some(element.into()),
            fault: fault.into(),
        }
    }
}

/// One repair made while loading: what was dropped or fixed, where, and how many.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Repair {
    /// The element repaired, e.g. `mesh 0 ("Floor") primitive 1`.
    pub element: String,
    /// What was done.
    pub action: String,
}

impl fmt::Display for Repair {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.element, self.action)
    }
}

/// What loading repaired, per source. Each repair is also logged as a warning.
#[derive(Resource, Clone, Debug, Default)]
pub struct ImportReport {
    /// Each source loaded into the world, with its repairs.
    pub sources: Vec<(String, Vec<Repair>)>,
}

impl ImportReport {
    /// Every repair with its source.
    pub fn repairs(&self) -> impl Iterator<Item = (&str, &Repair)> {
        self.sources
            .iter()
            .flat_map(|(source, repairs)| repairs.iter().map(move |r| (source.as_str(), r)))
    }
}
