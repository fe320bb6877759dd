// The material extensions' textures (chiaro_scene::LayerTextures) on a shading point's BRDF
// parameters, as chiaro_reference's surface_at applies them: each multiplies its factor, read
// in the channel its extension names. Without FEATURE_LAYER_TEXTURES nothing is read.

#import lib/scene_bindings.wgsl
#import lib/textures.wgsl
#import lib/features.wgsl
#import lib/brdf.wgsl

// `params` (built from `material`'s factors) with the material's extension textures applied
// at the UVs `uvs` of a mesh with flags `mesh_flags`.
fn layer_textured(params: SurfaceParams, material: GpuMaterial, uvs: vec4<f32>,
    mesh_flags: u32) -> SurfaceParams {
    if !FEATURE_LAYER_TEXTURES {
        return params;
    }
    let one = vec4<f32>(1.0);
    var p = params;
    p.specular *= texture_sample_slot(material.specular_texture, uvs, mesh_flags, one).w;
    p.specular_color *= texture_sample_slot(material.specular_color_texture, uvs, mesh_flags,
        one).xyz;
    p.clearcoat *= texture_sample_slot(material.clearcoat_texture, uvs, mesh_flags, one).x;
    p.clearcoat_roughness *= texture_sample_slot(material.clearcoat_roughness_texture, uvs,
        mesh_flags, one).y;
    p.transmission *= texture_sample_slot(material.transmission_texture, uvs, mesh_flags, one).x;
    p.sheen_color *= texture_sample_slot(material.sheen_color_texture, uvs, mesh_flags, one).xyz;
    p.sheen_roughness *= texture_sample_slot(material.sheen_roughness_texture, uvs, mesh_flags,
        one).w;
    return p;
}
