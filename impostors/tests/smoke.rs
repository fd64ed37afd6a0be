mod common;

#[test]
fn every_variant_renders_cornell_sphere_finite() {
    let _g = common::gpu_lock();
    for material in ["mirror", "glass-1.5"] {
        let mut strip = Vec::new();
        let scene = scene::load(&format!("cornell-sphere:material={material}")).unwrap();
        for mut t in impostors::techniques() {
            if !t.supports(&scene) {
                continue;
            }
            t.set_param("resolution", 64.0).unwrap();
            let img = common::render(t.as_mut(), &scene, 0.0, 64);
            assert_eq!(img.non_finite_count(), 0, "{} on {material}", t.id());
            if [
                "impostors/classic",
                "impostors/initial-guess",
                "impostors/false-position-4",
                "impostors/secant-4",
                "impostors/false-position-4-split",
                "impostors/double-refraction",
            ]
            .contains(&t.id().as_str())
            {
                strip.push(img);
            }
        }
        common::save_strip(
            &strip.iter().collect::<Vec<_>>(),
            &format!("smoke-{material}.png"),
            4,
        );
    }
}

/// `regen_threshold`: the map is regenerated only when the object moved farther than the
/// threshold from the map's reference point (the sphere moves 0.5 m per second along x).
#[test]
fn regeneration_follows_the_threshold() {
    use impostors::{Impostor, Settings};
    use scene::Technique;
    let _g = common::gpu_lock();
    let scene = scene::load("cornell-sphere:material=mirror").unwrap();
    let times = [0.0, 0.05, 0.1, 0.3, 0.6];
    for (threshold, expected) in [(0.0, 5), (0.2, 2), (1.0, 1)] {
        let mut t = Impostor::new("impostors/false-position-4", "test", Settings::default());
        t.set_param("resolution", 16.0).unwrap();
        t.set_param("regen_threshold", threshold).unwrap();
        common::render_frames(&mut t, &scene, &times, 16);
        assert_eq!(t.regenerations(), expected, "threshold {threshold}");
    }
}

/// The engine's probe (`Probe::RoomCentre`, as `impostors/box-projected`) is captured once at
/// `scene::probe_centre`, however far the object moves; the impostor's own map (`ObjectCentre`)
/// follows the object every frame.
#[test]
fn room_probe_is_captured_once() {
    use impostors::{Impostor, Lookup, Probe, Settings};
    let _g = common::gpu_lock();
    let scene = scene::load("cornell-sphere:material=mirror").unwrap();
    for (probe, expected) in [(Probe::RoomCentre, 1), (Probe::ObjectCentre, 3)] {
        let settings = Settings {
            lookup: Lookup::BoxProjected,
            probe,
            iterations: 0,
            resolution: 16,
            ..Settings::default()
        };
        let mut t = Impostor::new("impostors/box-projected", "test", settings);
        let image = common::render_frames(&mut t, &scene, &[0.0, 0.5, 1.0], 16);
        assert_eq!(t.regenerations(), expected, "{probe:?}");
        assert_eq!(image.non_finite_count(), 0);
    }
}

#[test]
fn variant_ids_and_params() {
    let ids: Vec<String> = impostors::techniques().iter().map(|t| t.id()).collect();
    let mut expected = vec![
        "impostors/classic".to_string(),
        "impostors/initial-guess".to_string(),
    ];
    expected.extend((1..=8).map(|n| format!("impostors/secant-{n}")));
    expected.extend((1..=8).map(|n| format!("impostors/false-position-{n}")));
    expected.push("impostors/false-position-4-split".into());
    expected.push("impostors/double-refraction".into());
    expected.push("impostors/box-projected".into());
    expected.push("impostors/box-projected-object".into());
    expected.push("impostors/box-projected-double".into());
    expected.push("impostors/caustics".into());
    expected.push("impostors/caustics-compute".into());
    assert_eq!(ids, expected);
    for mut t in impostors::techniques() {
        let names: Vec<&str> = t.params().iter().map(|p| p.name).collect();
        assert!(names.contains(&"resolution"), "{}", t.id());
        // The room probe is captured once: it has no regeneration threshold.
        assert_eq!(
            names.contains(&"regen_threshold"),
            t.id() != "impostors/box-projected",
            "{}",
            t.id()
        );
        // The classic map and the box-projected lookups read no distances: no Hit() steps.
        let searches = t.id() != "impostors/classic" && !t.id().contains("box-projected");
        assert_eq!(
            names.contains(&"iterations") && names.contains(&"split"),
            searches,
            "{}",
            t.id()
        );
        assert!(t.set_param("iterations", 1e9).is_err());
        assert!(t.set_param("nonsense", 1.0).is_err());
        for p in t.params() {
            t.set_param(p.name, p.default).unwrap();
        }
    }
}
