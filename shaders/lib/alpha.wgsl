// The alpha hook bvh.wgsl's traversal calls, as chiaro_reference's stops_ray decides: a
// candidate hit on an alpha-masked material counts only where base colour alpha x texture
// alpha x vertex colour alpha reaches the cutoff (glTF 2.0, alpha mode MASK); on an
// alpha-blended material it counts with probability alpha, decided by the coverage number of
// the world ray and the triangle (alpha mode BLEND as stochastic coverage: coverage.wgsl).
// Shadow rays take the same test: a blended surface blocks one with probability alpha.

#import lib/generated.wgsl
#import lib/bvh_bindings.wgsl
#import lib/bvh.wgsl
#import lib/scene_bindings.wgsl
#import lib/base_color.wgsl
#import lib/coverage.wgsl
#import lib/features.wgsl

// The alpha there: factor x texture x vertex colour.
fn hit_alpha(mesh: u32, material: GpuMaterial, triangle: u32, barycentrics: vec2<f32>) -> f32 {
    let indices = scene_triangle_indices(mesh, triangle);
    return material_base_color(material, scene_meshes[mesh].flags,
        scene_uvs(indices, barycentrics), vertex_color(indices, barycentrics)).w;
}

fn hit_accepted(ray: Ray, instance: u32, triangle: u32, barycentrics: vec2<f32>) -> bool {
    if !FEATURE_ALPHA_MASKS && !FEATURE_ALPHA_BLEND {
        return true;
    }
    let record = bvh_load_instance_whole(instance);
    let material = scene_material(record.material);
    if FEATURE_ALPHA_MASKS && (material.flags & MATERIAL_ALPHA_MASK) != 0u {
        return hit_alpha(record.mesh, material, triangle, barycentrics) >= material.alpha_cutoff;
    }
    if FEATURE_ALPHA_BLEND && (material.flags & MATERIAL_ALPHA_BLEND) != 0u {
        let u = coverage_ray_number(ray.origin, ray.direction, instance, triangle);
        return coverage_stops(hit_alpha(record.mesh, material, triangle, barycentrics), u);
    }
    return true;
}

// The coverage a light sample on an instance's emitter is weighted by (chiaro_reference's
// emitter_coverage): alpha there on an alpha-blended material, else 1.
fn emitter_coverage(instance: u32, indices: vec3<u32>, b: vec2<f32>) -> f32 {
    if !FEATURE_ALPHA_BLEND {
        return 1.0;
    }
    let record = bvh_load_instance_whole(instance);
    let material = scene_material(record.material);
    if (material.flags & MATERIAL_ALPHA_BLEND) == 0u {
        return 1.0;
    }
    let base = material_base_color(material, scene_meshes[record.mesh].flags,
        scene_uvs(indices, b), vertex_color(indices, b));
    return clamp(base.w, 0.0, 1.0);
}
