//! Refractor distance maps as one pass of a renderer's own frame: glass or metal pieces whose
//! rays are followed from piece to piece through each one's refractor map (sections 3-4.2),
//! drawn over the renderer's colour and depth targets in their formats.
//!
//! What the renderer provides (and nothing else: no `scene::Scene`, no `GpuScene`, no timer):
//!
//! - its wgpu device and queue, wrapped once with `gpu::Context::from_parts`;
//! - the pieces ([`Piece`]): each one's mesh (`gpu::HostedMesh`, in the piece's frame), what
//!   it is made of, its index among the renderer's objects and where it stands
//!   (`set_position_of` moves it; the renderer does not draw it); pieces with the same mesh
//!   share one refractor map. The rays find the next piece through a grid over the pieces'
//!   footprints on the ground plane (xz), as on the paper's chessboard;
//! - its world drawn on request, [`gpu::DrawScene`]: everything but the pieces, from the
//!   centre of the pieces' bounds, into the six faces of the environment impostor
//!   (`Rgba16Float`, radiance in rgb and the distance from the centre in alpha; depth
//!   `Depth32Float`), each frame;
//! - its colour and depth targets (any renderable colour format, any depth format), holding
//!   its frame already (the pass writes rgb and depth; the renderer's alpha is kept), and its
//!   camera ([`gpu::EyeView`]).
//!
//! The pass is the technique's own code: `RefractorMaps::draw_over` runs the steps the
//! harness's `refractor-maps/single-bounce` and `refractor-maps/multi-bounce-4` run in their
//! frames (the environment impostor drawn through `gpu::DrawScene`, the traced pieces), with
//! `scene::GpuScene` as the host there.

use crate::technique::{Maps, RefractorMaps, Search, Settings};
use glam::Vec3;
use gpu::{HostedMesh, TargetFormats};
use scene::Technique as _;
use scene::TechniqueResult;
pub use scene::hosted::Surface;
use scene::hosted::{HostedPass, HostedPiece};
use scene::multi_object::grid::ALL_CELLS;

/// One of the renderer's specular pieces.
#[derive(Clone, Debug, PartialEq)]
pub struct Piece {
    /// Its triangles in its own frame: a closed surface, normals outward, every point seen
    /// from the centre of its bounds (what a distance map holds).
    pub mesh: HostedMesh,
    /// What it is made of.
    pub surface: Surface,
    /// Its index among the renderer's objects: the one its [`gpu::DrawScene`] leaves out of
    /// the environment impostor.
    pub host_index: usize,
    /// Where it stands: the offset from where its mesh puts it.
    pub position: Vec3,
}

/// How far a path goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bounces {
    /// One interface split, the refractor map for the exit, then the environment: no other
    /// piece is seen (`refractor-maps/single-bounce`).
    Single,
    /// Paths split at up to `depth` interfaces (1 to 8) inside one piece; a ray that leaves it
    /// takes the environment: no other piece is seen (section 3's double refraction, with one
    /// environment impostor for every piece).
    Alone {
        /// Interfaces at which a path splits.
        depth: u32,
    },
    /// Paths split at up to `depth` interfaces (1 to 8), a ray that leaves a piece finding the
    /// next one through the grid and the search from outside (sections 4.1-4.2:
    /// `refractor-maps/multi-bounce-4` with depth 4).
    Multi {
        /// Interfaces at which a path splits.
        depth: u32,
    },
}

/// The refractor-map pass of some pieces, made for a renderer's formats: a [`HostedPass`] (its
/// `set_position_of` and `draw`) of the [`RefractorMaps`] technique.
pub struct RefractorMapsPass(HostedPass<RefractorMaps>);

impl RefractorMapsPass {
    /// The pass of `pieces` for targets of `formats`, their paths going as far as `bounces`,
    /// with refractor maps of `resolution` texels a side (one per mesh) and an environment
    /// impostor of `env_resolution`, asked of the renderer every frame.
    pub fn new(
        ctx: &gpu::Context,
        pieces: &[Piece],
        bounces: Bounces,
        formats: TargetFormats,
        (resolution, env_resolution): (u32, u32),
    ) -> TechniqueResult<Self> {
        let grid = Search::Grid {
            max_cells: ALL_CELLS,
        };
        let (name, depth, search) = match bounces {
            Bounces::Single => ("refractor-maps/single-bounce", 1, Search::None),
            Bounces::Alone { depth } => ("refractor-maps/alone", depth, Search::None),
            Bounces::Multi { depth } => ("refractor-maps/multi-bounce", depth, grid),
        };
        let settings = Settings {
            search,
            maps: Maps::with_env_resolution(env_resolution),
            caustics: None,
            ..Settings::default()
        };
        let mut technique =
            RefractorMaps::new(name, "refractor-map pass", true, settings).for_targets(formats);
        // Through the declared parameters: each value is checked against its range.
        technique.set_param("depth", depth as f64)?;
        technique.set_param("resolution", resolution as f64)?;
        technique.set_param("env_resolution", env_resolution as f64)?;
        let hosted: Vec<HostedPiece> = pieces
            .iter()
            .map(|p| HostedPiece {
                mesh: &p.mesh,
                material: p.surface.into(),
                host_index: p.host_index,
                position: p.position,
            })
            .collect();
        HostedPass::new(ctx, formats, &hosted, technique).map(Self)
    }
}

scene::hosted_pass_deref!(RefractorMapsPass, RefractorMaps);
