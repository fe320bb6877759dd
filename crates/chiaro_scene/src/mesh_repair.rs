//! Validation and repair of raw mesh data, shared by the glTF importer and the built-in scenes.
//!
//! Refused (a [`MeshFault`]): attribute arrays of the wrong length, an index past the last
//! vertex, more vertices than a u32 can index, no triangle left after repair.
//! Repaired, with one line per kind of repair saying how many were affected:
//! - an index count that is not a multiple of three: the trailing indices are dropped;
//! - triangles with a non-finite position, or a coordinate beyond [`MAX_COORDINATE`], are dropped;
//! - degenerate triangles are dropped: a repeated index, or a cross product below
//!   [`DEGENERATE_RELATIVE_AREA`] times the longest edge squared (zero area, collinear corners);
//! - missing normals become flat normals (each triangle gets its own three vertices, as glTF
//!   requires); non-finite or zero-length normals are replaced by the area-weighted normal of the
//!   triangles around the vertex; other normals are normalised;
//! - non-finite UVs become (0, 0);
//! - non-finite colour components become 1 (white, opaque: the colour then changes nothing),
//!   components outside [0, 1] are clamped to it;
//! - tangents with a non-finite or zero xyz are regenerated with MikkTSpace, as are missing ones
//!   when [`MeshData::tangent_uv_set`] asks for them.

use glam::{DVec3, Vec2, Vec3, Vec4};

use crate::mesh::Mesh;
use crate::tangents::generate_tangents;

/// Largest absolute coordinate accepted; beyond it a triangle is dropped (BVH builders and
/// single-precision ray tests break down well before f32's range ends).
pub const MAX_COORDINATE: f32 = 1.0e18;

/// A triangle whose doubled area is below this times its longest edge squared is degenerate.
pub const DEGENERATE_RELATIVE_AREA: f64 = 1.0e-10;

/// Raw, unvalidated mesh data, as read from a file or built in code.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshData {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Vertex normals; `None` gives flat normals.
    pub normals: Option<Vec<Vec3>>,
    /// Vertex tangents (xyz, w = bitangent sign).
    pub tangents: Option<Vec<Vec4>>,
    /// UV sets 0 and 1.
    pub uvs: [Option<Vec<Vec2>>; 2],
    /// Linear RGBA vertex colours (alpha 1 for RGB data).
    pub colors: Option<Vec<Vec4>>,
    /// Triangle list indices; `None` means vertices 0, 1, 2, ... in order.
    pub indices: Option<Vec<u32>>,
    /// When set, tangents are required (a normal map uses this UV set): generated if missing.
    pub tangent_uv_set: Option<usize>,
}

/// Why mesh data was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshFault {
    /// An attribute array's length differs from the position count.
    #[error("{attribute} has {len} elements but there are {vertex_count} positions")]
    AttributeLength {
        /// The attribute.
        attribute: &'static str,
        /// Its length.
        len: usize,
        /// The position count.
        vertex_count: usize,
    },
    /// An index refers past the last vertex.
    #[error("index {index} (at position {position}) is past the end of {vertex_count} vertices")]
    IndexOutOfRange {
        /// The index value.
        index: u32,
        /// Where it is in the index list.
        position: usize,
        /// The vertex count.
        vertex_count: usize,
    },
    /// More vertices than 32-bit indices reach.
    #[error("{0} vertices is more than 32-bit indices can address")]
    TooManyVertices(usize),
    /// Nothing is left to draw.
    #[error("no triangle is left: {0}")]
    NoTriangles(String),
}

pub(crate) fn repair_mesh(name: String, data: MeshData) -> Result<(Mesh, Vec<String>), MeshFault> {
    let vertex_count = data.positions.len();
    if u32::try_from(vertex_count).is_err() {
        return Err(MeshFault::TooManyVertices(vertex_count));
    }
    check_length("normals", data.normals.as_ref().map(Vec::len), vertex_count)?;
    check_length(
        "tangents",
        data.tangents.as_ref().map(Vec::len),
        vertex_count,
    )?;
    check_length("uv set 0", data.uvs[0].as_ref().map(Vec::len), vertex_count)?;
    check_length("uv set 1", data.uvs[1].as_ref().map(Vec::len), vertex_count)?;
    check_length("colors", data.colors.as_ref().map(Vec::len), vertex_count)?;

    let mut repairs = Vec::new();
    let mut indices = data
        .indices
        .unwrap_or_else(|| (0..vertex_count as u32).collect());
    if let Some((position, &index)) = indices
        .iter()
        .enumerate()
        .find(|&(_, &i)| i as usize >= vertex_count)
    {
        return Err(MeshFault::IndexOutOfRange {
            index,
            position,
            vertex_count,
        });
    }
    let trailing = indices.len() % 3;
    if trailing != 0 {
        indices.truncate(indices.len() - trailing);
        repairs.push(format!(
            "dropped {trailing} trailing indices (count not a multiple of 3)"
        ));
    }

    let (indices, dropped) = drop_bad_triangles(&data.positions, &indices);
    let total = indices.len() / 3 + dropped.total();
    dropped.describe(&mut repairs);
    if indices.is_empty() {
        return Err(MeshFault::NoTriangles(format!(
            "all {total} triangles were dropped{}",
            if repairs.is_empty() {
                String::new()
            } else {
                format!(" ({})", repairs.join("; "))
            }
        )));
    }

    let mut mesh = Mesh {
        name,
        positions: data.positions,
        normals: Vec::new(),
        tangents: data.tangents,
        uvs: data.uvs,
        colors: data.colors,
        indices,
    };
    for (set, uv) in mesh.uvs.iter_mut().enumerate() {
        let fixed = uv
            .iter_mut()
            .flatten()
            .filter(|t| !t.is_finite())
            .fold(0, |n, t| {
                *t = Vec2::ZERO;
                n + 1
            });
        if fixed > 0 {
            repairs.push(format!("set {fixed} non-finite UVs of set {set} to (0, 0)"));
        }
    }
    repair_colors(&mut mesh, &mut repairs);
    match data.normals {
        Some(normals) => repair_normals(&mut mesh, normals, &mut repairs),
        None => make_flat(&mut mesh),
    }
    repair_tangents(&mut mesh, data.tangent_uv_set, &mut repairs);
    Ok((mesh, repairs))
}

fn check_length(
    attribute: &'static str,
    len: Option<usize>,
    vertex_count: usize,
) -> Result<(), MeshFault> {
    match len {
        Some(len) if len != vertex_count => Err(MeshFault::AttributeLength {
            attribute,
            len,
            vertex_count,
        }),
        _ => Ok(()),
    }
}

/// Counts of triangles dropped, by reason.
#[derive(Default)]
struct Dropped {
    non_finite: usize,
    out_of_range: usize,
    repeated_index: usize,
    zero_area: usize,
}

impl Dropped {
    fn total(&self) -> usize {
        self.non_finite + self.out_of_range + self.repeated_index + self.zero_area
    }

    fn describe(&self, repairs: &mut Vec<String>) {
        let reasons = [
            (self.non_finite, "a non-finite position"),
            (self.out_of_range, "a coordinate beyond 1e18"),
            (self.repeated_index, "a repeated index (degenerate)"),
            (
                self.zero_area,
                "zero area (collinear or coincident corners)",
            ),
        ];
        for (count, reason) in reasons {
            if count > 0 {
                repairs.push(format!("dropped {count} triangles with {reason}"));
            }
        }
    }
}

fn drop_bad_triangles(positions: &[Vec3], indices: &[u32]) -> (Vec<u32>, Dropped) {
    let mut dropped = Dropped::default();
    let mut kept = Vec::with_capacity(indices.len());
    for tri in indices.chunks_exact(3) {
        let p = [0, 1, 2].map(|k| positions[tri[k] as usize]);
        if p.iter().any(|v| !v.is_finite()) {
            dropped.non_finite += 1;
        } else if p.iter().any(|v| v.abs().max_element() > MAX_COORDINATE) {
            dropped.out_of_range += 1;
        } else if tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] {
            dropped.repeated_index += 1;
        } else if is_zero_area(p) {
            dropped.zero_area += 1;
        } else {
            kept.extend_from_slice(tri);
        }
    }
    (kept, dropped)
}

fn is_zero_area(p: [Vec3; 3]) -> bool {
    let [a, b, c] = p.map(|v| v.as_dvec3());
    let (e0, e1, e2) = (b - a, c - a, c - b);
    let longest = e0
        .length_squared()
        .max(e1.length_squared())
        .max(e2.length_squared());
    let doubled_area = e0.cross(e1).length();
    doubled_area <= DEGENERATE_RELATIVE_AREA * longest || doubled_area == 0.0
}

/// Non-finite colour components become 1; the others are clamped to [0, 1].
fn repair_colors(mesh: &mut Mesh, repairs: &mut Vec<String>) {
    let (mut non_finite, mut clamped) = (0, 0);
    for c in mesh.colors.iter_mut().flatten() {
        if !c.is_finite() {
            non_finite += 1;
            *c = Vec4::select(c.is_finite_mask(), *c, Vec4::ONE);
        }
        let inside = c.clamp(Vec4::ZERO, Vec4::ONE);
        if inside != *c {
            clamped += 1;
            *c = inside;
        }
    }
    if non_finite > 0 {
        repairs.push(format!(
            "set the non-finite components of {non_finite} vertex colours to 1"
        ));
    }
    if clamped > 0 {
        repairs.push(format!("clamped {clamped} vertex colours to [0, 1]"));
    }
}

/// Area-weighted face normal sum at each vertex over the kept triangles.
fn accumulated_face_normals(mesh: &Mesh) -> Vec<DVec3> {
    let mut sum = vec![DVec3::ZERO; mesh.positions.len()];
    for tri in mesh.indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[tri[k] as usize].as_dvec3());
        let n = (b - a).cross(c - a);
        for &i in tri {
            sum[i as usize] += n;
        }
    }
    sum
}

fn repair_normals(mesh: &mut Mesh, mut normals: Vec<Vec3>, repairs: &mut Vec<String>) {
    let bad = |n: &Vec3| !n.is_finite() || n.length_squared() < 1e-24;
    let bad_count = normals.iter().filter(|n| bad(n)).count();
    if bad_count > 0 {
        let faces = accumulated_face_normals(mesh);
        for (n, face) in normals.iter_mut().zip(faces) {
            if bad(n) {
                *n = face.normalize_or(DVec3::Z).as_vec3();
            }
        }
        repairs.push(format!(
            "replaced {bad_count} non-finite or zero-length normals by the surrounding face normals"
        ));
    }
    for n in &mut normals {
        *n = n.normalize();
    }
    mesh.normals = normals;
}

/// Gives every triangle its own three vertices and its face normal.
fn make_flat(mesh: &mut Mesh) {
    let corners = std::mem::take(&mut mesh.indices);
    let pick = |values: &[Vec2]| corners.iter().map(|&i| values[i as usize]).collect();
    mesh.uvs = [
        mesh.uvs[0].as_deref().map(pick),
        mesh.uvs[1].as_deref().map(pick),
    ];
    mesh.tangents = mesh
        .tangents
        .as_deref()
        .map(|t| corners.iter().map(|&i| t[i as usize]).collect());
    mesh.colors = mesh
        .colors
        .as_deref()
        .map(|c| corners.iter().map(|&i| c[i as usize]).collect());
    let positions: Vec<Vec3> = corners
        .iter()
        .map(|&i| mesh.positions[i as usize])
        .collect();
    mesh.normals = positions
        .chunks_exact(3)
        .flat_map(|p| {
            let n = (p[1].as_dvec3() - p[0].as_dvec3())
                .cross(p[2].as_dvec3() - p[0].as_dvec3())
                .normalize()
                .as_vec3();
            [n; 3]
        })
        .collect();
    mesh.indices = (0..positions.len() as u32).collect();
    mesh.positions = positions;
}

fn repair_tangents(mesh: &mut Mesh, uv_set: Option<usize>, repairs: &mut Vec<String>) {
    let bad = |t: &Vec4| !t.is_finite() || t.truncate().length_squared() < 1e-24;
    let bad_count = mesh.tangents.iter().flatten().filter(|t| bad(t)).count();
    if bad_count > 0 {
        repairs.push(format!(
            "regenerated all tangents: {bad_count} were non-finite or zero-length"
        ));
        mesh.tangents = None;
    }
    if let Some(tangents) = &mut mesh.tangents {
        for t in tangents {
            let sign = if t.w < 0.0 { -1.0 } else { 1.0 };
            *t = t.truncate().normalize().extend(sign);
        }
        return;
    }
    let wanted = uv_set.or((bad_count > 0).then_some(0));
    if let Some(set) = wanted {
        if mesh.uv(set).is_some() {
            generate_tangents(mesh, set);
        } else {
            repairs.push(format!(
                "cannot generate tangents without UV set {set}: the normal map is ignored"
            ));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad() -> MeshData {
        MeshData {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
            normals: Some(vec![Vec3::Z; 4]),
            indices: Some(vec![0, 1, 2, 0, 2, 3]),
            ..Default::default()
        }
    }

    #[test]
    fn good_data_passes_unchanged() {
        let (mesh, repairs) = Mesh::new("quad", quad()).unwrap();
        assert!(repairs.is_empty(), "{repairs:?}");
        assert_eq!(mesh.triangle_count(), 2);
        assert_eq!(mesh.indices(), &[0, 1, 2, 0, 2, 3]);
    }

    #[test]
    fn index_past_the_end_is_refused() {
        let mut data = quad();
        data.indices = Some(vec![0, 1, 9]);
        let fault = Mesh::new("q", data).unwrap_err();
        assert_eq!(
            fault,
            MeshFault::IndexOutOfRange {
                index: 9,
                position: 2,
                vertex_count: 4
            }
        );
    }

    #[test]
    fn nan_vertex_drops_its_triangles() {
        let mut data = quad();
        data.positions[1] = Vec3::new(f32::NAN, 0.0, 0.0);
        let (mesh, repairs) = Mesh::new("q", data).unwrap();
        assert_eq!(mesh.indices(), &[0, 2, 3]);
        assert_eq!(
            repairs,
            vec!["dropped 1 triangles with a non-finite position"]
        );
    }

    #[test]
    fn degenerate_triangles_are_dropped_and_counted() {
        let mut data = quad();
        data.positions.push(Vec3::new(2.0, 0.0, 0.0));
        data.normals.as_mut().unwrap().push(Vec3::Z);
        // Collinear (0, 1, 4), repeated index (0, 0, 1), and the two good ones.
        data.indices = Some(vec![0, 1, 2, 0, 1, 4, 0, 0, 1, 0, 2, 3]);
        let (mesh, repairs) = Mesh::new("q", data).unwrap();
        assert_eq!(mesh.triangle_count(), 2);
        assert_eq!(repairs.len(), 2, "{repairs:?}");
        assert!(repairs[0].contains("1 triangles with a repeated index"));
        assert!(repairs[1].contains("1 triangles with zero area"));
    }

    #[test]
    fn all_degenerate_is_refused() {
        let data = MeshData {
            positions: vec![Vec3::ZERO; 3],
            ..Default::default()
        };
        assert!(matches!(
            Mesh::new("z", data),
            Err(MeshFault::NoTriangles(_))
        ));
    }

    #[test]
    fn missing_normals_become_flat() {
        let mut data = quad();
        data.normals = None;
        data.positions[2].z = 1.0; // fold the quad: two different face normals
        let (mesh, _) = Mesh::new("q", data).unwrap();
        assert_eq!(mesh.positions().len(), 6);
        let n = mesh.normals();
        assert!(n[0].abs_diff_eq(n[2], 0.0) && !n[0].abs_diff_eq(n[3], 1e-3));
        let expected = (Vec3::X).cross(Vec3::new(1.0, 1.0, 1.0)).normalize();
        assert!(n[0].abs_diff_eq(expected, 1e-6));
    }

    #[test]
    fn zero_and_nan_normals_are_replaced_by_face_normals() {
        let mut data = quad();
        let normals = data.normals.as_mut().unwrap();
        normals[0] = Vec3::ZERO;
        normals[1] = Vec3::splat(f32::NAN);
        normals[2] = Vec3::new(0.0, 0.0, 5.0);
        let (mesh, repairs) = Mesh::new("q", data).unwrap();
        assert!(mesh.normals().iter().all(|n| n.abs_diff_eq(Vec3::Z, 1e-6)));
        assert_eq!(repairs.len(), 1);
        assert!(repairs[0].starts_with("replaced 2 "));
    }

    #[test]
    fn non_finite_uvs_are_zeroed() {
        let mut data = quad();
        data.uvs[0] = Some(vec![Vec2::ONE, Vec2::NAN, Vec2::ONE, Vec2::INFINITY]);
        let (mesh, repairs) = Mesh::new("q", data).unwrap();
        assert_eq!(mesh.uv(0).unwrap()[1], Vec2::ZERO);
        assert_eq!(repairs, vec!["set 2 non-finite UVs of set 0 to (0, 0)"]);
    }

    #[test]
    fn bad_colours_are_repaired_and_flat_meshes_keep_them() {
        let mut data = quad();
        data.normals = None;
        data.colors = Some(vec![
            Vec4::new(0.25, 0.5, 0.75, 1.0),
            Vec4::new(f32::NAN, 0.5, f32::INFINITY, 0.5),
            Vec4::new(2.0, -1.0, 0.5, 1.0),
            Vec4::ONE,
        ]);
        let (mesh, repairs) = Mesh::new("q", data).unwrap();
        assert_eq!(
            repairs,
            vec![
                "set the non-finite components of 1 vertex colours to 1",
                "clamped 1 vertex colours to [0, 1]"
            ]
        );
        // Flat normals give each triangle its own corners: (0, 1, 2), (0, 2, 3).
        let colors = mesh.colors().unwrap();
        assert_eq!(colors.len(), 6);
        assert_eq!(colors[0], Vec4::new(0.25, 0.5, 0.75, 1.0));
        assert_eq!(colors[1], Vec4::new(1.0, 0.5, 1.0, 0.5));
        assert_eq!(colors[2], Vec4::new(1.0, 0.0, 0.5, 1.0));
        assert_eq!(colors[5], Vec4::ONE);
    }

    #[test]
    fn wrong_attribute_length_is_refused() {
        let mut data = quad();
        data.uvs[1] = Some(vec![Vec2::ZERO; 3]);
        assert!(matches!(
            Mesh::new("q", data),
            Err(MeshFault::AttributeLength {
                attribute: "uv set 1",
                len: 3,
                vertex_count: 4
            })
        ));
    }

    #[test]
    fn huge_coordinates_are_dropped() {
        let mut data = quad();
        data.positions[3] = Vec3::new(0.0, 1e30, 0.0);
        let (mesh, repairs) = Mesh::new("q", data).unwrap();
        assert_eq!(mesh.triangle_count(), 1);
        assert!(repairs[0].contains("beyond 1e18"));
    }
}
