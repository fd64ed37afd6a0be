//! Properties of the board grid and its nearest-piece search (`scene::multi_object::grid`), on
//! worlds of disjoint spheres whose exact hits are known: walked to the end, the grid finds
//! the same nearest piece as testing every piece; the paper's first-square shortcut searches
//! exactly the first occupied cell; every piece is listed in every cell its footprint reaches.

mod grid_common;

use glam::{IVec2, Vec2};
use grid_common::*;
use proptest::prelude::*;
use scene::multi_object::grid::{
    ALL_CELLS, BoardGrid, CELL_CAPACITY, EMPTY, nearest_piece, nearest_piece_brute,
};

fn config() -> ProptestConfig {
    ProptestConfig {
        cases: 1024,
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

proptest! {
    #![proptest_config(config())]

    /// The full walk agrees with the brute-force search: same piece, same ray parameter.
    #[test]
    fn the_walk_finds_the_nearest_piece(
        (spheres, o, d) in spheres().prop_flat_map(ray_among),
        skip_first in any::<bool>(),
    ) {
        let grid = grid_of(&spheres);
        let skip = if skip_first { 0 } else { EMPTY };
        let hit = |p: u32| sphere_hit(&spheres[p as usize], o, d);
        let walked = nearest_piece(&grid, o, d, skip, ALL_CELLS, hit);
        let brute = nearest_piece_brute(spheres.len() as u32, skip, hit);
        prop_assert_eq!(walked, brute);
        if let Some((p, _)) = walked {
            prop_assert!(p != skip);
        }
    }

    /// The paper's shortcut (first occupied cell only) returns a piece listed in the first
    /// occupied cell the ray meets (or nothing), and whenever the true nearest piece is listed
    /// there, exactly it.
    #[test]
    fn the_first_square_shortcut_searches_the_first_occupied_cell(
        (spheres, o, d) in spheres().prop_flat_map(ray_among),
    ) {
        let grid = grid_of(&spheres);
        let hit = |p: u32| sphere_hit(&spheres[p as usize], o, d);
        let first = nearest_piece(&grid, o, d, EMPTY, 1, hit);
        let brute = nearest_piece_brute(spheres.len() as u32, EMPTY, hit);
        let Some(cell) = first_occupied_cell(&grid, o, d) else {
            prop_assert_eq!(first, None);
            return Ok(());
        };
        if let Some((p, _)) = first {
            prop_assert!(cell.contains(&p), "piece {} is not in the first occupied cell", p);
        }
        if let Some((p, t)) = brute
            && cell.contains(&p)
        {
            prop_assert_eq!(first, Some((p, t)));
        }
    }

    /// Each piece is listed in every cell its footprint overlaps, at most CELL_CAPACITY per
    /// cell, and nowhere else.
    #[test]
    fn pieces_are_listed_in_the_cells_they_reach(spheres in spheres()) {
        let prints = footprints(&spheres);
        let grid = BoardGrid::build(&prints).unwrap();
        prop_assert!(grid.cell > 0.0);
        for j in 0..grid.count.y {
            for i in 0..grid.count.x {
                let cell_lo = grid.min + grid.cell * IVec2::new(i, j).as_vec2();
                let cell_hi = cell_lo + Vec2::splat(grid.cell);
                let slots = grid.cells[(j * grid.count.x + i) as usize];
                prop_assert!(slots.len() == CELL_CAPACITY);
                for (p, (lo, hi)) in prints.iter().enumerate() {
                    let listed = slots.contains(&(p as u32));
                    let strictly_inside = lo.x < cell_hi.x - 1e-5 && hi.x > cell_lo.x + 1e-5
                        && lo.y < cell_hi.y - 1e-5 && hi.y > cell_lo.y + 1e-5;
                    let strictly_outside = lo.x > cell_hi.x + 1e-5 || hi.x < cell_lo.x - 1e-5
                        || lo.y > cell_hi.y + 1e-5 || hi.y < cell_lo.y - 1e-5;
                    if strictly_inside {
                        prop_assert!(listed, "piece {} missing from cell ({}, {})", p, i, j);
                    }
                    if strictly_outside {
                        prop_assert!(!listed, "piece {} listed in far cell ({}, {})", p, i, j);
                    }
                }
            }
        }
    }
}

/// The pieces listed in the first cell along the ray that lists any (the walk of
/// `gpu::prelude::grid_walk`, itself tested in `gpu`).
fn first_occupied_cell(grid: &BoardGrid, o: glam::Vec3, d: glam::Vec3) -> Option<Vec<u32>> {
    let mut walk = gpu::prelude::grid_walk(o, d, grid.min, grid.cell, grid.count);
    while !walk.done() {
        let slots = grid.cells[(walk.cell.y * grid.count.x + walk.cell.x) as usize];
        let listed: Vec<u32> = slots.into_iter().filter(|p| *p != EMPTY).collect();
        if !listed.is_empty() {
            return Some(listed);
        }
        walk = gpu::prelude::grid_walk_next(walk, grid.count);
    }
    None
}

/// A ray that passes beside every piece finds none; one straight down onto a piece finds it.
#[test]
fn misses_and_direct_hits() {
    let spheres = vec![
        Sphere {
            centre: glam::Vec3::new(0.0, 0.2, 0.0),
            radius: 0.1,
        },
        Sphere {
            centre: glam::Vec3::new(0.5, 0.2, 0.0),
            radius: 0.1,
        },
    ];
    let grid = grid_of(&spheres);
    let hit = |p: u32| {
        sphere_hit(
            &spheres[p as usize],
            glam::Vec3::new(0.25, 1.0, 0.0),
            -glam::Vec3::Y,
        )
    };
    assert_eq!(
        nearest_piece(
            &grid,
            glam::Vec3::new(0.25, 1.0, 0.0),
            -glam::Vec3::Y,
            EMPTY,
            ALL_CELLS,
            hit
        ),
        None
    );
    let o = glam::Vec3::new(0.5, 1.0, 0.0);
    let hit = |p: u32| sphere_hit(&spheres[p as usize], o, -glam::Vec3::Y);
    let (p, t) = nearest_piece(&grid, o, -glam::Vec3::Y, EMPTY, ALL_CELLS, hit).unwrap();
    assert_eq!(p, 1);
    assert!((t - 0.7).abs() < 1e-5);
    // Skipping the piece the ray left: nothing else is below.
    assert_eq!(
        nearest_piece(&grid, o, -glam::Vec3::Y, 1, ALL_CELLS, hit),
        None
    );
}

/// Pieces crowded closer than the capacity allows are separated by halving the cells; the
/// same footprint repeated (overlapping pieces) cannot be.
#[test]
fn crowded_pieces_shrink_the_cells_or_are_refused() {
    let small = |x: f32, z: f32| (Vec2::new(x, z), Vec2::new(x + 0.1, z + 0.1));
    let row: Vec<_> = (0..8).map(|i| small(i as f32 * 0.101, 0.0)).collect();
    let grid = BoardGrid::build(&row).unwrap();
    assert!(
        grid.cells
            .iter()
            .all(|c| c.iter().filter(|p| **p != EMPTY).count() <= CELL_CAPACITY)
    );
    let same = vec![small(0.0, 0.0); CELL_CAPACITY + 1];
    assert!(BoardGrid::build(&same).is_err());
}

/// A piece listed in an earlier cell whose hit lies beyond that cell must not hide a nearer
/// piece of a later cell: the walk stops only at a hit within the current cell. (Found by a
/// search over random worlds against a walk that stopped at the first cell with any hit.)
#[test]
fn a_far_hit_of_an_earlier_cell_does_not_hide_a_nearer_piece() {
    use glam::Vec3;
    let spheres = vec![
        Sphere {
            centre: Vec3::new(0.0, 0.382_228_9, 0.0),
            radius: 0.15,
        },
        Sphere {
            centre: Vec3::new(-0.171_234_61, 0.226_252_62, -0.054_743_41),
            radius: 0.048_669_95,
        },
        Sphere {
            centre: Vec3::new(-0.71, 0.2, -0.71),
            radius: 0.03,
        },
    ];
    let o = Vec3::new(-0.518_437_2, 0.116_742_6, -0.345_342);
    let d = Vec3::new(0.711_324_63, 0.262_514_56, 0.651_999_5);
    let grid = grid_of(&spheres);
    let hit = |p: u32| sphere_hit(&spheres[p as usize], o, d);
    let (p, t) = nearest_piece(&grid, o, d, EMPTY, ALL_CELLS, hit).unwrap();
    assert_eq!(
        p, 1,
        "the small sphere at t = {t} is nearer than the big one's 0.597"
    );
    assert_eq!(Some((p, t)), nearest_piece_brute(3, EMPTY, hit));
}
