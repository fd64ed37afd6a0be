//! The refractor-map techniques on the GPU: every variant renders finite pixels on chess and
//! cornell-sphere; separated and full-update agree when nothing moves; separated rebuilds only
//! the moving piece's impostor; more bounces and the full walk change the image the way the
//! paper says.

use refractor_maps::{EnvSettings, EnvironmentMaps, Search, Settings};
use scene::Technique;
use scene::multi_object::ImpostorSettings;
use testkit::{Shot, gpu_lock, max_difference, render_shots};

const SIZE: u32 = 32;

fn small(t: &mut dyn Technique) {
    for (name, value) in [("resolution", 32.0), ("env_resolution", 16.0)] {
        t.set_param(name, value).unwrap();
    }
}

#[test]
fn every_variant_renders_finite_pixels() {
    let _lock = gpu_lock();
    for spec in ["chess:material=mirror-mover", "cornell-sphere"] {
        let scene = scene::load(spec).unwrap();
        for mut t in refractor_maps::techniques() {
            small(t.as_mut());
            let shots: Vec<_> = [0.0, 1.0]
                .map(|time| Shot::along_path(&scene, time, SIZE))
                .into();
            let image = render_shots(t.as_mut(), &scene, &shots);
            assert_eq!(image.non_finite_count(), 0, "{} on {spec}", t.id());
            let lit = image
                .pixels
                .iter()
                .filter(|p| p[0] + p[1] + p[2] > 1e-3)
                .count();
            assert!(
                lit > image.pixels.len() / 2,
                "{} on {spec}: mostly black",
                t.id()
            );
        }
    }
}

/// The section-5 impostors with `settings`, at the small sizes of [`small`].
fn small_environment_maps(settings: EnvSettings) -> EnvironmentMaps {
    let mut t = EnvironmentMaps::new("refractor-maps/test", "test", true, settings);
    small(&mut t);
    t
}

/// Separated (true) or full update, small maps.
fn make(separated: bool) -> Box<dyn Technique> {
    Box::new(small_environment_maps(EnvSettings {
        impostors: ImpostorSettings {
            separated,
            ..ImpostorSettings::separated()
        },
        ..EnvSettings::default()
    }))
}

testkit::section5_tests!(make);

/// Impostor renders over `times` on chess, at 16 x 16 with small maps, for `separated` or
/// full update and a `rebuild_threshold` (metres).
fn rebuilds_along_the_path(separated: bool, rebuild_threshold: f32, times: &[f32]) -> u32 {
    let scene = scene::load("chess").unwrap();
    let shots: Vec<_> = times
        .iter()
        .map(|&t| Shot::along_path(&scene, t, 16))
        .collect();
    let mut t = small_environment_maps(EnvSettings {
        impostors: ImpostorSettings {
            separated,
            env_depth: 2,
            rebuild_threshold,
            ..ImpostorSettings::separated()
        },
        ..EnvSettings::default()
    });
    render_shots(&mut t, &scene, &shots);
    t.rebuilds()
}

fn chess_pieces() -> u32 {
    scene::load("chess").unwrap().specular_objects().len() as u32
}

/// Separated: the static impostors once (a diffuse start and env_depth rounds), then one
/// impostor per frame; full update: every impostor, all of that, every frame.
#[test]
fn separated_rebuilds_only_the_moving_impostor() {
    let _lock = gpu_lock();
    let pieces = chess_pieces();
    let times = [0.0, 0.5, 1.0];
    for (separated, expected) in [(true, 3 * (pieces - 1) + 3), (false, 3 * pieces * 3)] {
        let rebuilds = rebuilds_along_the_path(separated, 0.0, &times);
        assert_eq!(rebuilds, expected, "separated: {separated}");
    }
}

/// `rebuild_threshold` (section 5.1's "only when the rate of changes makes it necessary"):
/// the pawn moves a square a second, so with a threshold of three quarters of a square the
/// frames at t = 0, 1 and 2 update the impostors and those at 0.5 and 1.5 keep them.
#[test]
fn impostors_are_updated_only_when_the_mover_has_gone_far_enough() {
    let _lock = gpu_lock();
    let pieces = chess_pieces();
    let times = [0.0, 0.5, 1.0, 1.5, 2.0];
    let threshold = 0.75 * scene::builtin::chess::SQUARE;
    for (separated, expected) in [(true, 3 * (pieces - 1) + 3), (false, 3 * pieces * 3)] {
        let rebuilds = rebuilds_along_the_path(separated, threshold, &times);
        assert_eq!(rebuilds, expected, "separated: {separated}");
    }
}

/// The tracer: searching every piece and walking every grid cell give the same image (the
/// grid only skips pieces a ray cannot meet first); the paper's first-square shortcut and a
/// single bounce differ from it.
#[test]
fn the_grid_walk_loses_nothing_against_searching_every_piece() {
    let _lock = gpu_lock();
    let scene = scene::load("chess").unwrap();
    let shot = [Shot::along_path(&scene, 0.0, SIZE)];
    let render = |search: Search, depth: u32| {
        let mut t = refractor_maps::RefractorMaps::new(
            "refractor-maps/test",
            "test",
            true,
            Settings {
                search,
                depth,
                ..Settings::default()
            },
        );
        small(&mut t);
        render_shots(&mut t, &scene, &shot)
    };
    let grid = render(
        Search::Grid {
            max_cells: u32::MAX,
        },
        4,
    );
    let all = render(Search::AllPieces, 4);
    let single = render(Search::None, 1);
    let diff = max_difference(&grid, &all);
    assert!(diff < 1e-3, "grid and every piece differ by {diff}");
    assert!(
        max_difference(&grid, &single) > 0.05,
        "more bounces must show more pieces"
    );
}
