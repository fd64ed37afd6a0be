//! The shared tests of section 5's per-piece impostors (`scene::multi_object::PieceImpostors`)
//! for any per-object search: `refractor-maps` (distance maps) and `height-maps` (height maps)
//! run them on their `full-update` and `separated` variants. Each takes `make(separated)`,
//! a fresh instance with small maps; parameters are set by name.

use crate::{Shot, max_difference, pixels_differing, relative_difference, render_shots};
use gpu::HdrImage;
use scene::{Scene, Technique};

/// The four shared tests as `#[test]` functions of the calling test crate, each holding the
/// GPU lock, on `make` (a `fn(bool) -> Box<dyn Technique>`): `testkit::section5_tests!(make);`.
#[macro_export]
macro_rules! section5_tests {
    ($make:path) => {
        #[test]
        fn separated_and_full_update_agree_when_nothing_moves() {
            let _lock = $crate::gpu_lock();
            $crate::section5::separated_and_full_update_agree_when_nothing_moves(&$make);
        }

        #[test]
        fn separated_stays_close_to_full_update_with_a_moving_mirror() {
            let _lock = $crate::gpu_lock();
            $crate::section5::separated_stays_close_to_full_update_with_a_moving_mirror(&$make);
        }

        #[test]
        fn the_static_pieces_find_the_moving_one_from_outside() {
            let _lock = $crate::gpu_lock();
            $crate::section5::the_static_pieces_find_the_moving_one_from_outside(&$make);
        }

        #[test]
        fn the_rounds_draw_the_pieces_into_the_impostors() {
            let _lock = $crate::gpu_lock();
            $crate::section5::the_rounds_draw_the_pieces_into_the_impostors(&$make);
        }
    };
}

/// A fresh variant: separated (true) or full update (false), with small maps.
pub type Make<'a> = &'a dyn Fn(bool) -> Box<dyn Technique>;

/// The last image of `shots` by `make(separated)` with parameters `params`.
fn render(
    make: Make,
    separated: bool,
    params: &[(&str, f64)],
    scene: &Scene,
    shots: &[Shot],
) -> HdrImage {
    let mut t = make(separated);
    for &(name, value) in params {
        t.set_param(name, value).unwrap();
    }
    render_shots(t.as_mut(), scene, shots)
}

/// Chess with nothing moving: separated's static impostors, built once, must be exactly what
/// full update rebuilds every frame (the build-once path against the rebuild path).
pub fn separated_and_full_update_agree_when_nothing_moves(make: Make) {
    let mut scene = scene::load("chess").unwrap();
    for o in &mut scene.objects {
        o.motion.keys.clear();
    }
    let shots: Vec<_> = [0.0, 1.0].map(|t| Shot::along_path(&scene, t, 32)).into();
    let separated = render(make, true, &[], &scene, &shots);
    let full_update = render(make, false, &[], &scene, &shots);
    let diff = max_difference(&separated, &full_update);
    assert!(diff < 1e-4, "separated and full update differ by {diff}");
}

/// The paper's figure-9 scene along its camera path: separated (the moving mirror pawn found
/// from outside) stays within 1 % of the radiance of full update (the pawn in every
/// impostor). Returns the difference.
pub fn separated_stays_close_to_full_update_with_a_moving_mirror(make: Make) -> f32 {
    let scene = scene::load("chess:material=mirror-mover").unwrap();
    let shots: Vec<_> = [0.0, 2.0].map(|t| Shot::along_path(&scene, t, 32)).into();
    let separated = render(make, true, &[], &scene, &shots);
    let full_update = render(make, false, &[], &scene, &shots);
    let difference = relative_difference(&separated, &full_update);
    println!("mean difference {difference:.5} of mean radiance");
    assert!(
        difference < 0.01,
        "separated strays from full update: {difference}"
    );
    difference
}

/// The paper's figure-9 scene seen from close behind the moving mirror pawn at time 0, while
/// it still stands between its glass neighbours: a shot in which the static pieces'
/// reflections and refractions show the moving piece (from the default camera it covers a
/// few pixels of them).
pub fn mover_close_up(size: u32) -> (Scene, Shot) {
    let mut scene = scene::load("chess:material=mirror-mover").expect("built-in scene");
    let mover = scene
        .objects
        .iter()
        .find(|o| !o.motion.is_static())
        .expect("the moving pawn")
        .center_at(0.0);
    scene.camera.eye = mover + glam::Vec3::new(0.1, 0.2, 0.45);
    scene.camera.target = mover;
    scene.camera_path = Default::default();
    let shot = Shot::default_camera(&scene, 0.0, size);
    (scene, shot)
}

/// Close behind the moving mirror ([`mover_close_up`], 64 x 64): the search from outside in
/// its map changes at least 20 of its neighbours' pixels (against `find_mover = 0`, the static
/// impostors alone) and brings separated a fifth or more closer to full update, which has the
/// pawn in every impostor. A search that finds nothing fails both. Returns (changed pixels,
/// difference with the search, without).
pub fn the_static_pieces_find_the_moving_one_from_outside(make: Make) -> (usize, f32, f32) {
    let (scene, shot) = mover_close_up(64);
    let separated = render(make, true, &[], &scene, &[shot]);
    let without_search = render(make, true, &[("find_mover", 0.0)], &scene, &[shot]);
    let full_update = render(make, false, &[], &scene, &[shot]);
    let with = relative_difference(&separated, &full_update);
    let without = relative_difference(&without_search, &full_update);
    let changed = pixels_differing(&separated, &without_search, 0.01);
    println!(
        "from full update: {with:.4} with the search, {without:.4} without; it changes \
         {changed} pixels"
    );
    assert!(changed >= 20, "the search changes {changed} pixels");
    assert!(
        with < 0.8 * without,
        "the search does not bring separated closer to full update: {with} against {without}"
    );
    (changed, with, without)
}

/// The rounds of section 5.1 draw the other pieces into each impostor: close among the
/// pieces ([`mover_close_up`], 64 x 64), the pixels with `env_depth = 2` differ from those
/// with `env_depth = 0` (impostors of the diffuse scene alone) on at least 150 pixels
/// (measured: 352 with distance maps, 314 with height maps). Impostors into which the pieces
/// were never drawn change none. Returns the changed pixels.
pub fn the_rounds_draw_the_pieces_into_the_impostors(make: Make) -> usize {
    let (scene, shot) = mover_close_up(64);
    let diffuse_only = render(make, true, &[("env_depth", 0.0)], &scene, &[shot]);
    let two_rounds = render(make, true, &[("env_depth", 2.0)], &scene, &[shot]);
    let changed = pixels_differing(&two_rounds, &diffuse_only, 0.01);
    println!("two rounds change {changed} of {} pixels", 64 * 64);
    assert!(
        changed >= 150,
        "two rounds change only {changed} pixels: the pieces are not in the impostors"
    );
    changed
}
