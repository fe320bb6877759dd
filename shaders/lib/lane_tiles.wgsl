// The pixel of a ray pass's invocation: its 8 x 8 workgroup's tile, and in it, each run of eight
// invocations (what lavapipe runs as the lanes of one SIMD vector, and a quarter of a hardware
// GPU's subgroup) on a 4 x 2 block rather than a row of 8: neighbouring rays traverse more of
// the same nodes, so the lanes' loops end closer together.
fn lane_tile_pixel(workgroup: vec3<u32>, local_index: u32) -> vec2<u32> {
    let lane = local_index & 7u;
    let run = local_index >> 3u;
    let x = (run & 1u) * 4u + (lane & 3u);
    let y = (run >> 1u) * 2u + (lane >> 2u);
    return workgroup.xy * 8u + vec2<u32>(x, y);
}
