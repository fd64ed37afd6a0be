//! The height-map techniques on the GPU: every variant renders finite pixels and draws every
//! piece where it is on chess (glass and a mirror mover) and cornell-sphere at two times; the
//! in-chess tracer's deeper paths change only the pieces.

use scene::Technique;
use testkit::{Shot, gpu_lock, render_shots};

const SIZE: u32 = 32;

fn small(t: &mut dyn Technique) {
    for (name, value) in [("resolution", 64.0), ("env_resolution", 16.0)] {
        t.set_param(name, value).unwrap();
    }
}

/// Every variant draws every piece where the piece is: on most pixels whose primary ray meets
/// a specular object (the exact BVH hit), the image is lit and its alpha (the distance of what
/// the pixel shows) lies within 2 cm of that hit (a variant whose search discarded the pieces
/// would show the board behind them, farther away).
#[test]
fn every_variant_draws_the_pieces_where_they_are() {
    let _lock = gpu_lock();
    for spec in ["chess", "chess:material=mirror-mover", "cornell-sphere"] {
        let scene = scene::load(spec).unwrap();
        let pieces = scene.specular_objects();
        let shot = Shot::along_path(&scene, 1.0, SIZE);
        let bvh = scene::bvh::SceneBvh::build(&scene, 1.0);
        let on_piece: Vec<(usize, f32)> = (0..SIZE * SIZE)
            .filter_map(|i| {
                let (x, y) = ((i % SIZE) as f32 + 0.5, (i / SIZE) as f32 + 0.5);
                let d = shot.camera.ray_dir(x, y, SIZE, SIZE);
                let hit = bvh.closest_hit(shot.camera.eye, d, f32::INFINITY)?;
                pieces.contains(&hit.object).then_some((i as usize, hit.t))
            })
            .collect();
        assert!(on_piece.len() > 20, "{spec}: too few piece pixels");
        for mut t in height_maps::techniques() {
            assert!(t.supports(&scene), "{} on {spec}", t.id());
            small(t.as_mut());
            let shots = [Shot::along_path(&scene, 0.0, SIZE), shot];
            let image = render_shots(t.as_mut(), &scene, &shots);
            assert_eq!(image.non_finite_count(), 0, "{} on {spec}", t.id());
            let drawn = on_piece
                .iter()
                .filter(|&&(i, distance)| {
                    let p = image.pixels[i];
                    p[0] + p[1] + p[2] > 1e-3 && (p[3] - distance).abs() < 0.02
                })
                .count();
            assert!(
                drawn * 10 > on_piece.len() * 8,
                "{} on {spec}: {drawn} of {} piece pixels drawn at the piece",
                t.id(),
                on_piece.len()
            );
        }
    }
}

#[test]
fn deeper_paths_in_chess_change_only_the_pieces() {
    let _lock = gpu_lock();
    let scene = scene::load("chess").unwrap();
    let shot = [Shot::along_path(&scene, 0.0, 48)];
    let render = |depth: f64| {
        let mut t = height_maps::HeightMapsInChess::new();
        small(&mut t);
        t.set_param("depth", depth).unwrap();
        render_shots(&mut t, &scene, &shot)
    };
    let (one, four) = (render(1.0), render(4.0));
    let reference = testkit::reference("chess", &scene, shot[0], 0);
    let pieces = scene.specular_objects();
    let mut changed = 0;
    for (i, (a, b)) in one.pixels.iter().zip(&four.pixels).enumerate() {
        let differs = (0..3).any(|c| (a[c] - b[c]).abs() > 1e-5);
        let id = reference.object_ids[i];
        let on_piece = id >= 0 && pieces.contains(&(id as usize));
        if differs {
            changed += 1;
            // Silhouettes may differ by a pixel between the raster pass and the reference.
            let near_piece = on_piece
                || [-1i32, 1, -48, 48].iter().any(|o| {
                    let j = i as i32 + o;
                    j >= 0
                        && (j as usize) < reference.object_ids.len()
                        && pieces.contains(&(reference.object_ids[j as usize].max(0) as usize))
                        && reference.object_ids[j as usize] >= 0
                });
            assert!(near_piece, "pixel {i} off the pieces changed with depth");
        }
    }
    assert!(changed > 20, "depth changed only {changed} pixels");
}
