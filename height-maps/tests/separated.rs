//! `height-maps/separated` and `full-update` on the GPU (section 5.2 with height maps): the
//! two agree when nothing moves (the build-once path against the rebuild path, with the
//! billboards drawn into the impostors); with the mirror pawn moving they stay close but
//! differ (the moving piece found from outside in its height map); separated rebuilds only the
//! moving piece's impostor.

use height_maps::{HeightMapsSeparated, SeparatedSettings};
use scene::{Scene, Technique};
use testkit::{Shot, gpu_lock, max_difference, relative_difference, render_shots};

const SIZE: u32 = 32;

/// The variant with `settings` and small maps.
fn small(settings: SeparatedSettings) -> HeightMapsSeparated {
    let mut t = HeightMapsSeparated::new("height-maps/test", "test", true, settings);
    for (name, value) in [("resolution", 64.0), ("env_resolution", 16.0)] {
        t.set_param(name, value).unwrap();
    }
    t
}

/// The last image of `shots` by separated, by full update and by separated with the static
/// pieces not searching for the moving one (`find_mover` off).
fn three_ways(scene: &Scene, shots: &[Shot]) -> [gpu::HdrImage; 3] {
    [(true, true), (false, true), (true, false)].map(|(separated, find_mover)| {
        let mut t = small(SeparatedSettings {
            separated,
            find_mover,
            ..SeparatedSettings::default()
        });
        render_shots(&mut t, scene, shots)
    })
}

#[test]
fn separated_and_full_update_agree_when_nothing_moves() {
    let _lock = gpu_lock();
    let mut scene = scene::load("chess").unwrap();
    for o in &mut scene.objects {
        o.motion.keys.clear();
    }
    let shots: Vec<_> = [0.0, 1.0].map(|t| Shot::along_path(&scene, t, SIZE)).into();
    let [separated, full_update, _] = three_ways(&scene, &shots);
    let diff = max_difference(&separated, &full_update);
    assert!(diff < 1e-4, "separated and full update differ by {diff}");
}

/// The paper's figure 9 scene along its camera path: separated finds the moving mirror pawn
/// from outside where full update has it in every impostor; the images stay within 1 % of
/// the radiance but differ.
#[test]
fn separated_stays_close_to_full_update_with_a_moving_mirror() {
    let _lock = gpu_lock();
    let scene = scene::load("chess:material=mirror-mover").unwrap();
    let shots: Vec<_> = [0.0, 2.0].map(|t| Shot::along_path(&scene, t, SIZE)).into();
    let [separated, full_update, _] = three_ways(&scene, &shots);
    let difference = relative_difference(&separated, &full_update);
    println!("mean difference {difference:.5} of mean radiance");
    assert!(
        difference < 0.01,
        "separated strays from full update: {difference}"
    );
    assert!(
        difference > 0.0,
        "the moving mirror changes nothing: the mover path is not exercised"
    );
}

/// Close behind the moving mirror pawn, where its glass neighbours show it: the search from
/// outside in its height map changes their pixels and brings separated closer to full
/// update, which has the pawn in every impostor, than the static impostors alone.
#[test]
fn the_static_pieces_find_the_moving_one_from_outside() {
    let _lock = gpu_lock();
    let (scene, shot) = testkit::mover_close_up(64);
    let [separated, full_update, without_search] = three_ways(&scene, &[shot]);
    let with = relative_difference(&separated, &full_update);
    let without = relative_difference(&without_search, &full_update);
    let changed = testkit::pixels_differing(&separated, &without_search, 0.01);
    println!(
        "from full update: {with:.4} with the search, {without:.4} without; it changes \
         {changed} pixels"
    );
    assert!(changed >= 20, "the search changes {changed} pixels");
    assert!(
        with < 0.8 * without,
        "the search does not bring separated closer to full update: {with} against {without}"
    );
}

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
            separated,
            ..SeparatedSettings::default()
        });
        render_shots(&mut t, &scene, &shots);
        assert_eq!(t.rebuilds(), expected, "separated: {separated}");
    }
}
