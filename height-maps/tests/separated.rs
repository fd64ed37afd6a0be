//! `height-maps/separated` and `full-update` on the GPU (section 5.2 with height maps), by
//! `testkit::section5`'s shared tests of the impostors: the two agree when nothing moves;
//! with the mirror pawn moving they stay close; close behind it the search from outside in
//! its height map shows it in its neighbours; the rounds draw the billboards into the
//! impostors; separated rebuilds only the moving piece's impostor.

use height_maps::{HeightMapsSeparated, SeparatedSettings};
use scene::Technique;
use scene::multi_object::ImpostorSettings;
use testkit::{Shot, gpu_lock, render_shots};

/// The variant with `settings` and small maps.
fn small(settings: SeparatedSettings) -> HeightMapsSeparated {
    let mut t = HeightMapsSeparated::new("height-maps/test", "test", true, settings);
    for (name, value) in [("resolution", 64.0), ("env_resolution", 16.0)] {
        t.set_param(name, value).unwrap();
    }
    t
}

/// Separated (true) or full update, small maps.
fn make(separated: bool) -> Box<dyn Technique> {
    Box::new(small(SeparatedSettings {
        impostors: ImpostorSettings {
            separated,
            ..ImpostorSettings::separated()
        },
        ..SeparatedSettings::default()
    }))
}

testkit::section5_tests!(make);

/// Separated: the static impostors once (a diffuse start and two rounds), then one impostor
/// per frame; full update: every impostor, all of that, every frame.
#[test]
fn separated_rebuilds_only_the_moving_impostor() {
    let _lock = gpu_lock();
    let scene = scene::load("chess").unwrap();
    let pieces = scene.specular_objects().len() as u32;
    let shots: Vec<_> = [0.0, 0.5, 1.0]
        .map(|t| Shot::along_path(&scene, t, 16))
        .into();
    for (separated, expected) in [(true, 3 * (pieces - 1) + 3), (false, 3 * pieces * 3)] {
        let mut t = small(SeparatedSettings {
            impostors: ImpostorSettings {
                separated,
                ..ImpostorSettings::separated()
            },
            ..SeparatedSettings::default()
        });
        render_shots(&mut t, &scene, &shots);
        assert_eq!(t.rebuilds(), expected, "separated: {separated}");
    }
}
