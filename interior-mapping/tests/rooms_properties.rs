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
