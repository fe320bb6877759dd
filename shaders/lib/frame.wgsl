// An orthonormal shading frame around a unit normal: Duff, Burgess, Christensen, Hery, Kensler,
// Liani and Villemin, 2017, "Building an Orthonormal Basis, Revisited" (JCGT 6(1)), listing 3.
//
// Mirrors chiaro_shading::frame::Frame: local x = tangent, y = bitangent, z = normal.

struct Frame {
    tangent: vec3<f32>,
    bitangent: vec3<f32>,
    normal: vec3<f32>,
}

// The frame around the unit normal `n`; the sign is +1 for n.z >= 0 (so -0 counts as +).
fn frame_from_normal(n: vec3<f32>) -> Frame {
    let sign = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    var f: Frame;
    f.tangent = vec3<f32>(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    f.bitangent = vec3<f32>(b, sign + n.y * n.y * a, -n.y);
    f.normal = n;
    return f;
}

// The world direction `v` in local coordinates.
fn frame_to_local(f: Frame, v: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(v, f.tangent), dot(v, f.bitangent), dot(v, f.normal));
}

// The local direction `v` in world coordinates.
fn frame_to_world(f: Frame, v: vec3<f32>) -> vec3<f32> {
    return f.tangent * v.x + f.bitangent * v.y + f.normal * v.z;
}
