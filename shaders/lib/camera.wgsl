// The camera parameters (chiaro_gpu::camera::GpuCamera) and primary rays built as
// chiaro_reference's CameraRays builds them (glTF pinhole or orthographic camera).

struct GpuCamera {
    view_proj: mat4x4<f32>,
    previous_view_proj: mat4x4<f32>,
    unjittered_view_proj: mat4x4<f32>,
    origin: vec3<f32>,
    orthographic: u32,
    right: vec3<f32>,
    width: f32,
    up: vec3<f32>,
    height: f32,
    forward: vec3<f32>,
    near: f32,
    jitter: vec2<f32>,
    frame_seed: u32,
    pad1: u32,
}

// Origin (xyz) and unit direction of the primary ray through the point `pixel` of the image
// (pixel units, row 0 at the top).
struct CameraRay {
    origin: vec3<f32>,
    direction: vec3<f32>,
}

fn camera_ray(camera: GpuCamera, pixel: vec2<f32>) -> CameraRay {
    let ndc = vec2<f32>(2.0 * pixel.x / camera.width - 1.0, 1.0 - 2.0 * pixel.y / camera.height);
    if camera.orthographic != 0u {
        return CameraRay(camera.origin + camera.right * ndc.x + camera.up * ndc.y, camera.forward);
    }
    let d = camera.forward + camera.right * ndc.x + camera.up * ndc.y;
    return CameraRay(camera.origin, normalize(d));
}
