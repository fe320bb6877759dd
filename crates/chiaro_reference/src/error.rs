//! Errors of the reference renderer.

/// Why a render could not run or be written.
#[derive(Debug, thiserror::Error)]
pub enum ReferenceError {
    /// The World has no active camera entity with a camera and a transform.
    #[error("the scene has no active camera")]
    NoCamera,
    /// The World holds no scene (no meshes, materials or textures resources).
    #[error("the world holds no scene: load one first")]
    NoScene,
    /// Bad render settings.
    #[error("invalid settings: {0}")]
    Settings(String),
    /// The image could not be written.
    #[error("cannot write {path}: {message}")]
    Write {
        /// The output path.
        path: String,
        /// What went wrong.
        message: String,
    },
}
