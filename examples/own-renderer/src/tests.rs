//! The three passes in the renderer's own frame, each checked against the frame without it.

use super::*;
use glam::Vec3;

const SIZE: u32 = 128;

fn pixel(rgba: &[u8], (x, y): (u32, u32)) -> [u8; 4] {
    let i = ((y * SIZE + x) * 4) as usize;
    rgba[i..i + 4].try_into().unwrap()
}

/// The summed change of a pixel's rgb from `before` to `after`.
fn change(before: &[u8], after: &[u8], at: (u32, u32)) -> i32 {
    let (b, a) = (pixel(before, at), pixel(after, at));
    (0..3).map(|c| a[c] as i32 - b[c] as i32).sum()
}

/// The pixels of the ball's disc on screen (a pixel inside it) and around it (a pixel just
/// outside), by projecting points of its silhouette.
fn inside_and_outside(world: &World, ball: &Ball) -> (Vec<(u32, u32)>, Vec<(u32, u32)>) {
    let (_, right, up) = {
        let (view, _) = world.camera();
        let w = view.inverse();
        (
            w.z_axis.truncate(),
            w.x_axis.truncate(),
            w.y_axis.truncate(),
        )
    };
    let mut inside = Vec::new();
    let mut outside = Vec::new();
    for k in 0..8 {
        let angle = std::f32::consts::TAU * k as f32 / 8.0;
        let offset = right * angle.cos() + up * angle.sin();
        inside.push(world.pixel_of(ball.center + offset * ball.radius * 0.5, SIZE));
        outside.push(world.pixel_of(ball.center + offset * ball.radius * 1.35, SIZE));
    }
    (inside, outside)
}

/// The three families in one frame (the picture the closing note describes), and each one's
/// footprint: a glass ball changes its disc and nothing around it.
#[test]
fn three_families_in_the_renderers_own_frame() {
    let world = World::default();
    let mut renderer = Renderer::new(&world, SIZE).expect("a renderer (lavapipe will do)");
    let plain = renderer.frame(&world, Passes::NONE).unwrap();
    let all = renderer.frame(&world, Passes::ALL).unwrap();
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../target/examples/own-renderer.png");
    write_png(&path, &all, SIZE).unwrap();
    for (name, ball, passes) in [
        (
            "impostor",
            world.impostor,
            Passes {
                impostor: true,
                ..Passes::NONE
            },
        ),
        (
            "refraction",
            world.refractor,
            Passes {
                refraction: true,
                ..Passes::NONE
            },
        ),
    ] {
        let with = renderer.frame(&world, passes).unwrap();
        write_png(
            &path.with_file_name(format!("own-renderer-{name}.png")),
            &with,
            SIZE,
        )
        .unwrap();
        let (inside, outside) = inside_and_outside(&world, &ball);
        let changed = inside
            .iter()
            .filter(|&&p| pixel(&with, p) != pixel(&plain, p));
        assert_eq!(
            changed.count(),
            inside.len(),
            "{name}: the ball covers its disc"
        );
        for p in outside {
            assert_eq!(
                pixel(&with, p),
                pixel(&plain, p),
                "{name}: {p:?} is not the ball's"
            );
        }
        // Glass shows the renderer's lit world through it, not the clear colour.
        let centre = pixel(&with, world.pixel_of(ball.center, SIZE));
        assert!(
            centre[..3].iter().any(|&c| c > 40),
            "{name}: centre {centre:?}"
        );
    }
}

/// The impostor's ball moves in the renderer's frame: it is drawn where it now stands, and
/// where it stood shows the renderer's frame again.
#[test]
fn the_impostor_follows_its_ball() {
    let mut world = World::default();
    let mut renderer = Renderer::new(&world, SIZE).unwrap();
    let only_impostor = Passes {
        impostor: true,
        ..Passes::NONE
    };
    let before = world.impostor.center;
    world.impostor.center += Vec3::new(-0.6, 0.0, 0.2);
    renderer.move_impostor(world.impostor.center);
    let plain = renderer.frame(&world, Passes::NONE).unwrap();
    let moved = renderer.frame(&world, only_impostor).unwrap();
    let old = world.pixel_of(before + Vec3::X * 0.35, SIZE);
    assert_eq!(
        pixel(&moved, old),
        pixel(&plain, old),
        "nothing left where it stood"
    );
    let now = world.pixel_of(world.impostor.center, SIZE);
    assert_ne!(
        pixel(&moved, now),
        pixel(&plain, now),
        "drawn where it stands"
    );
    // Back where it started: the first frame, bit for bit.
    let first = {
        let world = World::default();
        let mut fresh = Renderer::new(&world, SIZE).unwrap();
        fresh.frame(&world, only_impostor).unwrap()
    };
    world.impostor.center = before;
    renderer.move_impostor(before);
    let back = renderer.frame(&world, only_impostor).unwrap();
    assert!(back == first, "back where it started");
}

/// The ball of smoke whitens what is behind it, is hidden where the front box stands before
/// it, leaves the rest of the frame alone, and thins where the floor cuts it.
#[test]
fn soft_volumes_over_the_renderers_depth() {
    let world = World::default();
    let mut renderer = Renderer::new(&world, SIZE).unwrap();
    let only_volumes = Passes {
        volumes: true,
        ..Passes::NONE
    };
    let without = renderer.frame(&world, Passes::NONE).unwrap();
    let with = renderer.frame(&world, only_volumes).unwrap();
    let ball = world.volumes[0];
    let gain = change(&without, &with, world.pixel_of(ball.center, SIZE));
    assert!(gain > 60, "the smoke whitens its centre by {gain}");
    let front = world.pixel_of(world.front_box.0 + Vec3::Z * world.front_box.1, SIZE);
    assert_eq!(
        pixel(&with, front),
        pixel(&without, front),
        "the box hides it"
    );
    assert_eq!(pixel(&with, (2, 2)), pixel(&without, (2, 2)), "far corner");
    // Just above the floor the smoke adds less than half a radius above it.
    let base = ball.center - Vec3::Y * (ball.center.y - 0.02);
    let near_floor = change(&without, &with, world.pixel_of(base, SIZE));
    let higher = change(&without, &with, world.pixel_of(base + Vec3::Y * 0.4, SIZE));
    assert!(
        (0..higher).contains(&near_floor),
        "thinner at the floor: {near_floor} at the cut, {higher} above it"
    );
}

/// A colour format the device cannot blend into is refused with a sentence, not a panic in a
/// later frame.
#[test]
fn an_unblendable_colour_format_is_refused() {
    let renderer = Renderer::new(&World::default(), 16).unwrap();
    let refused = SoftVolumePass::new(&renderer.world.ctx, wgpu::TextureFormat::R32Uint);
    let message = refused.err().expect("R32Uint cannot blend").to_string();
    assert!(message.contains("R32Uint"), "{message}");
}
