//! glTF mesh primitives to raw [`MeshData`]: attributes (positions, normals, tangents, two UV
//! sets, COLOR_0) read through the checked accessor reader, strips and fans turned into triangle lists. Points and lines are not surfaces: they
//! are skipped, and the caller reports it.

use glam::{Vec2, Vec3, Vec4};
use gltf::mesh::{Mode, Semantic};

use crate::gltf::accessor::{AccessorReader, Formats};
use crate::mesh_repair::MeshData;
use crate::morph::MorphTarget;

/// What a primitive turned into.
pub(crate) enum Converted {
    /// Triangles to validate.
    Triangles(MeshData),
    /// Nothing to draw, and why (points, lines, no positions).
    Skipped(String),
}

/// Triangle-list indices for a strip of `n` vertices given by `strip`, keeping every triangle's
/// winding the same.
fn strip_to_list(strip: &[u32]) -> Vec<u32> {
    (0..strip.len().saturating_sub(2))
        .flat_map(|i| {
            if i % 2 == 0 {
                [strip[i], strip[i + 1], strip[i + 2]]
            } else {
                [strip[i + 1], strip[i], strip[i + 2]]
            }
        })
        .collect()
}

/// Triangle-list indices for a fan: (i + 1, i + 2, 0), as the glTF spec orders them.
fn fan_to_list(fan: &[u32]) -> Vec<u32> {
    (0..fan.len().saturating_sub(2))
        .flat_map(|i| [fan[i + 1], fan[i + 2], fan[0]])
        .collect()
}

/// Reads one primitive. `tangent_uv_set` is the UV set of the material's normal map, if any.
pub(crate) fn convert_primitive(
    reader: &AccessorReader,
    primitive: &gltf::Primitive,
    tangent_uv_set: Option<usize>,
) -> Result<Converted, String> {
    let mode = primitive.mode();
    if !matches!(
        mode,
        Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
    ) {
        return Ok(Converted::Skipped(format!(
            "{mode:?} primitives are not surfaces"
        )));
    }
    let Some(positions) = primitive.get(&Semantic::Positions) else {
        return Ok(Converted::Skipped("it has no POSITION attribute".into()));
    };
    let positions: Vec<Vec3> = reader
        .read_f32::<3>(&positions, Formats::Float)?
        .into_iter()
        .map(Vec3::from)
        .collect();
    let normals = match primitive.get(&Semantic::Normals) {
        Some(a) => Some(
            reader
                .read_f32::<3>(&a, Formats::Float)?
                .into_iter()
                .map(Vec3::from)
                .collect(),
        ),
        None => None,
    };
    let tangents = match primitive.get(&Semantic::Tangents) {
        Some(a) => Some(
            reader
                .read_f32::<4>(&a, Formats::Float)?
                .into_iter()
                .map(Vec4::from)
                .collect(),
        ),
        None => None,
    };
    let mut uvs: [Option<Vec<Vec2>>; 2] = [None, None];
    for (set, uv) in uvs.iter_mut().enumerate() {
        if let Some(a) = primitive.get(&Semantic::TexCoords(set as u32)) {
            *uv = Some(
                reader
                    .read_f32::<2>(&a, Formats::FloatOrUnorm)?
                    .into_iter()
                    .map(Vec2::from)
                    .collect(),
            );
        }
    }
    let colors = match primitive.get(&Semantic::Colors(0)) {
        Some(a) => Some(reader.read_color(&a)?.into_iter().map(Vec4::from).collect()),
        None => None,
    };
    let indices = match primitive.indices() {
        Some(a) => reader.read_indices(&a)?,
        None => (0..positions.len() as u32).collect(),
    };
    let indices = match mode {
        Mode::TriangleStrip => strip_to_list(&indices),
        Mode::TriangleFan => fan_to_list(&indices),
        _ => indices,
    };
    Ok(Converted::Triangles(MeshData {
        positions,
        normals,
        tangents,
        uvs,
        colors,
        indices: Some(indices),
        tangent_uv_set,
    }))
}

/// The morph targets of `primitive` (none when it has none), each displacement accessor of
/// `vertices` elements (floats, or normalized integers).
pub(crate) fn morph_targets(
    reader: &AccessorReader,
    primitive: &gltf::Primitive,
    vertices: usize,
) -> Result<Vec<MorphTarget>, String> {
    let read = |accessor: Option<gltf::Accessor>, what: &str, t: usize| {
        accessor
            .map(|a| {
                let d: Vec<Vec3> = reader
                    .read_f32::<3>(&a, Formats::FloatOrNorm)
                    .map_err(|why| format!("morph target {t} {what}: {why}"))?
                    .into_iter()
                    .map(Vec3::from)
                    .collect();
                if d.len() != vertices {
                    return Err(format!(
                        "morph target {t} {what} has {} elements but there are {vertices} positions",
                        d.len()
                    ));
                }
                Ok(d)
            })
            .transpose()
    };
    primitive
        .morph_targets()
        .enumerate()
        .map(|(t, target)| {
            Ok(MorphTarget {
                positions: read(target.positions(), "POSITION", t)?,
                normals: read(target.normals(), "NORMAL", t)?,
                tangents: read(target.tangents(), "TANGENT", t)?,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_alternate_winding() {
        assert_eq!(
            strip_to_list(&[0, 1, 2, 3, 4]),
            vec![0, 1, 2, 2, 1, 3, 2, 3, 4]
        );
        assert!(strip_to_list(&[0, 1]).is_empty());
    }

    #[test]
    fn fans_share_the_first_vertex() {
        assert_eq!(fan_to_list(&[0, 1, 2, 3]), vec![1, 2, 0, 2, 3, 0]);
    }
}
