//! chiaro's ray-tracing acceleration structures: a bottom-level BVH (BLAS) per mesh, shared by
//! every instance of it, and a top-level BVH (TLAS) over the instances, kept in step with a
//! `bevy_ecs` World; CPU traversal; flat GPU-ready buffers.
//!
//! - **BLAS** ([`Blas`]): obvhs's PLOC builder and reinsertion make a binary BVH, obvhs turns it
//!   into a compressed wide BVH (CWBVH: eight children per 80-byte [`CwBvhNode`]), and chiaro
//!   traverses it with its own conservative child-box test ([`wide`]). obvhs's own CWBVH
//!   traversal is not robust (it clamps `1/d` to `1/f32::EPSILON` and every box entry to
//!   `t >= 1e-4`: 80% of axis-parallel rays from 1e5 units away lose their hit) and obvhs's BVH2
//!   traversal is slower. Measured on one core, incoherent rays, 327,680 triangles
//!   (`examples/bvh_bench.rs`, same watertight triangle test everywhere): chiaro's robust CWBVH
//!   traversal 4.27 Mrays/s, obvhs's CWBVH 3.95, obvhs's BVH2 2.85; an earlier robust BVH2
//!   traversal of chiaro's reached 0.63x obvhs's CWBVH in the same comparison and was dropped.
//! - **TLAS** ([`SceneBvh`]): chiaro's binned SAH builder (obvhs's builder is quadratic on
//!   coincident instances); a moved instance is re-inserted where it now belongs (many moved at
//!   once: one refit pass), and the tree is rebuilt when instances come or
//!   go. Rays enter each instance's object space through its inverse matrix, direction not
//!   normalised so `t` is shared by all instances.
//! - **Exact answers**: every triangle test is the watertight test of Woop, Benthin and Wald
//!   (2013) ([`watertight`]); box tests are conservative (Ize 2013) and padded so that traversal
//!   never culls a triangle the watertight test would report ([`slab`]): closest-hit and any-hit
//!   agree with brute force ([`SceneBvh::closest_hit_brute_force`]).
//! - **Hardened input**: invalid rays get no hit ([`Ray::is_valid`]); instances with
//!   non-finite, singular or ill-conditioned matrices or huge bounds are left out with a warning
//!   ([`InstanceRejection`]); obvhs never sees input it panics or stalls on.
//! - **ECS**: [`update_scene_bvh`] builds each mesh's BLAS once and touches the TLAS only when
//!   instances change ([`BvhStats`] counts the work); [`add_bvh_systems`] schedules it after
//!   [`chiaro_scene::propagate_transforms`].
//! - **Still scenes** ([`FlatBvh`]): every instance's triangles in world space under one BVH,
//!   for a renderer that traces a scene that will not change; the same hits without the TLAS.
//! - **Secondary rays**: [`offset_ray_origin`] (Wächter and Binder 2019).
//! - **GPU**: [`GpuBvhBuffers`].
//!
//! ```
//! use bevy_ecs::prelude::*;
//! use chiaro_bvh::{BvhStats, Ray, SceneBvh, add_bvh_systems, offset_ray_origin};
//! use glam::Vec3;
//!
//! let mut world = World::new();
//! chiaro_scene::load_scene(&mut world, "builtin:cornell").unwrap();
//!
//! // One-off: build and trace.
//! let bvh = SceneBvh::build(&mut world);
//! let center = bvh.bounds().center();
//! let hit = bvh.closest_hit(&Ray::new(center, Vec3::NEG_Y)).expect("the floor");
//! let floor = bvh.hit_point(&hit).unwrap();
//! assert!(floor.y < center.y);
//!
//! // A shadow ray back up, from just above the floor, to the centre: nothing in between.
//! let up = bvh.geometric_normal(&hit).unwrap();
//! let up = if up.dot(Vec3::Y) > 0.0 { up } else { -up };
//! let origin = offset_ray_origin(floor, up);
//! let shadow = Ray::new(origin, center - origin).with_interval(0.0, 1.0);
//! assert!(!bvh.any_hit(&shadow));
//!
//! // Every frame: keep it current, doing only what changed.
//! let mut schedule = Schedule::default();
//! add_bvh_systems(&mut schedule);
//! schedule.run(&mut world);
//! schedule.run(&mut world);
//! let stats = world.resource::<BvhStats>();
//! assert_eq!((stats.tlas_builds, stats.tlas_updates), (1, 0), "nothing changed the second time");
//! assert!(world.resource::<SceneBvh>().closest_hit(&Ray::new(center, Vec3::NEG_Y)).is_some());
//! ```

#![warn(missing_docs)]

pub mod binned;
pub mod blas;
mod brute_force;
pub mod flat;
pub mod gpu;
pub mod instance;
pub mod layout;
mod object_ray;
pub mod offset;
mod query;
pub mod ray;
pub mod scene_bvh;
pub mod slab;
pub mod system;
pub mod tlas;
mod update;
pub mod watertight;
pub mod wide;

pub use blas::{Blas, BlasBuilder};
pub use flat::{FLAT_MAX_TRIANGLES, FlatBvh};
pub use gpu::{GpuBvhBuffers, GpuInstance};
pub use instance::{InstanceRecord, InstanceRejection};
pub use layout::{BvhTriangle, TLAS_LEAF_BIT, TlasNode};
pub use obvhs::cwbvh::node::CwBvhNode;
pub use offset::offset_ray_origin;
pub use ray::{Hit, Ray};
pub use scene_bvh::SceneBvh;
pub use system::{BvhStats, add_bvh_systems, update_scene_bvh};
