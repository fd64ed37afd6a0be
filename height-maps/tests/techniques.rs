//! The height-map techniques on the GPU: every variant renders finite, lit pixels on chess
//! (glass and a mirror mover) and cornell-sphere at two times; the in-chess tracer's one-bounce
//! image keeps the board where the pieces are not, and its deeper paths change the pieces.

use scene::Technique;
use testkit::{Shot, gpu_lock, render_shots};

const SIZE: u32 = 32;

fn small(t: &mut dyn Technique) {
    for (name, value) in [("resolution", 64.0), ("env_resolution", 16.0)] {
        t.set_param(name, value).unwrap();
    }
}

#[test]
fn every_variant_renders_finite_lit_pixels() {
    let _lock = gpu_lock();
    for spec in ["chess", "chess:material=mirror-mover", "cornell-sphere"] {
        let scene = scene::load(spec).unwrap();
        for mut t in height_maps::techniques() {
            assert!(t.supports(&scene), "{} on {spec}", t.id());
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
