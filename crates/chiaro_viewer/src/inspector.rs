//! The scene part of the panel: the environment's strength and rotation, the list of mesh
//! instances and lights, and editors for the selected one (its `Transform`, its material in
//! the `Materials` resource, its `Light`), plus adding and removing point lights. Every edit
//! is written to the World only when a value changed, so change tracking sees real edits only.

use bevy_ecs::prelude::*;
use chiaro_scene::{Environment, Light, LightKind, Materials, MeshInstance, Name, Transform};
use glam::{EulerRot, Quat, Vec3};

/// Most entities the list shows (a scene of 10,000 instances lists the first ones).
const MAX_LISTED: usize = 200;

fn vec3_editor(ui: &mut egui::Ui, label: &str, value: &mut Vec3, speed: f32) -> bool {
    ui.horizontal(|ui| {
        ui.label(label);
        let mut changed = false;
        for c in [&mut value.x, &mut value.y, &mut value.z] {
            changed |= ui.add(egui::DragValue::new(c).speed(speed)).changed();
        }
        changed
    })
    .inner
}

fn color_editor(ui: &mut egui::Ui, label: &str, color: &mut Vec3) -> bool {
    ui.horizontal(|ui| {
        let mut rgb = color.to_array();
        let changed = ui.color_edit_button_rgb(&mut rgb).changed();
        ui.label(label);
        if changed {
            *color = Vec3::from(rgb);
        }
        changed
    })
    .inner
}

fn environment(ui: &mut egui::Ui, world: &mut World) {
    let Some(env) = world.get_resource::<Environment>() else {
        return;
    };
    let (mut strength, mut degrees) = (env.strength, env.rotation.to_degrees());
    let strength_changed = ui
        .add(
            egui::Slider::new(&mut strength, 0.0..=100.0)
                .logarithmic(true)
                .text("env strength"),
        )
        .changed();
    let rotation_changed = ui
        .add(egui::Slider::new(&mut degrees, -180.0..=180.0).text("env rotation (deg)"))
        .changed();
    if strength_changed || rotation_changed {
        let mut env = world.resource_mut::<Environment>();
        env.strength = strength;
        env.rotation = degrees.to_radians();
    }
}

fn list(ui: &mut egui::Ui, world: &mut World, selected: &mut Option<Entity>) {
    let mut query = world.query_filtered::<(Entity, Option<&Name>, Has<Light>), Or<(
        With<MeshInstance>,
        With<Light>,
    )>>();
    let entries: Vec<(Entity, String)> = query
        .iter(world)
        .take(MAX_LISTED)
        .map(|(e, name, light)| {
            let kind = if light { "light" } else { "mesh" };
            let name = name.map_or_else(|| format!("{e}"), |n| n.as_str().to_string());
            (e, format!("{name} ({kind})"))
        })
        .collect();
    egui::ScrollArea::vertical()
        .id_salt("scene list")
        .max_height(140.0)
        .show(ui, |ui| {
            for (entity, label) in entries {
                if ui
                    .selectable_label(*selected == Some(entity), label)
                    .clicked()
                {
                    *selected = Some(entity);
                }
            }
        });
}

fn transform(ui: &mut egui::Ui, world: &mut World, entity: Entity) {
    let Some(&t) = world.get::<Transform>(entity) else {
        return;
    };
    let mut translation = t.translation;
    let (y, x, z) = t.rotation.to_euler(EulerRot::YXZ);
    let mut degrees = Vec3::new(x, y, z) * 180.0 / std::f32::consts::PI;
    let mut scale = t.scale;
    let mut changed = vec3_editor(ui, "move", &mut translation, 0.01);
    changed |= vec3_editor(ui, "rotate", &mut degrees, 0.5);
    changed |= vec3_editor(ui, "scale", &mut scale, 0.01);
    if changed {
        let r = degrees * std::f32::consts::PI / 180.0;
        let edited = Transform {
            translation,
            rotation: Quat::from_euler(EulerRot::YXZ, r.y, r.x, r.z),
            scale: scale.max(Vec3::splat(1e-4)),
        };
        if let Some(mut t) = world.get_mut::<Transform>(entity) {
            *t = edited;
        }
    }
}

fn material(ui: &mut egui::Ui, world: &mut World, entity: Entity) {
    let Some(id) = world.get::<MeshInstance>(entity).map(|m| m.material) else {
        return;
    };
    let Some(mut m) = world
        .get_resource::<Materials>()
        .and_then(|ms| ms.get(id))
        .cloned()
    else {
        return;
    };
    ui.label(format!("material '{}' (shared by its instances)", m.name));
    let mut base = m.base_color.truncate();
    let mut changed = color_editor(ui, "base colour", &mut base);
    changed |= ui
        .add(egui::Slider::new(&mut m.metallic, 0.0..=1.0).text("metallic"))
        .changed();
    changed |= ui
        .add(egui::Slider::new(&mut m.roughness, 0.0..=1.0).text("roughness"))
        .changed();
    changed |= color_editor(ui, "emission", &mut m.emissive);
    changed |= ui
        .add(
            egui::Slider::new(&mut m.emissive_strength, 0.0..=1000.0)
                .logarithmic(true)
                .text("emission strength"),
        )
        .changed();
    if changed {
        m.base_color = base.extend(m.base_color.w);
        if let Some(slot) = world.resource_mut::<Materials>().get_mut(id) {
            *slot = m;
        }
    }
}

fn light(ui: &mut egui::Ui, world: &mut World, entity: Entity) -> bool {
    let Some(&original) = world.get::<Light>(entity) else {
        return false;
    };
    let mut l = original;
    color_editor(ui, "colour", &mut l.color);
    ui.add(
        egui::Slider::new(&mut l.intensity, 0.0..=1e5)
            .logarithmic(true)
            .text("intensity"),
    );
    if l != original
        && let Some(mut slot) = world.get_mut::<Light>(entity)
    {
        *slot = l;
    }
    ui.button("remove light").clicked()
}

/// Shows the scene section; `selected` is the selected entity, `eye` where a new light goes.
pub fn show(ui: &mut egui::Ui, world: &mut World, selected: &mut Option<Entity>, eye: Vec3) {
    environment(ui, world);
    if ui.button("add point light at the camera").clicked() {
        let entity = world
            .spawn((
                Light {
                    kind: LightKind::Point,
                    color: Vec3::ONE,
                    intensity: 10.0,
                    range: None,
                },
                Transform::from_translation(eye),
                Name::new("added light"),
            ))
            .id();
        *selected = Some(entity);
    }
    if let Some(entity) = selected.filter(|&e| world.get_entity(e).is_ok()) {
        selected_editor(ui, world, selected, entity);
    } else {
        *selected = None;
    }
    ui.separator();
    list(ui, world, selected);
}

fn selected_editor(
    ui: &mut egui::Ui,
    world: &mut World,
    selected: &mut Option<Entity>,
    entity: Entity,
) {
    ui.separator();
    let name = world
        .get::<Name>(entity)
        .map_or_else(|| format!("{entity}"), |n| n.as_str().to_string());
    ui.label(format!("selected: {name}"));
    transform(ui, world, entity);
    material(ui, world, entity);
    if light(ui, world, entity) {
        world.despawn(entity);
        *selected = None;
    }
}
