//! The counters side of the cost-of-an-edit benchmark (`examples/edit_cost.rs`, whose `measure`
//! this runs), on `builtin:instances?n=1000` with 40 moves (the timing is the example's, in
//! release, not a test's):
//!
//! - moving one instance writes only the instance record (in the instance buffer and in the
//!   traversal's texel array), TLAS nodes and the per-instance extras (the previous transform):
//!   never vertices, indices, BLAS nodes or triangles, materials or lights; exactly one instance
//!   record in each copy and at most one extras record per move, and under 5% of the TLAS's
//!   bytes;
//! - the BVH re-inserts (one TLAS update per move): no BLAS is built;
//! - a material colour edit writes one material record and nothing else;
//! - a run without edits writes nothing.

mod common;

#[path = "../examples/edit_cost.rs"]
mod edit_cost;

use chiaro_bvh::{GpuInstance, TlasNode};
use chiaro_gpu::gpu_scene::GpuInstanceExtra;

#[test]
fn an_edit_uploads_what_changed_only() {
    let Some(gpu) = common::gpu() else { return };
    let edits = 40;
    let cost = edit_cost::measure(&gpu, 1000, edits).unwrap();
    assert_eq!(cost.instances, 1001, "1000 spheres and the ground");
    assert_eq!(cost.move_uploads.len(), edits);

    let allowed = [
        "scene instance extras",
        "scene instance texels",
        "scene instances",
        "scene tlas nodes",
    ];
    let buffers = cost.move_buffers();
    assert!(
        buffers.iter().all(|b| allowed.contains(b)),
        "moves wrote {buffers:?}"
    );
    let tlas_bytes = (cost.instances as usize * 2 - 1) * size_of::<TlasNode>();
    for (i, upload) in cost.move_uploads.iter().enumerate() {
        // The moved instance's record, for the shading passes and for the traversal.
        for copy in ["scene instances", "scene instance texels"] {
            assert_eq!(
                upload.bytes_of(copy),
                size_of::<GpuInstance>() as u64,
                "move {i}: {copy}: {upload:?}"
            );
        }
        assert!(
            upload.bytes_of("scene instance extras") <= size_of::<GpuInstanceExtra>() as u64,
            "move {i}: {upload:?}"
        );
        let tlas = upload.bytes_of("scene tlas nodes");
        assert!(
            tlas > 0 && tlas * 20 < tlas_bytes as u64,
            "move {i}: {tlas} of {tlas_bytes} TLAS bytes"
        );
        assert_eq!(upload.allocations, 0, "move {i}: {upload:?}");
    }
    let (before, after) = (&cost.bvh_before, &cost.bvh_after);
    assert_eq!(after.blas_builds, before.blas_builds, "no BLAS built");
    assert_eq!(
        after.tlas_updates - before.tlas_updates,
        edits as u64,
        "one TLAS update per move"
    );

    assert_eq!(
        cost.material_upload.written(),
        ["scene materials"],
        "{:?}",
        cost.material_upload
    );
    assert_eq!(cost.material_records(), 1);
    assert_eq!(cost.idle_upload.bytes, 0, "{:?}", cost.idle_upload);
    assert_eq!(cost.idle_upload.writes, 0);
}
