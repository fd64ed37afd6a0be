//! Refractor height maps against refractor distance maps, per kind of chess piece (the
//! height-maps README's table): the mean FLIP over the pixels that show each kind, on the whole
//! board and on a close-up of one piece of each kind, for the two techniques that trace one
//! piece per path the same way (enter, exit through the piece's map, then the diffuse
//! environment impostor): `refractor-maps/single-bounce` (distance maps) and
//! `height-maps/double-refraction` (height maps, the paper's binary search; and with an
//! 8-step linear bracket); and for the many-object tracer with either map:
//! `refractor-maps/multi-bounce-4` and `height-maps/in-chess`. The reference has no caustics here: a caustic is never seen through
//! a piece, so the pieces' pixels do not change.
//!
//! `cargo test -p workspace-tests --test height_vs_distance -- --nocapture` prints the table
//! and writes each close-up (reference, then each technique, then their FLIP maps) to
//! `target/height-vs-distance/<kind>.png`.

use glam::Vec3;
use scene::builtin::chess::PieceKind;
use scene::{Camera, Kinds, Scene, Technique};
use testkit::Shot;

const SPEC: &str = "chess";

fn technique(id: &str, params: &[(&str, f64)]) -> Box<dyn Technique> {
    let mut t = harness::registry()
        .into_iter()
        .find(|t| t.id() == id)
        .unwrap_or_else(|| panic!("no technique {id}"));
    for &(name, value) in params {
        t.set_param(name, value).unwrap();
    }
    t
}

/// Mean FLIP of `image` over the pixels whose reference object is in `objects`, and their count.
fn kind_error(flip: &truth::metrics::FlipMap, ids: &[i32], objects: &[usize]) -> (f64, usize) {
    let (sum, n) = flip
        .values
        .iter()
        .zip(ids)
        .filter(|(_, id)| objects.contains(&(**id as usize)) && **id >= 0)
        .fold((0.0, 0), |(s, n), (v, _)| (s + *v as f64, n + 1));
    (sum / n.max(1) as f64, n)
}

/// A FLIP map as an image (its magma colours).
fn flip_image(flip: &truth::metrics::FlipMap) -> gpu::HdrImage {
    let rgb = flip.to_magma_rgb8();
    let mut image = gpu::HdrImage::new(flip.width, flip.height);
    for (i, p) in rgb.chunks_exact(3).enumerate() {
        let c = |v: u8| {
            let v = v as f32 / 255.0;
            if v <= 0.04045 {
                v / 12.92
            } else {
                ((v + 0.055) / 1.055).powf(2.4)
            }
        };
        image.pixels[i] = [c(p[0]), c(p[1]), c(p[2]), 1.0];
    }
    image
}

/// A close-up of `object`: from 0.3 m in front of it toward the board's white side, 0.15 m up.
fn close_up(scene: &Scene, object: usize) -> Camera {
    let c = scene.objects[object].center_at(0.0);
    Camera {
        eye: c + Vec3::new(0.08, 0.15, 0.3),
        target: c,
        up: Vec3::Y,
        fov_y_deg: 40.0,
        orthographic: None,
    }
}

#[test]
fn height_maps_against_distance_maps_per_piece_kind() {
    let _lock = testkit::gpu_lock();
    let scene = scene::load(SPEC).unwrap();
    let kinds = Kinds::of(&scene);
    // Each chess kind's objects, and one white piece of it for the close-up.
    let by_kind: Vec<(PieceKind, Vec<usize>, usize)> = PieceKind::ALL
        .iter()
        .map(|&k| {
            let objects: Vec<usize> = kinds
                .pieces
                .iter()
                .map(|&(o, _)| o)
                .filter(|&o| PieceKind::of_object(&scene.objects[o].name) == Some(k))
                .collect();
            let white = *objects
                .iter()
                .find(|&&o| scene.objects[o].name.starts_with("white"))
                .unwrap();
            (k, objects, white)
        })
        .collect();
    let mut techniques = [
        ("distance", technique("refractor-maps/single-bounce", &[])),
        ("height", technique("height-maps/double-refraction", &[])),
        (
            "height, bracket",
            technique("height-maps/double-refraction", &[("linear_steps", 8.0)]),
        ),
        (
            "distance, traced",
            technique("refractor-maps/multi-bounce-4", &[]),
        ),
        ("height, traced", technique("height-maps/in-chess", &[])),
    ];
    let mut errors = vec![[[0.0f64; 5]; 2]; by_kind.len()];
    // The board once (every kind's error from the same images), then a close-up per kind.
    let board = Shot::along_path(&scene, 0.0, 192);
    let reference = testkit::reference(SPEC, &scene, board, 0);
    for (j, (_, t)) in techniques.iter_mut().enumerate() {
        let image = testkit::render(t.as_mut(), &scene, board);
        let (_, flip) = truth::metrics::compare(&image, &reference.image, None);
        for (k, (_, objects, _)) in by_kind.iter().enumerate() {
            let (e, n) = kind_error(&flip, &reference.object_ids, objects);
            assert!(n > 20, "too few pixels of kind {k} on the board");
            errors[k][0][j] = e;
        }
    }
    for (k, (kind, objects, white)) in by_kind.iter().enumerate() {
        let shot = Shot {
            camera: close_up(&scene, *white),
            time: 0.0,
            size: 128,
        };
        let reference = testkit::reference(SPEC, &scene, shot, 0);
        let (mut images, mut flips) = (vec![reference.image.clone()], vec![]);
        for (j, (_, t)) in techniques.iter_mut().enumerate() {
            let image = testkit::render(t.as_mut(), &scene, shot);
            let (_, flip) = truth::metrics::compare(&image, &reference.image, None);
            let (e, n) = kind_error(&flip, &reference.object_ids, objects);
            assert!(n > 20, "too few pixels of kind {k} in its close-up");
            errors[k][1][j] = e;
            images.push(image);
            flips.push(flip_image(&flip));
        }
        let row: Vec<&gpu::HdrImage> = images.iter().chain(&flips).collect();
        let path = testkit::out_dir("height-vs-distance").join(format!("{}.png", kind.name()));
        testkit::save_png(&testkit::strip(&row, 1), &path);
    }
    for (view, name) in ["board", "close-up"].iter().enumerate() {
        println!("\n{name}:\n");
        let names: Vec<&str> = techniques.iter().map(|(n, _)| *n).collect();
        println!("| kind | {} |", names.join(" | "));
        println!("| --- |{}", " --- |".repeat(names.len()));
        for (k, (kind, _, _)) in by_kind.iter().enumerate() {
            let row: Vec<String> = errors[k][view].iter().map(|e| format!("{e:.4}")).collect();
            println!("| {} | {} |", kind.name(), row.join(" | "));
        }
    }
    // The claims of the README, as measured. On the board the paper's search beats distance
    // maps on the revolved pieces but the queen (within 2% there) ...
    let name = |k: usize| by_kind[k].0.name();
    for (k, (kind, _, _)) in by_kind.iter().enumerate() {
        let e = errors[k];
        if matches!(
            kind,
            PieceKind::Pawn | PieceKind::Rook | PieceKind::Bishop | PieceKind::King
        ) {
            assert!(
                e[0][1] < 0.9 * e[0][0],
                "{}: height {} vs distance {}",
                name(k),
                e[0][1],
                e[0][0]
            );
        }
        // ... with the linear bracket every kind but the knight, on both views ...
        if *kind != PieceKind::Knight {
            for view in 0..2 {
                assert!(
                    e[view][2] < e[view][0],
                    "{} view {view}: {:?}",
                    name(k),
                    e[view]
                );
            }
        }
    }
    // ... the many-object tracer with height maps beats it with distance maps on every kind,
    // the knight included (its first hit is the rasterized mesh, not a billboard), in both
    // views ...
    for k in 0..by_kind.len() {
        for view in 0..2 {
            let e = errors[k][view];
            assert!(
                e[4] < 0.95 * e[3],
                "{} view {view}: traced {:?}",
                name(k),
                e
            );
        }
    }
    // ... and the knight, whose side profile the billboard shows from every side, is the
    // height map's worst kind on the board.
    let knight = PieceKind::ALL
        .iter()
        .position(|&k| k == PieceKind::Knight)
        .unwrap();
    for k in 0..by_kind.len() {
        assert!(
            errors[k][0][1] <= errors[knight][0][1],
            "{} worse than the knight",
            name(k)
        );
    }
}
