//! Local and world transforms, and the system that propagates them down the hierarchy.
//!
//! The hierarchy is bevy_ecs's own `ChildOf` / `Children` relationship. A [`Transform`] is relative
//! to the parent; [`GlobalTransform`] is the world matrix, written by [`propagate_transforms`]
//! only where something above it or on it changed, so `Changed<GlobalTransform>` tells a system
//! exactly which entities moved in the world, children of a moved parent included.

use bevy_ecs::hierarchy::{ChildOf, Children};
use bevy_ecs::prelude::*;
use glam::{Affine3A, Mat3, Mat4, Quat, Vec3};

/// Deepest hierarchy [`propagate_transforms`] follows; anything deeper is left unchanged and
/// logged, which also stops a (malformed) cyclic `ChildOf` graph.
pub const MAX_HIERARCHY_DEPTH: usize = 4096;

/// Position, orientation and scale relative to the parent entity (or the world for a root).
#[derive(Component, Clone, Copy, Debug, PartialEq)]
#[require(GlobalTransform)]
pub struct Transform {
    /// Translation, applied last.
    pub translation: Vec3,
    /// Rotation, a unit quaternion.
    pub rotation: Quat,
    /// Non-uniform scale, applied first.
    pub scale: Vec3,
}

impl Default for Transform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Transform {
    /// No translation, rotation or scale.
    pub const IDENTITY: Self = Self {
        translation: Vec3::ZERO,
        rotation: Quat::IDENTITY,
        scale: Vec3::ONE,
    };

    /// A pure translation.
    pub fn from_translation(translation: Vec3) -> Self {
        Self {
            translation,
            ..Self::IDENTITY
        }
    }

    /// Placed at `eye`, rotated so that its local -Z looks at `target` with +Y as close to `up`
    /// as possible (the glTF camera convention). When `up` is parallel to the view direction,
    /// any perpendicular up is used.
    pub fn looking_at(eye: Vec3, target: Vec3, up: Vec3) -> Self {
        let back = (eye - target).normalize_or(Vec3::Z);
        let right = up
            .cross(back)
            .try_normalize()
            .unwrap_or_else(|| back.any_orthonormal_vector());
        let true_up = back.cross(right);
        let rotation = Quat::from_mat3(&Mat3::from_cols(right, true_up, back));
        Self {
            translation: eye,
            rotation,
            scale: Vec3::ONE,
        }
    }

    /// This transform with `scale` replaced.
    pub fn with_scale(mut self, scale: Vec3) -> Self {
        self.scale = scale;
        self
    }

    /// This transform with `rotation` replaced.
    pub fn with_rotation(mut self, rotation: Quat) -> Self {
        self.rotation = rotation;
        self
    }

    /// The affine matrix: scale, then rotate, then translate.
    pub fn to_affine(&self) -> Affine3A {
        Affine3A::from_scale_rotation_translation(self.scale, self.rotation, self.translation)
    }
}

/// The world-space matrix of an entity, kept by [`propagate_transforms`]; read it, don't write it.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct GlobalTransform(pub Affine3A);

impl Default for GlobalTransform {
    fn default() -> Self {
        Self(Affine3A::IDENTITY)
    }
}

impl GlobalTransform {
    /// The world matrix as a `Mat4`.
    pub fn matrix(&self) -> Mat4 {
        Mat4::from(self.0)
    }

    /// World-space position of the local origin.
    pub fn translation(&self) -> Vec3 {
        self.0.translation.into()
    }

    /// Transforms a local point to world space.
    pub fn transform_point(&self, point: Vec3) -> Vec3 {
        self.0.transform_point3(point)
    }

    /// Transforms a local direction to world space (no translation; not normalised).
    pub fn transform_vector(&self, vector: Vec3) -> Vec3 {
        self.0.transform_vector3(vector)
    }
}

/// What [`propagate_transforms`] reads of each node: its transform, its parent link, its children.
type NodeData = (
    Ref<'static, Transform>,
    Option<Ref<'static, ChildOf>>,
    Option<&'static Children>,
);

/// Writes every [`GlobalTransform`] whose own [`Transform`], parent link, or any ancestor's
/// transform changed since the system last ran; leaves the others untouched so change detection
/// stays exact. Uses an explicit stack: deep hierarchies cannot overflow the call stack.
pub fn propagate_transforms(
    roots: Query<Entity, (With<Transform>, Without<ChildOf>)>,
    nodes: Query<NodeData>,
    mut globals: Query<&mut GlobalTransform>,
) {
    let mut stack: Vec<(Entity, Affine3A, bool, usize)> = roots
        .iter()
        .map(|root| (root, Affine3A::IDENTITY, false, 0))
        .collect();
    while let Some((entity, parent_world, parent_dirty, depth)) = stack.pop() {
        let Ok((local, child_of, children)) = nodes.get(entity) else {
            continue;
        };
        if depth > MAX_HIERARCHY_DEPTH {
            log::error!(
                "hierarchy deeper than {MAX_HIERARCHY_DEPTH} levels at {entity}: not followed"
            );
            continue;
        }
        let relinked = child_of.is_some_and(|c| c.is_changed());
        let dirty = parent_dirty || relinked || local.is_changed();
        let world = parent_world * local.to_affine();
        if dirty && let Ok(mut global) = globals.get_mut(entity) {
            global.set_if_neq(GlobalTransform(world));
        }
        for &child in children.into_iter().flatten() {
            stack.push((child, world, dirty, depth + 1));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn looking_at_points_minus_z_at_the_target() {
        let t = Transform::looking_at(Vec3::new(1.0, 2.0, 3.0), Vec3::ZERO, Vec3::Y);
        let forward = t.rotation * Vec3::NEG_Z;
        let expected = (Vec3::ZERO - Vec3::new(1.0, 2.0, 3.0)).normalize();
        assert!(forward.abs_diff_eq(expected, 1e-5), "{forward}");
        let up = t.rotation * Vec3::Y;
        assert!(up.y > 0.0);
    }

    #[test]
    fn affine_applies_scale_then_rotation_then_translation() {
        let t = Transform {
            translation: Vec3::X,
            rotation: Quat::from_rotation_z(std::f32::consts::FRAC_PI_2),
            scale: Vec3::splat(2.0),
        };
        let p = t.to_affine().transform_point3(Vec3::X);
        assert!(p.abs_diff_eq(Vec3::new(1.0, 2.0, 0.0), 1e-5), "{p}");
    }

    #[derive(Resource, Default)]
    struct Moved(Vec<Entity>);

    fn record_moved(query: Query<Entity, Changed<GlobalTransform>>, mut moved: ResMut<Moved>) {
        moved.0 = query.iter().collect();
        moved.0.sort();
    }

    fn schedule() -> Schedule {
        let mut schedule = Schedule::default();
        schedule.add_systems((propagate_transforms, record_moved).chain());
        schedule
    }

    #[test]
    fn three_levels_propagate_and_a_moved_parent_marks_its_children() {
        let mut world = World::new();
        world.init_resource::<Moved>();
        let root = world
            .spawn(Transform::from_translation(Vec3::X).with_scale(Vec3::splat(2.0)))
            .id();
        let rotation = Quat::from_rotation_z(std::f32::consts::FRAC_PI_2);
        let middle = world
            .spawn((
                Transform::from_translation(Vec3::Y).with_rotation(rotation),
                ChildOf(root),
            ))
            .id();
        let leaf = world
            .spawn((Transform::from_translation(Vec3::X), ChildOf(middle)))
            .id();
        let other = world.spawn(Transform::from_translation(Vec3::Z)).id();
        let mut schedule = schedule();
        schedule.run(&mut world);

        let global = |world: &World, e| world.get::<GlobalTransform>(e).unwrap().0;
        // middle: root * (translate Y, rotate 90 about Z) -> origin at (1, 2, 0)
        assert!(
            global(&world, middle)
                .translation
                .abs_diff_eq(Vec3::new(1.0, 2.0, 0.0).into(), 1e-6)
        );
        // leaf: its +X offset is rotated to +Y and scaled by 2 -> (1, 4, 0)
        let leaf_world = global(&world, leaf);
        assert!(
            leaf_world
                .translation
                .abs_diff_eq(Vec3::new(1.0, 4.0, 0.0).into(), 1e-5)
        );
        let expected = Affine3A::from_translation(Vec3::X)
            * Affine3A::from_scale(Vec3::splat(2.0))
            * Affine3A::from_translation(Vec3::Y)
            * Affine3A::from_quat(rotation)
            * Affine3A::from_translation(Vec3::X);
        assert!(leaf_world.abs_diff_eq(expected, 1e-5));

        schedule.run(&mut world);
        assert!(
            world.resource::<Moved>().0.is_empty(),
            "nothing moved, nothing changed"
        );

        world.get_mut::<Transform>(root).unwrap().translation = Vec3::new(5.0, 0.0, 0.0);
        schedule.run(&mut world);
        let mut expected_moved = vec![root, middle, leaf];
        expected_moved.sort();
        assert_eq!(world.resource::<Moved>().0, expected_moved);
        assert!(!world.resource::<Moved>().0.contains(&other));
        assert!(
            global(&world, leaf)
                .translation
                .abs_diff_eq(Vec3::new(5.0, 4.0, 0.0).into(), 1e-5)
        );

        world.get_mut::<Transform>(middle).unwrap().scale = Vec3::splat(3.0);
        schedule.run(&mut world);
        let mut expected_moved = vec![middle, leaf];
        expected_moved.sort();
        assert_eq!(
            world.resource::<Moved>().0,
            expected_moved,
            "a child's edit leaves its parent alone"
        );
    }

    #[test]
    fn reparenting_moves_the_child() {
        let mut world = World::new();
        world.init_resource::<Moved>();
        let a = world.spawn(Transform::from_translation(Vec3::X)).id();
        let b = world.spawn(Transform::from_translation(Vec3::Y)).id();
        let child = world.spawn((Transform::IDENTITY, ChildOf(a))).id();
        let mut schedule = schedule();
        schedule.run(&mut world);
        world.entity_mut(child).insert(ChildOf(b));
        schedule.run(&mut world);
        assert_eq!(world.resource::<Moved>().0, vec![child]);
        assert_eq!(
            world.get::<GlobalTransform>(child).unwrap().translation(),
            Vec3::Y
        );
    }
}
