// The alpha-mask hook bvh.wgsl's traversal calls: a candidate hit on an alpha-masked material
// counts only where base colour alpha x texture alpha x vertex colour alpha reaches the cutoff (glTF 2.0, alpha mode
// MASK), as chiaro_reference's alpha_passes decides.

#import lib/generated.wgsl
#import lib/bvh_bindings.wgsl
#import lib/scene_bindings.wgsl
#import lib/base_color.wgsl
#import lib/features.wgsl

fn hit_accepted(instance: u32, triangle: u32, barycentrics: vec2<f32>) -> bool {
    if !FEATURE_ALPHA_MASKS {
        return true;
    }
    let record = bvh_load_instance_whole(instance);
    let material = scene_material(record.material);
    if (material.flags & MATERIAL_ALPHA_MASK) == 0u {
        return true;
    }
    let indices = scene_triangle_indices(record.mesh, triangle);
    let base = material_base_color(material, scene_meshes[record.mesh].flags,
        scene_uvs(indices, barycentrics), vertex_color(indices, barycentrics));
    return base.w >= material.alpha_cutoff;
}
