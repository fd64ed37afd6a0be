//! Properties of the interior-mapping ray cast (`interior_mapping::rooms`) against a brute
//! force search: every plane of every family with index in [-RANGE, RANGE] is intersected
//! in f64, the nearest one beyond the start (by the same `ROOM_EPS` rule) wins.

use glam::{IVec3, Vec3};
use interior_mapping::rooms::*;
use proptest::prelude::*;
use testkit::strategies::{direction_with_zeros, vec3_in};

const RANGE: i32 = 3000;

/// Brute force: (family, t) of the nearest plane, or None when no plane is hit.
fn brute(origin: Vec3, dir: Vec3, size: Vec3, disp: Vec3, seed: u32) -> Option<(u32, f64)> {
    let u = origin / size;
    let du = dir / size;
    let mut best: Option<(u32, f64)> = None;
    for a in 0..3usize {
        if du[a].abs() < ROOM_FLAT {
            continue;
        }
        for k in -RANGE..=RANGE {
            {
                let p = room_plane_pos(a as u32, k, disp[a], seed);
                let beyond = if du[a] > 0.0 {
                    p > u[a] + ROOM_EPS
                } else {
                    p < u[a] - ROOM_EPS
                };
                if !beyond {
                    continue;
                }
                let t = (p as f64 - u[a] as f64) / du[a] as f64;
                if best.is_none_or(|(_, bt)| t < bt) {
                    best = Some((a as u32, t));
                }
            }
        }
    }
    best
}

fn check(origin: Vec3, dir: Vec3, size: Vec3, disp: Vec3, seed: u32) -> Result<(), TestCaseError> {
    let hit = cast_rooms(origin, dir, size, disp, seed);
    prop_assert!(
        hit.t.is_finite() && hit.point.is_finite(),
        "non-finite hit {hit:?}"
    );
    match brute(origin, dir, size, disp, seed) {
        None => prop_assert!(hit.t >= 1e29, "hit {hit:?} where brute force finds none"),
        Some((family, t)) => {
            let tol = 1e-4 * (1.0 + t.abs());
            prop_assert!(
                (hit.t as f64 - t).abs() <= tol,
                "t {} vs brute {t} (family {family}, twin {hit:?})",
                hit.t
            );
            if family != hit.family {
                // Only a near tie may pick the other family.
                let other = brute_family(origin, dir, size, disp, seed, hit.family);
                prop_assert!(
                    other.is_some_and(|o| (o - t).abs() <= tol),
                    "family {} vs brute {family}",
                    hit.family
                );
            }
            prop_assert!(hit.t > 0.0);
        }
    }
    Ok(())
}

fn brute_family(
    origin: Vec3,
    dir: Vec3,
    size: Vec3,
    disp: Vec3,
    seed: u32,
    family: u32,
) -> Option<f64> {
    let mut d = Vec3::ZERO;
    d[family as usize] = dir[family as usize];
    brute(origin, d, size, disp, seed).map(|(_, t)| t)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// Regular grid, origins anywhere (negative coordinates included), any room size.
    #[test]
    fn nearest_plane_matches_brute_force(origin in vec3_in(-200.0, 200.0), dir in direction_with_zeros(),
                                         size in vec3_in(0.3, 6.0), seed in any::<u32>()) {
        check(origin, dir, size, Vec3::ZERO, seed)?;
    }

    /// Displaced walls never skip a wall (two candidates per family suffice).
    #[test]
    fn displaced_walls_never_skip_a_wall(origin in vec3_in(-200.0, 200.0), dir in direction_with_zeros(),
                                         size in vec3_in(0.3, 6.0), disp in vec3_in(0.0, MAX_DISPLACEMENT),
                                         seed in any::<u32>()) {
        check(origin, dir, size, disp, seed)?;
    }

    /// A ray parallel to a family never hits it and stays finite.
    #[test]
    fn parallel_rays_are_finite(origin in vec3_in(-50.0, 50.0), dir in direction_with_zeros(), size in vec3_in(0.3, 6.0),
                                axis in 0usize..3) {
        let mut d = dir;
        d[axis] = 0.0;
        prop_assume!(d.length() > 1e-3);
        let hit = cast_rooms(origin, d, size, Vec3::ZERO, 0);
        prop_assert!(hit.t.is_finite() && hit.point.is_finite());
        prop_assert!(hit.family as usize != axis);
        prop_assert!((hit.point[axis] - origin[axis]).abs() <= 1e-4 * (1.0 + origin[axis].abs()));
        check(origin, d, size, Vec3::ZERO, 0)?;
    }

    /// Camera inside a building: the first plane is a face of the room holding the eye, and
    /// the hit point lies on that room's boundary.
    #[test]
    fn camera_inside_hits_its_own_room(room in (-20i32..20, -20i32..20, -20i32..20),
                                       frac in vec3_in(0.05, 0.95), dir in direction_with_zeros(),
                                       size in vec3_in(0.5, 5.0), disp in vec3_in(0.0, MAX_DISPLACEMENT)) {
        let room = IVec3::new(room.0, room.1, room.2);
        // The eye somewhere inside room `room` of the displaced grid.
        let mut eye = Vec3::ZERO;
        for a in 0..3 {
            let lo = room_plane_pos(a as u32, room[a], disp[a], 7);
            let hi = room_plane_pos(a as u32, room[a] + 1, disp[a], 7);
            eye[a] = (lo + frac[a] * (hi - lo)) * size[a];
        }
        let hit = cast_rooms(eye, dir, size, disp, 7);
        prop_assert_eq!(hit.room, room);
        let a = hit.family as usize;
        let expected = if dir[a] > 0.0 { room[a] + 1 } else { room[a] };
        prop_assert_eq!(hit.plane, expected);
        check(eye, dir, size, disp, 7)?;
    }
}

/// Exactly axis-aligned rays and a start exactly on a plane (a facade on a wall plane).
#[test]
fn start_on_a_plane_skips_it() {
    let size = Vec3::new(2.5, 3.0, 4.0);
    let hit = cast_rooms(Vec3::new(5.0, 1.0, 1.0), Vec3::X, size, Vec3::ZERO, 0);
    assert_eq!((hit.family, hit.plane), (FAMILY_X, 3));
    assert!((hit.t - 2.5).abs() < 1e-5);
    let hit = cast_rooms(Vec3::new(5.0, 1.0, 1.0), -Vec3::X, size, Vec3::ZERO, 0);
    assert_eq!((hit.family, hit.plane, hit.room.x), (FAMILY_X, 1, 1));
    let hit = cast_rooms(
        Vec3::new(-5.0, -6.0, 1.0),
        Vec3::new(0.0, -1.0, 0.0),
        size,
        Vec3::ZERO,
        0,
    );
    assert_eq!((hit.family, hit.plane, hit.room.y), (FAMILY_Y, -3, -3));
    let hit = cast_rooms(Vec3::ONE, Vec3::ZERO, size, Vec3::ZERO, 0);
    assert!(hit.t.is_finite() && hit.point.is_finite());
}

// ---------------------------------------------------------------------------------------------
// Cube-map interiors (`cubemap_room`, the engine baseline)
// ---------------------------------------------------------------------------------------------

/// `cubemap_room` against `cast_rooms` on the regular grid: the same ray parameter (1e-4
/// relative), the same room, the same hit point, the same family unless two families tie.
fn check_cubemap_agrees(origin: Vec3, dir: Vec3, size: Vec3) -> Result<(), TestCaseError> {
    let cube = cubemap_room(origin, dir, size, 1, 0);
    let cast = cast_rooms(origin, dir, size, Vec3::ZERO, 0);
    prop_assert!(cube.t.is_finite() && cube.point.is_finite() && cube.lookup.is_finite());
    let tol = 1e-4 * (1.0 + cast.t.abs());
    prop_assert!(
        (cube.t - cast.t).abs() <= tol,
        "t {} vs cast_rooms {} ({cube:?} vs {cast:?})",
        cube.t,
        cast.t
    );
    prop_assert_eq!(cube.room, cast.room, "{:?} vs {:?}", cube, cast);
    let scale = 1e-4 * (1.0 + cast.point.abs().max_element());
    prop_assert!(
        (cube.point - cast.point).abs().max_element() <= scale,
        "{cube:?} vs {cast:?}"
    );
    if cube.family != cast.family {
        // A tie: the ray leaves through an edge of the room, both faces at the same t.
        let other = brute_family(origin, dir, size, Vec3::ZERO, 0, cube.family);
        prop_assert!(
            other.is_some_and(|t| (t - cast.t as f64).abs() <= tol as f64),
            "family {} vs {}",
            cube.family,
            cast.family
        );
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// From inside a room the cube map's box exit is the plane the thesis's ray cast hits:
    /// on a grid of box rooms the two techniques see the same surface point.
    #[test]
    fn cubemap_room_exit_is_the_plane_cast_rooms_hits(
        room in (-30i32..30, -30i32..30, -30i32..30), frac in vec3_in(0.01, 0.99),
        dir in direction_with_zeros(), size in vec3_in(0.3, 6.0),
    ) {
        let origin = (Vec3::new(room.0 as f32, room.1 as f32, room.2 as f32) + frac) * size;
        check_cubemap_agrees(origin, dir, size)?;
    }

    /// From a facade lying on a wall plane (where the shader starts), the room is the one
    /// ahead of the ray, and the exit agrees with the ray cast (which skips the start plane).
    #[test]
    fn cubemap_room_from_a_facade_enters_the_room_ahead(
        room in (-30i32..30, -30i32..30, -30i32..30), frac in vec3_in(0.01, 0.99),
        dir in direction_with_zeros(), size in vec3_in(0.3, 6.0), axis in 0usize..3,
    ) {
        // The ray must leave the facade plane (the shader starts only on front faces).
        let mut dir = dir;
        if dir[axis].abs() < 0.05 {
            dir[axis] = if dir[axis].is_sign_negative() { -0.5 } else { 0.5 };
            dir = dir.normalize();
        }
        let mut origin = (Vec3::new(room.0 as f32, room.1 as f32, room.2 as f32) + frac) * size;
        origin[axis] = (origin[axis] / size[axis]).round() * size[axis];
        let cube = cubemap_room(origin, dir, size, 1, 0);
        let ahead = (origin[axis] / size[axis]).round() as i32 - i32::from(dir[axis] < 0.0);
        prop_assert_eq!(cube.room[axis], ahead);
        check_cubemap_agrees(origin, dir, size)?;
    }

    /// Without variation the lookup points from the room's centre to the exit point, and the
    /// baked cube map shows there exactly the surface and texture coordinate the thesis's
    /// textures show at that point (`textures::room_surface_seen` vs `plane_uv`).
    #[test]
    fn cubemap_lookup_sees_the_exit_surface(
        room in (-30i32..30, -30i32..30, -30i32..30), frac in vec3_in(0.01, 0.99),
        dir in direction_with_zeros(), size in vec3_in(0.3, 6.0),
    ) {
        let origin = (Vec3::new(room.0 as f32, room.1 as f32, room.2 as f32) + frac) * size;
        let cube = cubemap_room(origin, dir, size, 1, 0);
        let centre = cube.room.as_vec3() + Vec3::splat(0.5);
        let to_exit = (cube.point / size - centre).normalize();
        prop_assert!(cube.lookup.normalize().dot(to_exit) > 1.0 - 1e-5, "{cube:?}");
        let (surface, s, t) = interior_mapping::textures::room_surface_seen(cube.lookup);
        let expected = match cube.family {
            FAMILY_X => interior_mapping::textures::RoomSurface::WallX,
            FAMILY_Y if dir.y > 0.0 => interior_mapping::textures::RoomSurface::Ceiling,
            FAMILY_Y => interior_mapping::textures::RoomSurface::Floor,
            _ => interior_mapping::textures::RoomSurface::WallZ,
        };
        // Near an edge of the room two faces meet: either may be chosen.
        let edge = {
            let a = (cube.point / size - centre).abs();
            let mut sorted = [a.x, a.y, a.z];
            sorted.sort_by(f32::total_cmp);
            sorted[2] - sorted[1] < 1e-3
        };
        if !edge {
            prop_assert_eq!(surface, expected);
            let uv = plane_uv(cube.family, cube.point / size);
            let wrap = |x: f32| x - x.floor();
            let close = |a: f32, b: f32| { let d = (a - b).abs(); d.min(1.0 - d) < 1e-3 };
            prop_assert!(close(s, wrap(uv.x)) && close(t, wrap(uv.y)),
                "cube ({s}, {t}) vs texture ({}, {})", wrap(uv.x), wrap(uv.y));
        }
    }

    /// Variation: the atlas index is below the count, each mirroring only flips the sign of
    /// a horizontal lookup component, and the exit itself does not change.
    #[test]
    fn cubemap_variation_only_picks_and_mirrors(
        origin in vec3_in(-100.0, 100.0), dir in direction_with_zeros(), size in vec3_in(0.3, 6.0),
        variants in 2u32..8, seed in any::<u32>(),
    ) {
        let plain = cubemap_room(origin, dir, size, 1, seed);
        let varied = cubemap_room(origin, dir, size, variants, seed);
        prop_assert_eq!(plain.atlas, 0);
        prop_assert!(varied.atlas < variants);
        prop_assert_eq!((plain.t, plain.point, plain.room), (varied.t, varied.point, varied.room));
        prop_assert_eq!(varied.lookup.abs(), plain.lookup.abs());
        prop_assert_eq!(varied.lookup.y, plain.lookup.y);
    }
}

/// Across many rooms every cube map of the atlas and every mirroring is used.
#[test]
fn cubemap_variation_uses_every_room_and_mirroring() {
    let mut atlas = [0u32; 4];
    let mut mirrors = [0u32; 4];
    for i in 0..400 {
        let room = IVec3::new(i % 20, i / 20, 3);
        let h = room_hash(room, 11);
        atlas[(h % 4) as usize] += 1;
        let m = usize::from(h & MIRROR_X_BIT != 0) + 2 * usize::from(h & MIRROR_Z_BIT != 0);
        mirrors[m] += 1;
    }
    assert!(atlas.iter().all(|&n| n > 50), "atlas use {atlas:?}");
    assert!(mirrors.iter().all(|&n| n > 50), "mirroring use {mirrors:?}");
}
