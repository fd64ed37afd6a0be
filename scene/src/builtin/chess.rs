//! The `chess` scene: the glass chess set of Szirmay-Kalos and co-authors' multi-bounce paper
//! ("Real-time multi-bounce many-object ray tracing with distance-normal impostors",
//! sections 4.2 and 8): a textured chessboard, two full sets of glass pieces (32), a glass sphere, one point
//! light, and one piece that moves (the white king's pawn, e2 to e4) while the others stand.
//!
//! The pieces are generated, not loaded: pawn, rook, bishop, queen and king are surfaces of
//! revolution of profile curves ([`Ring::circle`] lofts). The knight's head is a loft of
//! leaning ellipses whose muzzle overhangs the throat, so the knight is *not* star-shaped from
//! its centre: rays from the centre towards the underside of the jaw leave the surface and
//! enter it again. That is the paper's hard case for refractor distance maps, which assume one
//! surface point per direction (the collars and crowns of the revolved pieces overhang too, a
//! little: the module's tests print the share of directions that cross twice, per kind).
//!
//! Coordinates: the board's top is y = 0, files a-h run along +x, ranks 1-8 along -z (white
//! sits at +z, towards the default camera). One square is [`SQUARE`] metres; every piece
//! stands at the centre of its square (at most one piece per square, as the paper's board grid
//! assumes), the knights facing the opponent.

use super::textures::checker_texture;
use crate::mesh::{Ring, cuboid, loft, quad, uv_sphere};
use crate::{Camera, CameraPath, Light, Material, Motion, Object, Roles, Scene, SceneError};
use glam::{Mat4, Quat, Vec2, Vec3};

/// Side of one board square, metres.
pub const SQUARE: f32 = 0.2;

/// The values of the `material` parameter.
pub const MATERIAL_HELP: &str = "glass (every piece and the sphere glass of index `ior`), mirror \
                                 (every piece a mirror, the sphere glass), mirror-mover (glass, \
                                 but the moving pawn a mirror: the paper's figure 9)";

/// The six kinds of piece; one refractor map per kind serves every piece of that kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PieceKind {
    Pawn,
    Rook,
    Knight,
    Bishop,
    Queen,
    King,
}

impl PieceKind {
    pub const ALL: [PieceKind; 6] = [
        PieceKind::Pawn,
        PieceKind::Rook,
        PieceKind::Knight,
        PieceKind::Bishop,
        PieceKind::Queen,
        PieceKind::King,
    ];

    /// The lower-case name used in object names (`white knight g1`).
    pub fn name(self) -> &'static str {
        match self {
            PieceKind::Pawn => "pawn",
            PieceKind::Rook => "rook",
            PieceKind::Knight => "knight",
            PieceKind::Bishop => "bishop",
            PieceKind::Queen => "queen",
            PieceKind::King => "king",
        }
    }

    /// The kind named at the start of a piece's object name (`"black queen d8"` is a queen).
    pub fn of_object(name: &str) -> Option<PieceKind> {
        let word = name.split_whitespace().nth(1)?;
        PieceKind::ALL.into_iter().find(|k| k.name() == word)
    }

    /// The piece's mesh in its own frame: standing on y = 0, centred on the y axis, facing +x
    /// (only the knight has a facing), with `slices` vertices round each cross-section.
    pub fn mesh(self, slices: u32) -> crate::Mesh {
        let rings = match self {
            PieceKind::Knight => knight_outline(),
            kind => revolved_outline(kind),
        };
        let scaled: Vec<Ring> = rings
            .iter()
            .map(|r| Ring {
                y: r.y * SQUARE,
                x: r.x * SQUARE,
                rx: r.rx * SQUARE,
                rz: r.rz * SQUARE,
            })
            .collect();
        loft(&scaled, slices, 40.0)
    }
}

/// Profile (height, radius) pairs of the revolved pieces, in squares, bottom to top. Every
/// piece shares the stepped base; a radius of 0 closes the top.
fn revolved_outline(kind: PieceKind) -> Vec<Ring> {
    let base: &[(f32, f32)] = &[
        (0.0, 0.34),
        (0.06, 0.34),
        (0.09, 0.30),
        (0.12, 0.30),
        (0.16, 0.24),
        (0.22, 0.18),
    ];
    let top: &[(f32, f32)] = match kind {
        PieceKind::Pawn => &[
            (0.40, 0.11),
            (0.43, 0.17),
            (0.46, 0.17),
            (0.49, 0.10),
            (0.52, 0.11),
            (0.56, 0.135),
            (0.61, 0.145),
            (0.66, 0.135),
            (0.71, 0.105),
            (0.75, 0.055),
            (0.76, 0.0),
        ],
        PieceKind::Rook => &[
            (0.56, 0.17),
            (0.60, 0.23),
            (0.64, 0.25),
            (0.86, 0.25),
            (0.86, 0.17),
            (0.80, 0.17),
            (0.80, 0.0),
        ],
        PieceKind::Bishop => &[
            (0.58, 0.11),
            (0.62, 0.18),
            (0.65, 0.18),
            (0.68, 0.11),
            (0.74, 0.15),
            (0.82, 0.17),
            (0.90, 0.15),
            (0.97, 0.10),
            (1.01, 0.06),
            (1.04, 0.07),
            (1.07, 0.05),
            (1.09, 0.0),
        ],
        PieceKind::Queen => &[
            (0.70, 0.12),
            (0.74, 0.21),
            (0.77, 0.21),
            (0.80, 0.13),
            (0.96, 0.20),
            (1.02, 0.21),
            (1.04, 0.14),
            (1.08, 0.09),
            (1.12, 0.08),
            (1.16, 0.06),
            (1.18, 0.0),
        ],
        PieceKind::King => &[
            (0.74, 0.13),
            (0.78, 0.22),
            (0.81, 0.22),
            (0.84, 0.14),
            (1.00, 0.19),
            (1.06, 0.20),
            (1.08, 0.12),
            (1.12, 0.07),
            (1.28, 0.05),
            (1.30, 0.08),
            (1.33, 0.08),
            (1.35, 0.0),
        ],
        PieceKind::Knight => unreachable!("the knight is lofted, not revolved"),
    };
    base.iter()
        .chain(top)
        .map(|&(y, r)| Ring::circle(y, r))
        .collect()
}

/// The knight: the revolved base, then a head lofted through ellipses (x offset, half-axes
/// along x and z, in squares) that leans back at the neck and juts forward (+x) at the muzzle,
/// so the jaw overhangs the throat.
fn knight_outline() -> Vec<Ring> {
    let ellipse = |y: f32, x: f32, rx: f32, rz: f32| Ring { y, x, rx, rz };
    let mut rings: Vec<Ring> = revolved_outline(PieceKind::Pawn)[..6].to_vec();
    rings.extend([
        ellipse(0.30, -0.02, 0.19, 0.15),
        ellipse(0.42, -0.05, 0.19, 0.13),
        ellipse(0.54, -0.05, 0.18, 0.12),
        ellipse(0.62, 0.00, 0.20, 0.12),
        ellipse(0.68, 0.12, 0.28, 0.11),
        ellipse(0.76, 0.17, 0.30, 0.10),
        ellipse(0.84, 0.12, 0.25, 0.095),
        ellipse(0.92, 0.03, 0.16, 0.08),
        ellipse(0.98, -0.02, 0.08, 0.06),
        ellipse(1.00, -0.03, 0.0, 0.0),
    ]);
    rings
}

/// `chess` with glass of index `ior`, the pieces' `material` (one of [`MATERIAL_HELP`]) and
/// `slices` vertices round each cross-section of a piece.
pub fn chess(material: &str, ior: f32, slices: u32) -> Result<Scene, SceneError> {
    super::check_ior(ior)?;
    let glass = (
        Material::glass(ior),
        Roles::REFRACTOR | Roles::CAUSTIC_CASTER,
    );
    let mirror = (
        Material::perfect_mirror(),
        Roles::REFLECTOR | Roles::CAUSTIC_CASTER,
    );
    let (piece, mover) = match material {
        "glass" => (glass.clone(), glass.clone()),
        "mirror" => (mirror.clone(), mirror),
        "mirror-mover" => (glass.clone(), mirror),
        other => {
            return Err(SceneError::BadParam(format!(
                "unknown material \"{other}\" ({MATERIAL_HELP})"
            )));
        }
    };
    let meshes: Vec<_> = PieceKind::ALL.map(|k| (k, k.mesh(slices))).into();
    let mesh_of = |kind| meshes.iter().find(|(k, _)| *k == kind).unwrap().1.clone();

    let mut objects = board_objects();
    let back_rank = [
        PieceKind::Rook,
        PieceKind::Knight,
        PieceKind::Bishop,
        PieceKind::Queen,
        PieceKind::King,
        PieceKind::Bishop,
        PieceKind::Knight,
        PieceKind::Rook,
    ];
    for (side, home, pawns, facing) in [("white", 0, 1, 0.5), ("black", 7, 6, -0.5)] {
        let ranks = [(home, back_rank), (pawns, [PieceKind::Pawn; 8])];
        for (rank, kinds) in ranks {
            for (file, kind) in kinds.into_iter().enumerate() {
                // The knight's head faces +x in its frame: turn it to face the opponent.
                let turn = Quat::from_rotation_y(facing * std::f32::consts::PI);
                let name = format!("{side} {} {}", kind.name(), square_name(file, rank));
                let (material, roles) = if name == MOVER { &mover } else { &piece };
                let mut object = Object::new(
                    &name,
                    mesh_of(kind),
                    material.clone(),
                    Mat4::from_rotation_translation(turn, square_centre(file, rank) + LIFT),
                )
                .with_roles(*roles);
                if name == MOVER {
                    // e2-e4 over the camera path: two squares towards black.
                    object.motion = Motion {
                        keys: vec![(0.0, Vec3::ZERO), (2.0, Vec3::Z * (-2.0 * SQUARE))],
                    };
                }
                objects.push(object);
            }
        }
    }
    // The 33rd refractor of the paper's scene: a glass sphere resting on d5.
    let radius = 0.4 * SQUARE;
    objects.push(
        Object::new(
            "sphere d5",
            uv_sphere(radius, 24, 48),
            glass.0.clone(),
            Mat4::from_translation(square_centre(3, 4) + LIFT + Vec3::Y * radius),
        )
        .with_roles(glass.1),
    );

    let camera = Camera {
        eye: Vec3::new(0.55, 1.45, 1.95),
        target: Vec3::new(0.0, 0.0, -0.1),
        up: Vec3::Y,
        fov_y_deg: 45.0,
        orthographic: None,
    };
    let side_view = Camera {
        eye: Vec3::new(-0.9, 1.1, 1.6),
        ..camera
    };
    Ok(Scene {
        name: String::new(),
        objects,
        textures: vec![checker_texture(
            "chessboard",
            128,
            8,
            [232, 220, 190],
            [92, 64, 44],
        )],
        lights: vec![Light {
            name: "lamp".into(),
            position: Vec3::new(0.5, 2.2, 0.9),
            intensity: Vec3::splat(9.0),
            kind: crate::LightKind::Point,
        }],
        camera,
        camera_path: CameraPath {
            keys: vec![(0.0, camera), (1.0, side_view), (2.0, camera)],
        },
        volumes: vec![],
        medium: None,
        background: Vec3::new(0.25, 0.28, 0.32),
    })
}

/// The pieces stand a millimetre above the board: a base coplanar with the board's top would
/// make every renderer guess which of the two a ray inside the glass meets first.
const LIFT: Vec3 = Vec3::new(0.0, 0.001, 0.0);

/// The piece that moves over the camera path.
pub const MOVER: &str = "white pawn e2";

/// The centre of square (`file`, `rank`) on the board's top, both counted from 0 (a1 is
/// (0, 0)).
pub fn square_centre(file: usize, rank: usize) -> Vec3 {
    Vec3::new(
        (file as f32 - 3.5) * SQUARE,
        0.0,
        (3.5 - rank as f32) * SQUARE,
    )
}

fn square_name(file: usize, rank: usize) -> String {
    format!("{}{}", (b'a' + file as u8) as char, rank + 1)
}

/// The board (8 x 8 textured squares, a1 dark), its wooden frame a hair below, and the table
/// top under both.
fn board_objects() -> Vec<Object> {
    let half = 4.0 * SQUARE;
    let id = Mat4::IDENTITY;
    let squares = quad(
        Vec3::new(-half, 0.0, half),
        Vec3::X * (2.0 * half),
        Vec3::NEG_Z * (2.0 * half),
        Vec2::ONE,
    );
    let frame = cuboid(
        Vec3::new(-half - 0.06, -0.05, -half - 0.06),
        Vec3::new(half + 0.06, -0.001, half + 0.06),
    );
    let table = quad(
        Vec3::new(-3.0, -0.05, 3.0),
        Vec3::X * 6.0,
        Vec3::NEG_Z * 6.0,
        Vec2::ONE,
    );
    vec![
        Object::new("table", table, Material::diffuse(0.45, 0.45, 0.48), id),
        Object::new("board frame", frame, Material::diffuse(0.35, 0.2, 0.1), id),
        Object::new(
            "board",
            squares,
            Material::Diffuse {
                albedo: Vec3::ONE,
                texture: Some(0),
                cutout: None,
            },
            id,
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_set_is_complete_and_one_piece_stands_per_square() {
        let scene = chess("glass", 1.5, 16).unwrap();
        let pieces: Vec<_> = scene
            .objects
            .iter()
            .filter_map(|o| PieceKind::of_object(&o.name).map(|k| (k, o)))
            .collect();
        assert_eq!(pieces.len(), 32);
        for (kind, per_side) in [
            (PieceKind::Pawn, 8),
            (PieceKind::Rook, 2),
            (PieceKind::Knight, 2),
            (PieceKind::Bishop, 2),
            (PieceKind::Queen, 1),
            (PieceKind::King, 1),
        ] {
            let n = pieces.iter().filter(|(k, _)| *k == kind).count();
            assert_eq!(n, 2 * per_side, "{kind:?}");
        }
        // Every piece (and the sphere) fits its square, on the board, one per square, at
        // every time of the camera path.
        for t in [0.0, 0.5, 1.0, 1.5, 2.0] {
            let mut seen = std::collections::HashSet::new();
            for o in scene.objects.iter().filter(|o| o.material.is_specular()) {
                let (lo, hi) = o.mesh.bounds();
                assert!(hi.x - lo.x <= SQUARE && hi.z - lo.z <= SQUARE, "{}", o.name);
                let c = o.world_at(t).transform_point3(Vec3::ZERO);
                let cell = [c.x, c.z].map(|v| (v / SQUARE + 4.0).floor() as i32);
                assert!(
                    cell.iter().all(|v| (0..8).contains(v)),
                    "{} off the board",
                    o.name
                );
                assert!(
                    seen.insert(cell),
                    "{} shares square {cell:?} at t = {t}",
                    o.name
                );
            }
        }
    }

    #[test]
    fn only_the_mover_moves_and_the_variants_change_materials() {
        let glass = chess("glass", 1.5, 16).unwrap();
        let moving: Vec<_> = glass
            .objects
            .iter()
            .filter(|o| !o.motion.is_static())
            .map(|o| o.name.as_str())
            .collect();
        assert_eq!(moving, [MOVER]);
        let figure9 = chess("mirror-mover", 1.5, 16).unwrap();
        for o in &figure9.objects {
            let mirror = matches!(o.material, Material::Metal { .. });
            assert_eq!(mirror, o.name == MOVER, "{}", o.name);
        }
        let mirrors = chess("mirror", 1.2, 16).unwrap();
        let n = mirrors
            .objects
            .iter()
            .filter(|o| matches!(o.material, Material::Metal { .. }))
            .count();
        assert_eq!(n, 32);
        assert!(chess("brass", 1.5, 16).is_err());
        assert!(chess("glass", 9.0, 16).is_err());
    }

    /// The knight is not star-shaped from its bounding-box centre: a measurable share of the
    /// rays from there cross its surface more than once (leaving the throat and entering the
    /// jaw). Printed for every kind: no piece is exactly star-shaped, since collars, crowns and
    /// the stepped base overhang too (with 24 slices: pawn 1.6%, rook 3.7%, knight 4.7%,
    /// bishop 2.9%, queen 7.7%, king 3.8% of 1500 directions).
    #[test]
    fn the_knight_is_not_star_shaped_from_its_centre() {
        let mut shares = Vec::new();
        for kind in PieceKind::ALL {
            let share = not_star_shaped_share(&kind.mesh(24), 1500);
            println!(
                "{:>6}: {:.2}% of directions cross more than once",
                kind.name(),
                share * 100.0
            );
            shares.push((kind, share));
        }
        let knight = shares
            .iter()
            .find(|(k, _)| *k == PieceKind::Knight)
            .unwrap()
            .1;
        assert!(knight > 0.01, "knight {knight}");
    }

    /// The share of `n` directions (a Fibonacci sphere) along which the ray from the mesh's
    /// bounding-box centre crosses the surface more than once.
    fn not_star_shaped_share(mesh: &crate::Mesh, n: usize) -> f32 {
        let (lo, hi) = mesh.bounds();
        let centre = 0.5 * (lo + hi);
        let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
        let multiple = (0..n)
            .filter(|&i| {
                let y = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
                let r = (1.0 - y * y).sqrt();
                let phi = golden * i as f32;
                let dir = Vec3::new(r * phi.cos(), y, r * phi.sin());
                let crossings = mesh
                    .indices
                    .chunks(3)
                    .filter(|t| {
                        let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[t[k] as usize]);
                        ray_hits_triangle(centre, dir, a, b, c)
                    })
                    .count();
                crossings > 1
            })
            .count();
        multiple as f32 / n as f32
    }

    /// Möller-Trumbore, for the star-shape test only.
    fn ray_hits_triangle(o: Vec3, d: Vec3, a: Vec3, b: Vec3, c: Vec3) -> bool {
        let (e1, e2) = (b - a, c - a);
        let p = d.cross(e2);
        let det = e1.dot(p);
        if det.abs() < 1e-12 {
            return false;
        }
        let s = o - a;
        let u = s.dot(p) / det;
        let q = s.cross(e1);
        let v = d.dot(q) / det;
        let t = e2.dot(q) / det;
        (0.0..=1.0).contains(&u) && v >= 0.0 && u + v <= 1.0 && t > 0.0
    }
}
