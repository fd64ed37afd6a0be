//! How often the search from outside (section 4.1) fails on each chess piece, and how much of
//! that is the star-shaped assumption, measured, not asserted away: rays aimed at each piece
//! kind are searched in its refractor distance map (the Rust twin,
//! `gpu::distance_map::hit_from_outside`, on a map ray-cast from the mesh on the CPU, nearest
//! surface per texel as the GPU's depth test keeps) and compared with the exact first hit on
//! the mesh. An exact hit point that is not the nearest surface from the centre in its own
//! direction is *hidden*: no search in the map can find it (the star-shaped assumption fails
//! there). The other hits fail when the search finds nothing or a point farther than 2 mm
//! away (the map's texels, grazing rays, the epsilon test). The rates are printed per kind
//! (`cargo test -p rtapprox-refractor-maps --test star_shape -- --nocapture`). The test bounds the
//! search's failures on the hits it can find (missed, off by more than 2 mm) and its false
//! hits per kind, at the measured rates rounded up ([`MAX_MISSED`], [`MAX_FAR`],
//! [`MAX_FALSE`]): a search that finds nothing, or stops short of the surface, fails them.
//! Of the geometry it asserts that the knight, whose jaw overhangs its throat, hides more of
//! its hits than the pawn.

use glam::{Vec2, Vec3};
use gpu::distance_map::{CubeDistanceMap, Method, hit_from_outside};
use scene::builtin::chess::{PieceKind, SQUARE};

const MAP_SIZE: u32 = 128;
const RAYS: u32 = 3000;
const TOLERANCE: f32 = 2e-3;
/// Bounds per kind on the shares of the search's failures, the measured rates (README, "The
/// search from outside on the chess pieces") rounded up.
const MAX_MISSED: f32 = 0.17;
const MAX_FAR: f32 = 0.17;
const MAX_FALSE: f32 = 0.09;

struct Mesh {
    triangles: Vec<[Vec3; 3]>,
}

impl Mesh {
    fn of(kind: PieceKind) -> (Mesh, Vec3, Vec3, Vec3) {
        let m = kind.mesh(24);
        let (lo, hi) = m.bounds();
        let centre = 0.5 * (lo + hi);
        let triangles = m
            .indices
            .chunks(3)
            .map(|t| [0, 1, 2].map(|k| m.positions[t[k] as usize] - centre))
            .collect();
        (Mesh { triangles }, centre, lo - centre, hi - centre)
    }

    /// The nearest hit of o + t d, t > 0 (Möller-Trumbore).
    fn hit(&self, o: Vec3, d: Vec3) -> Option<f32> {
        self.triangles
            .iter()
            .filter_map(|[a, b, c]| {
                let (e1, e2) = (*b - *a, *c - *a);
                let p = d.cross(e2);
                let det = e1.dot(p);
                if det.abs() < 1e-12 {
                    return None;
                }
                let s = o - *a;
                let u = s.dot(p) / det;
                let q = s.cross(e1);
                let v = d.dot(q) / det;
                let t = e2.dot(q) / det;
                ((0.0..=1.0).contains(&u) && v >= 0.0 && u + v <= 1.0 && t > 1e-6).then_some(t)
            })
            .min_by(f32::total_cmp)
    }

    /// The refractor map: distance of the nearest surface from the centre per texel centre.
    fn distance_map(&self) -> CubeDistanceMap {
        let faces: Vec<Vec<[f32; 4]>> = (0..6)
            .map(|face| {
                (0..MAP_SIZE * MAP_SIZE)
                    .map(|k| {
                        let (i, j) = (k % MAP_SIZE, k / MAP_SIZE);
                        let uv = (Vec2::new(i as f32, j as f32) + 0.5) / MAP_SIZE as f32;
                        let dir = gpu::prelude::cube_face_uv_to_dir(face, uv.x, uv.y).normalize();
                        [0.0, 0.0, 0.0, self.hit(Vec3::ZERO, dir).unwrap_or(60000.0)]
                    })
                    .collect()
            })
            .collect();
        CubeDistanceMap::from_rgba_faces(MAP_SIZE, &faces, 3)
    }
}

/// Rays from 3 squares away, aimed at random points of the piece's bounding box.
fn rays(lo: Vec3, hi: Vec3) -> Vec<(Vec3, Vec3)> {
    let h = |k: u32| gpu::prelude::hash_to_unit(k);
    (0..RAYS)
        .map(|i| {
            let k = 6 * i;
            let target = lo + (hi - lo) * Vec3::new(h(k), h(k + 1), h(k + 2));
            let from = Vec3::new(h(k + 3) - 0.5, h(k + 4) * 0.8, h(k + 5) - 0.5)
                .normalize_or(Vec3::X)
                * 3.0
                * SQUARE;
            (from, (target - from).normalize())
        })
        .collect()
}

/// What happened to the rays aimed at one kind.
#[derive(Debug, Default)]
struct Outcome {
    rays: usize,
    /// Rays that hit the mesh.
    hits: usize,
    /// Hits the map cannot hold: the exact hit point is not the nearest surface from the
    /// centre in its direction (the star-shaped assumption fails there).
    hidden: usize,
    /// Failures of the search on the other hits: no hit found, or one off by > TOLERANCE.
    missed: usize,
    far: usize,
    /// A hit found where the mesh has none (the ray passes within epsilon of the surface).
    false_hits: usize,
}

fn outcome(kind: PieceKind) -> Outcome {
    let (mesh, _, lo, hi) = Mesh::of(kind);
    let map = mesh.distance_map();
    let settings = refractor_maps::Settings::default();
    let mut out = Outcome::default();
    for (o, d) in rays(lo, hi) {
        out.rays += 1;
        let exact = mesh.hit(o, d);
        let found = hit_from_outside(
            &map,
            o,
            d,
            lo,
            hi,
            Method::FalsePosition,
            settings.maps.iterations,
            settings.maps.epsilon,
        )
        .map(|h| h.d);
        let Some(t) = exact else {
            out.false_hits += found.is_some() as usize;
            continue;
        };
        out.hits += 1;
        let point = o + d * t;
        let seen_from_centre = mesh.hit(Vec3::ZERO, point.normalize()).unwrap_or(f32::MAX);
        if seen_from_centre < point.length() - TOLERANCE {
            out.hidden += 1;
            continue;
        }
        match found {
            None => out.missed += 1,
            Some(s) if (s - t).abs() > TOLERANCE => out.far += 1,
            Some(_) => {}
        }
    }
    out
}

#[test]
fn the_search_from_outside_fails_within_its_measured_rates() {
    let mut hidden_share = Vec::new();
    let mut failures = Vec::new();
    println!(
        "search from outside, {RAYS} rays per kind, map {MAP_SIZE}^2 per face, the tracer's \
         defaults (false position, iterations and epsilon of refractor_maps::Settings)"
    );
    for kind in PieceKind::ALL {
        let o = outcome(kind);
        let pct = |n: usize, of: usize| 100.0 * n as f32 / of.max(1) as f32;
        println!(
            "{:>6}: {} hits; hidden from the centre {:.1}%; of the rest missed {:.1}%, off by \
             > 2 mm {:.1}%; false hits {:.1}% of the {} rays that miss",
            kind.name(),
            o.hits,
            pct(o.hidden, o.hits),
            pct(o.missed, o.hits - o.hidden),
            pct(o.far, o.hits - o.hidden),
            pct(o.false_hits, o.rays - o.hits),
            o.rays - o.hits,
        );
        assert!(o.hits > RAYS as usize / 3, "{:?}: the rays must hit", kind);
        hidden_share.push((kind, o.hidden as f32 / o.hits as f32));
        let found = o.hits - o.hidden;
        let share = |n: usize, of: usize| n as f32 / of.max(1) as f32;
        let (missed, far) = (share(o.missed, found), share(o.far, found));
        let false_hits = share(o.false_hits, o.rays - o.hits);
        failures.extend(
            [
                ("missed", missed, MAX_MISSED),
                ("off by > 2 mm", far, MAX_FAR),
                ("false hits", false_hits, MAX_FALSE),
            ]
            .into_iter()
            .filter(|(_, share, max)| share > max)
            .map(|(what, share, max)| format!("{}: {what} {share:.3} > {max}", kind.name())),
        );
    }
    assert!(failures.is_empty(), "{failures:#?}");
    let share = |k| hidden_share.iter().find(|(kind, _)| *kind == k).unwrap().1;
    assert!(share(PieceKind::Knight) > share(PieceKind::Pawn));
}
