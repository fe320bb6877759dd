//! Sampling against values computed by hand for each interpolation, the checks on keys, looping,
//! and the system's writes.

use super::*;

fn x(values: &[f32]) -> Vec<Vec4> {
    values
        .iter()
        .map(|&v| Vec4::new(v, 0.0, 0.0, 0.0))
        .collect()
}

#[test]
fn step_holds_the_last_key_reached() {
    let k = Keyframes::new(
        vec![0.0, 1.0, 2.0],
        x(&[0.0, 10.0, 20.0]),
        Interpolation::Step,
    )
    .unwrap();
    for (t, expected) in [
        (-1.0, 0.0),
        (0.0, 0.0),
        (0.5, 0.0),
        (1.0, 10.0),
        (1.99, 10.0),
        (2.0, 20.0),
        (7.0, 20.0),
    ] {
        assert_eq!(k.sample(t, false).x, expected, "t {t}");
    }
}

#[test]
fn linear_interpolates_between_keys() {
    let k = Keyframes::new(vec![1.0, 3.0], x(&[2.0, 6.0]), Interpolation::Linear).unwrap();
    assert_eq!(k.sample(0.0, false).x, 2.0);
    assert_eq!(k.sample(1.5, false).x, 3.0);
    assert_eq!(k.sample(2.5, false).x, 5.0);
    assert_eq!(k.sample(9.0, false).x, 6.0);
}

/// Linear rotations are spherical: halfway from the identity to 90 degrees about z is 45
/// degrees about z, (0, 0, sin 22.5, cos 22.5), not the normalised average of the quaternions'
/// components at other fractions (at a quarter: 22.5 degrees).
#[test]
fn linear_rotations_are_slerped() {
    let a = Vec4::from(Quat::IDENTITY);
    let b = Vec4::from(Quat::from_rotation_z(std::f32::consts::FRAC_PI_2));
    let k = Keyframes::new(vec![0.0, 1.0], vec![a, b], Interpolation::Linear).unwrap();
    for (s, degrees) in [(0.5f32, 45.0f32), (0.25, 22.5), (0.75, 67.5)] {
        let half = degrees.to_radians() / 2.0;
        let expected = Vec4::new(0.0, 0.0, half.sin(), half.cos());
        let got = k.sample(s, true);
        assert!(
            (got - expected).abs().max_element() < 1e-6,
            "{s}: {got} vs {expected}"
        );
    }
}

/// glTF's cubic Hermite spline: keys at 0 and 2 s, value 0 with out-tangent 1, then value 1
/// with in-tangent 0. At 1 s (s = 0.5, dt = 2): 2 (s^3 - 2 s^2 + s) 1 + (-2 s^3 + 3 s^2) 1 =
/// 0.25 + 0.5 = 0.75; at 0.5 s (s = 0.25): 2 (0.140625) + 0.15625 = 0.4375.
#[test]
fn cubic_splines_follow_the_tangents() {
    // (in-tangent, value, out-tangent) per key.
    let k = Keyframes::new(
        vec![0.0, 2.0],
        x(&[9.0, 0.0, 1.0, 0.0, 1.0, 9.0]),
        Interpolation::CubicSpline,
    )
    .unwrap();
    assert!((k.sample(1.0, false).x - 0.75).abs() < 1e-6);
    assert!((k.sample(0.5, false).x - 0.4375).abs() < 1e-6);
    assert_eq!(k.sample(2.0, false).x, 1.0);
    assert_eq!(k.sample(-3.0, false).x, 0.0);
}

#[test]
fn spline_rotations_come_back_unit() {
    let q = Vec4::from(Quat::from_rotation_y(1.0));
    let k = Keyframes::new(
        vec![0.0, 1.0],
        vec![Vec4::ZERO, Vec4::W, q * 3.0, q * 3.0, q, Vec4::ZERO],
        Interpolation::CubicSpline,
    )
    .unwrap();
    for t in [0.1, 0.5, 0.9] {
        assert!((k.sample(t, true).length() - 1.0).abs() < 1e-6);
    }
}

#[test]
fn bad_keys_are_refused_with_the_reason() {
    let err = |times: Vec<f32>, values: Vec<Vec4>, i| Keyframes::new(times, values, i).unwrap_err();
    assert!(err(vec![], vec![], Interpolation::Linear).contains("no keys"));
    assert!(
        err(vec![0.0, 1.0, 1.0], x(&[0.0; 3]), Interpolation::Linear)
            .contains("not increasing: key 2 at 1 s follows 1 s")
    );
    assert!(err(vec![0.0, f32::NAN], x(&[0.0; 2]), Interpolation::Step).contains("not finite"));
    assert!(
        err(vec![0.0, 1.0], x(&[0.0; 2]), Interpolation::CubicSpline)
            .contains("2 keys but 2 values (3 per key expected)")
    );
    assert!(err(vec![0.0], x(&[f32::INFINITY]), Interpolation::Step).contains("value 0"));
}

#[test]
fn clips_loop_over_their_duration() {
    let clip = AnimationClip {
        name: "c".into(),
        channels: vec![Channel {
            target: 0usize,
            property: Property::Translation,
            keyframes: Keyframes::new(vec![0.5, 2.0], x(&[0.0, 1.0]), Interpolation::Linear)
                .unwrap(),
        }],
    };
    assert_eq!(clip.duration(), 2.0);
    assert_eq!(clip.local_time(5.0), 1.0);
    assert_eq!(clip.local_time(-0.5), 1.5);
    assert_eq!(clip.local_time(f64::NAN), 0.0);
}

/// The system writes the transforms the time asks for, and leaves them unchanged (not even
/// marked changed) when neither the time nor the clips changed.
#[test]
fn the_system_poses_nodes_and_only_when_time_moves() {
    let mut world = World::new();
    let node = world.spawn(Transform::IDENTITY).id();
    let keyframes = Keyframes::new(vec![0.0, 1.0], x(&[0.0, 4.0]), Interpolation::Linear).unwrap();
    world.insert_resource(Animations {
        clips: vec![AnimationClip {
            name: "slide".into(),
            channels: vec![Channel {
                target: node,
                property: Property::Translation,
                keyframes,
            }],
        }],
    });
    world.insert_resource(Time { seconds: 0.25 });
    let mut schedule = Schedule::default();
    schedule.add_systems(animate_nodes);
    schedule.run(&mut world);
    assert_eq!(world.get::<Transform>(node).unwrap().translation.x, 1.0);

    let mut changed = world.query_filtered::<Entity, Changed<Transform>>();
    world.clear_trackers();
    schedule.run(&mut world);
    assert_eq!(changed.iter(&world).count(), 0, "nothing moved");

    world.resource_mut::<Time>().seconds = 0.5;
    schedule.run(&mut world);
    assert_eq!(world.get::<Transform>(node).unwrap().translation.x, 2.0);
    assert_eq!(changed.iter(&world).count(), 1);
}
