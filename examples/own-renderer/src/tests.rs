//! The six passes in the renderer's own frame, each checked against the frame without it.

use super::*;
use glam::Vec3;

const SIZE: u32 = 128;

/// A pixel: column, row from the top.
type Pixel = (u32, u32);

fn pixel(rgba: &[u8], (x, y): Pixel) -> [u8; 4] {
    let i = ((y * SIZE + x) * 4) as usize;
    rgba[i..i + 4].try_into().unwrap()
}

/// The summed change of a pixel's rgb from `before` to `after`.
fn change(before: &[u8], after: &[u8], at: Pixel) -> i32 {
    let (b, a) = (pixel(before, at), pixel(after, at));
    (0..3).map(|c| a[c] as i32 - b[c] as i32).sum()
}

/// The pixels of the ball's disc on screen (a pixel inside it) and around it (a pixel just
/// outside), by projecting points of its silhouette.
fn inside_and_outside(world: &World, ball: &Ball) -> (Vec<Pixel>, Vec<Pixel>) {
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

/// The six families in one frame (the picture the closing note describes), and each glass
/// ball's footprint: it changes its disc and nothing around it.
#[test]
fn six_families_in_the_renderers_own_frame() {
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
        assert!(shows_the_world(centre), "{name}: centre {centre:?}");
    }
}

/// Whether a pixel shows the renderer's lit world rather than its clear colour (sRGB8 about
/// (39, 39, 48)): the floor and the walls are much brighter in red or green.
fn shows_the_world(rgba: [u8; 4]) -> bool {
    rgba[0] > 70 || rgba[1] > 70
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

/// The pixels (inclusive, one pixel of margin) that a pawn standing at `base` covers at most:
/// the screen bounds of its bounding box's corners.
fn pawn_rect(world: &World, base: Vec3) -> [Pixel; 2] {
    let (mut lo, mut hi) = ((u32::MAX, u32::MAX), (0, 0));
    for corner in 0..8 {
        let pick = |bit: u32, a: f32, b: f32| if corner & bit == 0 { a } else { b };
        let r = 0.4;
        let p = base + Vec3::new(pick(1, -r, r), pick(2, 0.0, Pawn::HEIGHT), pick(4, -r, r));
        let (x, y) = world.pixel_of(p, SIZE);
        lo = (lo.0.min(x), lo.1.min(y));
        hi = (hi.0.max(x), hi.1.max(y));
    }
    [
        (lo.0.saturating_sub(1), lo.1.saturating_sub(1)),
        (hi.0 + 1, hi.1 + 1),
    ]
}

/// Every pixel that differs between `a` and `b`.
fn changed_pixels(a: &[u8], b: &[u8]) -> Vec<Pixel> {
    (0..SIZE * SIZE)
        .map(|i| (i % SIZE, i / SIZE))
        .filter(|&p| pixel(a, p) != pixel(b, p))
        .collect()
}

/// Whether `p` lies in one of `rects`.
fn within(rects: &[[Pixel; 2]], p: Pixel) -> bool {
    rects
        .iter()
        .any(|[lo, hi]| (lo.0..=hi.0).contains(&p.0) && (lo.1..=hi.1).contains(&p.1))
}

/// Points on a pawn's axis, inside its silhouette (body, collar, head).
fn pawn_axis(base: Vec3) -> [Vec3; 3] {
    [0.3, 0.5, 0.8].map(|t| base + Vec3::Y * Pawn::HEIGHT * t)
}

/// The pawns of both height-field families: each pass covers its pawns' axes with glass that
/// shows the renderer's lit world, and changes nothing outside their screen bounds.
#[test]
fn the_pawns_change_their_own_pixels_only() {
    let world = World::default();
    let mut renderer = Renderer::new(&world, SIZE).unwrap();
    let plain = renderer.frame(&world, Passes::NONE).unwrap();
    let cases = [
        (
            "refractor-maps",
            world.pawns.map(|p| p.base).to_vec(),
            Passes {
                refractor_maps: true,
                ..Passes::NONE
            },
        ),
        (
            "height-maps",
            vec![world.height_pawn.base],
            Passes {
                height_maps: true,
                ..Passes::NONE
            },
        ),
    ];
    for (name, bases, passes) in cases {
        let with = renderer.frame(&world, passes).unwrap();
        let rects: Vec<_> = bases.iter().map(|&b| pawn_rect(&world, b)).collect();
        let changed = changed_pixels(&plain, &with);
        let stray: Vec<_> = changed.iter().filter(|&&p| !within(&rects, p)).collect();
        assert!(
            stray.is_empty(),
            "{name}: changed outside its pawns: {stray:?}"
        );
        for &base in &bases {
            for point in pawn_axis(base) {
                let at = world.pixel_of(point, SIZE);
                let (before, after) = (pixel(&plain, at), pixel(&with, at));
                assert_ne!(before, after, "{name}: the pawn covers {at:?}");
                assert!(shows_the_world(after), "{name}: {at:?} is {after:?}");
            }
        }
    }
}

/// Rays that leave one pawn find the other: paths through the grid change the pawns' pixels
/// from the same paths taking the environment when they leave a pawn (same depth, same
/// environment impostor), and only theirs.
#[test]
fn the_refractor_map_pawns_see_each_other() {
    let world = World::default();
    let mut renderer = Renderer::new(&world, SIZE).unwrap();
    let only_pawns = Passes {
        refractor_maps: true,
        ..Passes::NONE
    };
    let between = renderer.frame(&world, only_pawns).unwrap();
    let alone = refractor_maps::Bounces::Alone { depth: 4 };
    renderer.set_pawn_bounces(&world, alone).unwrap();
    let each_alone = renderer.frame(&world, only_pawns).unwrap();
    let rects: Vec<_> = world
        .pawns
        .iter()
        .map(|p| pawn_rect(&world, p.base))
        .collect();
    let changed = changed_pixels(&each_alone, &between);
    assert!(changed.iter().all(|&p| within(&rects, p)));
    for rect in &rects {
        let seen = changed.iter().filter(|&&p| within(&[*rect], p)).count();
        assert!(seen >= 3, "each pawn shows the other in {seen} pixels");
    }
}

/// The pixels of two frames that differ by more than two sRGB8 steps in some channel.
fn pixels_apart(a: &[u8], b: &[u8]) -> usize {
    let apart = |(p, q): (&[u8], &[u8])| p.iter().zip(q).any(|(x, y)| x.abs_diff(*y) > 2);
    a.chunks(4)
        .zip(b.chunks(4))
        .filter(|&pair| apart(pair))
        .count()
}

/// How a test moves one object: in the renderer, by an offset from where `World::default`
/// has it, and in a world.
type Mover = (fn(&mut Renderer, &World, Vec3), fn(&mut World, Vec3));

/// Each moving object of the pawns and the building, moved in the renderer's frame, is drawn
/// as a renderer whose world has it there from the start draws it: the building's records, the
/// pawns' piece table and grid and the height-map pawn's environment impostor follow it (each
/// left behind fails this test; the refractor-map pawns' impostor follows too, but their
/// localized search barely sees where it is taken from). Moved back, the frame is the first
/// one, bit for bit.
#[test]
fn moved_objects_are_drawn_where_they_stand() {
    let world = World::default();
    let mut renderer = Renderer::new(&world, SIZE).unwrap();
    let offset = Vec3::new(0.9, 0.0, 0.2);
    let only = |passes: fn(&mut Passes)| {
        let mut only = Passes::NONE;
        passes(&mut only);
        only
    };
    let cases: [(&str, Passes, Mover); 3] = [
        (
            "refractor-map pawn",
            only(|p| p.refractor_maps = true),
            (
                |r, w, by| r.move_pawn(1, w.pawns[1].base + by),
                |w, by| w.pawns[1].base += by,
            ),
        ),
        (
            "height-map pawn",
            only(|p| p.height_maps = true),
            (
                |r, w, by| r.move_height_pawn(w.height_pawn.base + by),
                |w, by| w.height_pawn.base += by,
            ),
        ),
        (
            "building",
            only(|p| p.interiors = true),
            (
                |r, w, by| r.move_house(w.house.corner - by),
                |w, by| w.house.corner -= by,
            ),
        ),
    ];
    for (name, passes, (move_it, move_in_world)) in cases {
        let first = renderer.frame(&world, passes).unwrap();
        move_it(&mut renderer, &world, offset);
        let moved = renderer.frame(&world, passes).unwrap();
        let mut there = World::default();
        move_in_world(&mut there, offset);
        let fresh = Renderer::new(&there, SIZE)
            .unwrap()
            .frame(&there, passes)
            .unwrap();
        assert!(moved != first, "{name}: it moved");
        // Maps and searches made where the object first stood round differently: a few
        // speckles (a chord that grazes total internal reflection) apart, no more.
        let apart = pixels_apart(&moved, &fresh);
        assert!(
            apart <= 8,
            "{name}: {apart} pixels from a renderer that had it there"
        );
        move_it(&mut renderer, &world, Vec3::ZERO);
        let back = renderer.frame(&world, passes).unwrap();
        assert!(back == first, "{name}: back where it started");
    }
}

/// What a pass cannot draw is refused with a sentence when it is made: paths of no interface
/// or past the tracer's stack, no object, a mesh whose normals do not match its positions.
#[test]
fn passes_refuse_what_they_cannot_draw() {
    let world = World::default();
    let renderer = Renderer::new(&world, 16).unwrap();
    let ctx = &renderer.world.ctx;
    let formats = TargetFormats::new(COLOR_FORMAT, DEPTH_FORMAT);
    let pawn = |mesh: gpu::HostedMesh| refractor_maps::Piece {
        mesh,
        surface: Surface::Glass { ior: 1.5 },
        host_index: 6,
        position: Vec3::ZERO,
    };
    let make = |pieces: &[refractor_maps::Piece], depth| {
        let bounces = refractor_maps::Bounces::Multi { depth };
        RefractorMapsPass::new(ctx, pieces, bounces, formats, (32, 32)).err()
    };
    let whole = [pawn(Pawn::mesh())];
    for depth in [0, 9] {
        let refused = make(&whole, depth).expect("refused").to_string();
        assert!(refused.contains("depth"), "{refused}");
    }
    assert!(make(&[], 4).is_some(), "no piece");
    let mut torn = Pawn::mesh();
    torn.normals.pop();
    let refused = make(&[pawn(torn)], 4).expect("refused").to_string();
    assert!(refused.contains("normals"), "{refused}");
    assert!(
        make(&whole, 4).is_none(),
        "a whole pawn at depth 4 is drawn"
    );
}

/// The building's screen bounds (inclusive, one pixel of margin).
fn house_rect(world: &World) -> [Pixel; 2] {
    let house = world.house;
    let (mut lo, mut hi) = ((u32::MAX, u32::MAX), (0, 0));
    for corner in 0..8 {
        let pick = |bit: u32, size: f32| if corner & bit == 0 { 0.0 } else { size };
        let offset = Vec3::new(
            pick(1, house.size.x),
            pick(2, house.size.y),
            pick(4, house.size.z),
        );
        let (x, y) = world.pixel_of(house.corner + offset, SIZE);
        lo = (lo.0.min(x), lo.1.min(y));
        hi = (hi.0.max(x), hi.1.max(y));
    }
    [
        (lo.0.saturating_sub(1), lo.1.saturating_sub(1)),
        (hi.0 + 1, hi.1 + 1),
    ]
}

/// The building through interior mapping: it covers its facade's middle, changes nothing
/// outside its screen bounds, and its windows show rooms of many colours; the same textured
/// rooms behind glass that reflects the renderer's world (asked through `gpu::DrawScene`)
/// differ from them inside the building only.
#[test]
fn the_building_shows_rooms_behind_its_windows() {
    let world = World::default();
    let mut renderer = Renderer::new(&world, SIZE).unwrap();
    let only_house = Passes {
        interiors: true,
        ..Passes::NONE
    };
    let plain = renderer.frame(&world, Passes::NONE).unwrap();
    let varied = renderer.frame(&world, only_house).unwrap();
    let rect = [house_rect(&world)];
    let changed = changed_pixels(&plain, &varied);
    assert!(
        changed.iter().all(|&p| within(&rect, p)),
        "outside the building"
    );
    let house = world.house;
    let middle = world.pixel_of(house.corner + house.size * Vec3::new(0.5, 0.5, 1.0), SIZE);
    assert!(changed.contains(&middle), "the facade covers {middle:?}");
    let colours: std::collections::HashSet<[u8; 4]> =
        changed.iter().map(|&p| pixel(&varied, p)).collect();
    assert!(colours.len() > 40, "{} colours", colours.len());
    renderer
        .set_interiors(&world, interior_mapping::Variant::Textured)
        .unwrap();
    let textured = renderer.frame(&world, only_house).unwrap();
    renderer
        .set_interiors(&world, interior_mapping::Variant::Exterior)
        .unwrap();
    let reflecting = renderer.frame(&world, only_house).unwrap();
    let reflected = changed_pixels(&textured, &reflecting);
    assert!(reflected.len() >= 10, "{} pixels reflect", reflected.len());
    assert!(reflected.iter().all(|&p| within(&rect, p)));
}
