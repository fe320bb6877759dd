//! Triangle meshes, validated on construction, and the shared [`Meshes`] store.

use glam::{Vec2, Vec3, Vec4};

use crate::asset_store::{AssetId, AssetStore};
use crate::bounds::Aabb;
use crate::mesh_repair::{MeshData, MeshFault, repair_mesh};

/// Index of a mesh in [`Meshes`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct MeshId(pub u32);

/// An indexed triangle mesh whose data is known good: every index is in range, every position,
/// normal, tangent, UV and colour is finite, normals are unit length, colours lie in [0, 1], no
/// triangle has zero area.
/// Built only through [`Mesh::new`], which repairs or refuses raw data.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    pub(crate) name: String,
    pub(crate) positions: Vec<Vec3>,
    pub(crate) normals: Vec<Vec3>,
    pub(crate) tangents: Option<Vec<Vec4>>,
    pub(crate) uvs: [Option<Vec<Vec2>>; 2],
    pub(crate) colors: Option<Vec<Vec4>>,
    pub(crate) indices: Vec<u32>,
}

impl Mesh {
    /// Validates and repairs `data`. Returns the mesh and one line per repair made (what was
    /// dropped or fixed, and how many), or the fault that makes the data unusable.
    pub fn new(name: impl Into<String>, data: MeshData) -> Result<(Self, Vec<String>), MeshFault> {
        repair_mesh(name.into(), data)
    }

    /// The mesh's name (from the file, or given by the builder).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Vertex positions, object space.
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// Unit vertex normals, one per position.
    pub fn normals(&self) -> &[Vec3] {
        &self.normals
    }

    /// Tangents (xyz unit, w = +-1 the bitangent sign), present when a normal map needs them.
    pub fn tangents(&self) -> Option<&[Vec4]> {
        self.tangents.as_deref()
    }

    /// UV set 0 or 1, when present.
    pub fn uv(&self, set: usize) -> Option<&[Vec2]> {
        self.uvs.get(set).and_then(|uv| uv.as_deref())
    }

    /// Linear RGBA vertex colours (glTF's COLOR_0, alpha 1 where the file gives RGB), when
    /// present: they multiply the material's base colour and alpha.
    pub fn colors(&self) -> Option<&[Vec4]> {
        self.colors.as_deref()
    }

    /// Triangle list indices, three per triangle.
    pub fn indices(&self) -> &[u32] {
        &self.indices
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Object-space bounds of the triangles: vertices no triangle uses (such as those of
    /// triangles import dropped for a non-finite position) do not count.
    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(self.indices.iter().map(|&i| self.positions[i as usize]))
    }
}

/// Every mesh of the scene, stored once however many instances use it.
pub type Meshes = AssetStore<MeshId, Mesh>;

impl AssetId for MeshId {
    fn from_index(index: u32) -> Self {
        Self(index)
    }

    fn index(self) -> usize {
        self.0 as usize
    }
}
