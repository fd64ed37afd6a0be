//! Multi-bounce rays with per-piece environment distance impostors (paper section 5): the
//! [`EnvironmentMaps`] technique, variants `full-update` and `separated`.
//!
//! Every piece keeps an environment impostor (a cube of radiance + distance taken from its
//! centre) beside the refractor map of its kind. A pixel of a piece needs three searches: the
//! exit through its refractor map and `Hit()` in its impostor along the reflected and the
//! exit rays (environment_pieces.wgsl). The impostors hold multi-bounce radiance because
//! they are built in rounds (section 5.1): the diffuse scene first, then, `env_depth` times,
//! every other piece drawn into each impostor with the same shader and the impostors of the
//! round before.
//!
//! - `full-update` rebuilds every impostor, all rounds, every frame: the paper's first test
//!   (1.8 FPS on its scene).
//! - `separated` (section 5.2) builds the static pieces' impostors once, in `prepare`, without
//!   the moving piece; only the moving piece's impostor is rebuilt each frame (the diffuse
//!   scene and the static pieces drawn into it), and a static piece finds the moving one by
//!   searching its refractor map from outside along each lookup ray (11.3 FPS in the paper,
//!   "approximately 6 times faster").

use crate::grid::EMPTY;
use crate::pieces::{Kinds, PieceGpu, pieces_at, render_kind_maps};
use crate::technique::{MAP_FORMAT, storage};
use glam::Vec3;
use gpu::cube::{CubeArray, cube_face_view_proj};
use gpu::distance_map::{HIT_WGSL, layered_hit_wgsl};
use gpu::pass::{self, Load};
use gpu::wgpu;
use gpu::{Context, Target, Uniform, bind};
use scene::technique::check_param;
use scene::{
    Frame, GpuScene, ObjectFilter, Param, RasterTarget, Scene, Technique, TechniqueError,
    TechniqueResult, View,
};

const ENVIRONMENT_PIECES_WGSL: &str = include_str!("shaders/environment_pieces.wgsl");

/// Deepest multi-bounce build of the impostors (`env_depth`).
pub const MAX_ENV_DEPTH: u32 = 8;

/// Parameters of an [`EnvironmentMaps`] variant.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvSettings {
    /// Static pieces' impostors built once without the moving piece (section 5.2), or every
    /// impostor rebuilt every frame.
    pub separated: bool,
    /// Rounds of drawing the pieces into the impostors (section 5.1's DEPTH).
    pub env_depth: u32,
    /// Cube face size of each kind's refractor map.
    pub resolution: u32,
    /// Cube face size of each piece's environment impostor.
    pub env_resolution: u32,
    /// Hit() refinement steps in the refractor maps (inside and from outside).
    pub iterations: u32,
    /// Hit() refinement steps in the environment impostors.
    pub env_iterations: u32,
    /// A search from outside is accepted within this distance of the ray (metres).
    pub epsilon: f32,
}

impl Default for EnvSettings {
    fn default() -> Self {
        Self {
            separated: true,
            env_depth: 2,
            resolution: 256,
            env_resolution: 128,
            iterations: 4,
            env_iterations: 4,
            epsilon: 0.004,
        }
    }
}

/// A section-5 variant: per-piece environment impostors, fully updated or separated.
pub struct EnvironmentMaps {
    id: String,
    description: String,
    representative: bool,
    /// The variant's parameters.
    pub settings: EnvSettings,
    state: Option<State>,
}

struct State {
    kinds: Kinds,
    /// The refractor map of kind k is cube k.
    kind_maps: CubeArray,
    /// The impostor of piece p (in `kinds.pieces` order) is cube p; a round renders into
    /// `scratch` while reading `current`, then copies its cubes over.
    current: CubeArray,
    scratch: CubeArray,
    /// The point each impostor was taken from.
    centres: Vec<Vec3>,
    /// The moving piece (separated: its impostor is rebuilt each frame, the others never).
    mover: Option<usize>,
    layout: wgpu::BindGroupLayout,
    eye_pipeline: wgpu::RenderPipeline,
    cube_pipeline: wgpu::RenderPipeline,
    /// The piece of each scene object, [`EMPTY`] for a diffuse one.
    piece_of_object: wgpu::Buffer,
    /// Impostor renders (one per impostor per round) since `prepare` (for tests).
    rebuilds: u32,
}

/// The uniform block `EnvParams` of environment_pieces.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct EnvParamsGpu {
    mover: u32,
    iterations: u32,
    env_iterations: u32,
    epsilon: f32,
}

impl EnvironmentMaps {
    /// A variant named `id` (`refractor-maps/<variant>`).
    pub fn new(id: &str, description: &str, representative: bool, settings: EnvSettings) -> Self {
        Self {
            id: id.into(),
            description: description.into(),
            representative,
            settings,
            state: None,
        }
    }

    /// Impostor rebuilds (one per impostor per round) since `prepare` (for tests).
    pub fn rebuilds(&self) -> u32 {
        self.state.as_ref().map_or(0, |s| s.rebuilds)
    }
}

/// The section-5 variants.
pub fn variants() -> Vec<Box<dyn Technique>> {
    let s = EnvSettings::default();
    vec![
        Box::new(EnvironmentMaps::new(
            "refractor-maps/full-update",
            "per-piece environment impostors holding multi-bounce radiance (section 5.1), every \
             impostor rebuilt every frame: the paper's baseline for a moving piece",
            true,
            EnvSettings {
                separated: false,
                ..s.clone()
            },
        )),
        Box::new(EnvironmentMaps::new(
            "refractor-maps/separated",
            "static pieces' impostors built once without the moving piece, the moving piece's \
             rebuilt each frame and found by the search from outside (section 5.2)",
            true,
            s,
        )),
    ]
}

fn param(
    name: &'static str,
    default: f64,
    (min, max): (f64, f64),
    integer: bool,
    help: &'static str,
) -> Param {
    Param {
        name,
        default,
        min,
        max,
        integer,
        help,
    }
}

impl Technique for EnvironmentMaps {
    fn id(&self) -> String {
        self.id.clone()
    }
    fn description(&self) -> String {
        self.description.clone()
    }
    fn representative(&self) -> bool {
        self.representative
    }
    fn params(&self) -> Vec<Param> {
        let s = &self.settings;
        vec![
            param(
                "env_depth",
                s.env_depth as f64,
                (0.0, MAX_ENV_DEPTH as f64),
                true,
                "rounds of drawing the pieces into each other's impostors (0: diffuse scene only)",
            ),
            param(
                "resolution",
                s.resolution as f64,
                (4.0, 4096.0),
                true,
                "cube face size of each kind's refractor map (texels)",
            ),
            param(
                "env_resolution",
                s.env_resolution as f64,
                (4.0, 4096.0),
                true,
                "cube face size of each piece's environment impostor (texels)",
            ),
            param(
                "iterations",
                s.iterations as f64,
                (0.0, 64.0),
                true,
                "Hit() refinement steps in the refractor maps",
            ),
            param(
                "env_iterations",
                s.env_iterations as f64,
                (0.0, 64.0),
                true,
                "Hit() refinement steps in the environment impostors",
            ),
            param(
                "epsilon",
                s.epsilon as f64,
                (1e-6, 1.0),
                false,
                "a search from outside is accepted within this distance of the ray (metres)",
            ),
        ]
    }
    fn set_param(&mut self, name: &str, value: f64) -> TechniqueResult<()> {
        check_param(&self.id, &self.params(), name, value)?;
        let s = &mut self.settings;
        match name {
            "env_depth" => s.env_depth = value as u32,
            "resolution" => s.resolution = value as u32,
            "env_resolution" => s.env_resolution = value as u32,
            "iterations" => s.iterations = value as u32,
            "env_iterations" => s.env_iterations = value as u32,
            "epsilon" => s.epsilon = value as f32,
            _ => unreachable!("check_param accepted an undeclared parameter"),
        }
        self.state = None;
        Ok(())
    }
    fn supports(&self, scene: &Scene) -> bool {
        !scene.specular_objects().is_empty()
    }
    fn prepare(&mut self, frame: &mut Frame, scene: &GpuScene) -> TechniqueResult<()> {
        let ctx = frame.gpu;
        let kinds = Kinds::of(&scene.scene);
        let s = &self.settings;
        let movers: Vec<usize> = kinds
            .pieces
            .iter()
            .enumerate()
            .filter(|(_, (o, _))| !scene.scene.objects[*o].motion.is_static())
            .map(|(p, _)| p)
            .collect();
        if s.separated && movers.len() > 1 {
            return Err(TechniqueError::Unsupported(format!(
                "{} separates one moving piece from the static ones (as a chess move does); \
                 this scene has {} moving specular objects",
                self.id,
                movers.len()
            )));
        }
        let n = kinds.pieces.len() as u32;
        let bytes = 2 * CubeArray::bytes(s.env_resolution, n, MAP_FORMAT)
            + CubeArray::bytes(s.resolution, kinds.representative.len() as u32, MAP_FORMAT);
        if bytes > scene::technique::MAP_BUDGET_BYTES {
            return Err(TechniqueError::OverBudget(format!(
                "{}: {n} impostors at {} texels and the refractor maps need {:.2} GB, over the \
                 {} MB budget of per-object maps; lower `env_resolution`",
                self.id,
                s.env_resolution,
                bytes as f64 / 1e9,
                scene::technique::MAP_BUDGET_BYTES >> 20
            )));
        }
        let kind_cubes = render_kind_maps(frame, scene, &kinds, s.resolution)?;
        let kind_maps = CubeArray::new(
            ctx,
            s.resolution,
            kind_cubes.len() as u32,
            MAP_FORMAT,
            "refractor maps",
        )?;
        for (k, cube) in kind_cubes.iter().enumerate() {
            kind_maps.copy_from_cube(frame.encoder, cube, k as u32);
        }
        let source = format!(
            "{}\n{}\n{}\n{}",
            scene::SCENE_WGSL,
            HIT_WGSL,
            layered_hit_wgsl(),
            ENVIRONMENT_PIECES_WGSL
        );
        let module = gpu::shader_with_prelude(ctx, &self.id, &source);
        let array = bind::texture(wgpu::TextureViewDimension::CubeArray, true);
        let layout = bind::layout(
            ctx,
            "environment pieces",
            wgpu::ShaderStages::FRAGMENT,
            &[
                bind::uniform(),
                bind::storage(true),
                bind::storage(true),
                bind::storage(true),
                bind::sampler(),
                array,
                array,
            ],
        );
        let pipeline_layout = scene.pipeline_layout_with(ctx, &[&layout]);
        let pipeline = |format| {
            scene::scene_pipeline(
                ctx,
                &self.id,
                &pipeline_layout,
                &module,
                "environment_piece_fs",
                format,
            )
        };
        let time = scene.time();
        let impostors = |label| CubeArray::new(ctx, s.env_resolution, n, MAP_FORMAT, label);
        let centres = kinds
            .pieces
            .iter()
            .map(|&(o, _)| scene.scene.objects[o].center_at(time))
            .collect();
        let mut piece_of_object = vec![EMPTY; scene.scene.objects.len()];
        for (piece, &(object, _)) in kinds.pieces.iter().enumerate() {
            piece_of_object[object] = piece as u32;
        }
        let mut state = State {
            kinds,
            kind_maps,
            current: impostors("piece impostors")?,
            scratch: impostors("piece impostors (next round)")?,
            centres,
            mover: movers.first().copied(),
            layout,
            eye_pipeline: pipeline(gpu::HDR_FORMAT),
            cube_pipeline: pipeline(MAP_FORMAT),
            piece_of_object: storage(ctx, "piece of object", &piece_of_object),
            rebuilds: 0,
        };
        if s.separated {
            // The static impostors, once: every piece but the moving one, all rounds.
            let statics: Vec<usize> = (0..state.kinds.pieces.len())
                .filter(|p| Some(*p) != state.mover)
                .collect();
            frame.timer.begin(frame.encoder, "static impostors");
            build_impostors(frame, scene, &mut state, s, &statics, &statics, s.env_depth);
            frame.timer.end(frame.encoder, "static impostors");
        }
        self.state = Some(state);
        Ok(())
    }
    fn render(
        &mut self,
        frame: &mut Frame,
        scene: &GpuScene,
        view: &View,
        target: &Target,
    ) -> TechniqueResult<()> {
        let s = self.settings.clone();
        let state = self
            .state
            .as_mut()
            .ok_or(TechniqueError::NotPrepared(self.id.clone()))?;
        let all: Vec<usize> = (0..state.kinds.pieces.len()).collect();
        frame.timer.begin(frame.encoder, "update impostors");
        if s.separated {
            if let Some(mover) = state.mover {
                let statics: Vec<usize> = all.iter().copied().filter(|&p| p != mover).collect();
                let rounds = s.env_depth.min(1);
                build_impostors(frame, scene, state, &s, &[mover], &statics, rounds);
            }
        } else {
            build_impostors(frame, scene, state, &s, &all, &all, s.env_depth);
        }
        frame.timer.end(frame.encoder, "update impostors");

        let ctx = frame.gpu;
        let (pieces, _) = pieces_at(&scene.scene, &state.kinds, scene.time());
        // Static pieces look for the moving one (separated only).
        let mover = if s.separated { state.mover } else { None };
        let group = environment_group(ctx, state, &s, &pieces, mover);
        let view_proj = view.camera.view_proj(view.width, view.height);
        let main = RasterTarget {
            color: &target.color_view,
            depth: &target.depth_view,
            format: gpu::HDR_FORMAT,
            clear: true,
        };
        let objects: Vec<usize> = state.kinds.pieces.iter().map(|&(o, _)| o).collect();
        scene.raster(
            frame,
            &main,
            view_proj,
            view.camera.eye,
            &ObjectFilter::Except(objects.clone()),
            false,
        );
        let camera = scene.camera_bind_group(ctx, view_proj, view.camera.eye);
        let mut pass = gpu::pass::begin(
            frame.encoder,
            &self.id,
            &[pass::color(&target.color_view, Load::Keep)],
            Some(pass::depth(&target.depth_view, Load::Keep)),
            frame.timer.render_pass("pieces"),
        );
        pass.set_pipeline(&state.eye_pipeline);
        pass.set_bind_group(0, &camera, &[]);
        pass.set_bind_group(1, scene.bind_group(), &[]);
        pass.set_bind_group(2, &group, &[]);
        scene.draw_objects(&mut pass, &ObjectFilter::Only(objects));
        Ok(())
    }
}

/// Builds the impostors of pieces `targets` in `rounds` rounds: each round renders, for each
/// target, the diffuse scene from the piece's centre now, then every piece of `drawn` but the
/// target itself, shaded with the impostors of the round before (section 5.1). With 0 rounds
/// the impostors hold the diffuse scene alone.
fn build_impostors(
    frame: &mut Frame,
    scene: &GpuScene,
    state: &mut State,
    settings: &EnvSettings,
    targets: &[usize],
    drawn: &[usize],
    rounds: u32,
) {
    let ctx = frame.gpu;
    let (pieces, _) = pieces_at(&scene.scene, &state.kinds, scene.time());
    for &t in targets {
        state.centres[t] = pieces_centre(&pieces[t]);
    }
    let drawn = if rounds == 0 { &[][..] } else { drawn };
    let far = 2.0 * scene::BACKGROUND_DISTANCE;
    for _ in 0..rounds.max(1) {
        // Pieces drawn into impostors do not look for a moving piece: it is in the impostors
        // or, separated, its own impostor is the one being built.
        let group = environment_group(ctx, state, settings, &pieces, None);
        for &t in targets {
            let centre = state.centres[t];
            let others: Vec<usize> = drawn
                .iter()
                .filter(|&&p| p != t)
                .map(|&p| state.kinds.pieces[p].0)
                .collect();
            for face in 0..6 {
                let view_proj = cube_face_view_proj(face, centre, 0.01, far);
                let target = RasterTarget {
                    color: &state.scratch.face_views[6 * t + face],
                    depth: &state.scratch.depth_face_views[face],
                    format: MAP_FORMAT,
                    clear: true,
                };
                scene.raster(frame, &target, view_proj, centre, &ObjectFilter::All, false);
                if others.is_empty() {
                    continue;
                }
                let keep = RasterTarget {
                    clear: false,
                    ..target
                };
                let camera = scene.camera_bind_group(ctx, view_proj, centre);
                let mut pass = scene::begin_scene_pass(
                    frame.encoder,
                    &keep,
                    Vec3::ZERO,
                    "pieces into impostor",
                );
                pass.set_pipeline(&state.cube_pipeline);
                pass.set_bind_group(0, &camera, &[]);
                pass.set_bind_group(1, scene.bind_group(), &[]);
                pass.set_bind_group(2, &group, &[]);
                scene.draw_objects(&mut pass, &ObjectFilter::Only(others.clone()));
            }
            state.rebuilds += 1;
        }
        let cubes: Vec<u32> = targets.iter().map(|&t| t as u32).collect();
        state
            .scratch
            .copy_cubes_to(frame.encoder, &state.current, &cubes);
    }
}

fn pieces_centre(p: &PieceGpu) -> Vec3 {
    Vec3::new(p.centre[0], p.centre[1], p.centre[2])
}

/// The `@group(2)` of environment_pieces.wgsl reading the current impostors, with `mover`
/// the piece the others search for (or none).
fn environment_group(
    ctx: &Context,
    state: &State,
    settings: &EnvSettings,
    pieces: &[PieceGpu],
    mover: Option<usize>,
) -> wgpu::BindGroup {
    let params = Uniform::new(
        ctx,
        "environment params",
        &EnvParamsGpu {
            mover: mover.map_or(EMPTY, |m| m as u32),
            iterations: settings.iterations,
            env_iterations: settings.env_iterations,
            epsilon: settings.epsilon,
        },
    );
    let centres: Vec<[f32; 4]> = state
        .centres
        .iter()
        .map(|c| c.extend(0.0).to_array())
        .collect();
    let piece_buffer = storage(ctx, "pieces", pieces);
    let centre_buffer = storage(ctx, "impostor centres", &centres);
    bind::group(
        ctx,
        "environment pieces",
        &state.layout,
        &[
            params.binding(),
            piece_buffer.as_entire_binding(),
            centre_buffer.as_entire_binding(),
            state.piece_of_object.as_entire_binding(),
            bind::sampler_resource(&ctx.samplers.linear_clamp),
            bind::view(&state.current.array_view),
            bind::view(&state.kind_maps.array_view),
        ],
    )
}
