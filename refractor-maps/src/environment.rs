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

use crate::pieces::{Kinds, PieceGpu, pieces_at, render_kind_maps};
use crate::technique::{MAP_FORMAT, Maps};
use glam::Vec3;
use gpu::cube::{CubeArray, cube_face_view_proj};
use gpu::distance_map::{HIT_WGSL, layered_hit_wgsl};
use gpu::pass::{self, Load};
use gpu::wgpu;
use gpu::{Context, Target, Uniform, bind};
use scene::multi_object::grid::EMPTY;
use scene::multi_object::storage;
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
    /// Metres the moving piece may travel from where the impostors were last updated before
    /// they are updated again (0: every frame). Section 5.1: the maps are recomputed "only
    /// when the rate of changes makes it necessary", not every frame; between updates the
    /// impostors show the moving piece where it was.
    pub rebuild_threshold: f32,
    /// The maps and their searches (`env_resolution`: each piece's impostor).
    pub maps: Maps,
}

impl Default for EnvSettings {
    fn default() -> Self {
        Self {
            separated: true,
            env_depth: 2,
            rebuild_threshold: 0.0,
            maps: Maps::with_env_resolution(128),
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
    /// The impostor of piece p (in `kinds.pieces` order) is cube p; a round renders into the
    /// atlas while reading `current`, then copies its faces over.
    current: CubeArray,
    atlas: Atlas,
    /// The point each impostor was taken from.
    impostor_centres: Vec<Vec3>,
    /// The moving piece (separated: its impostor is rebuilt each frame, the others never).
    mover: Option<usize>,
    eye_pipeline: wgpu::RenderPipeline,
    cube_pipeline: wgpu::RenderPipeline,
    /// The shared raster pass's shading (`raster_fs`) for the diffuse objects in the atlas.
    diffuse_pipeline: wgpu::RenderPipeline,
    /// The pieces now and each impostor's reference point, rewritten each frame.
    pieces: wgpu::Buffer,
    centres: wgpu::Buffer,
    /// The bind group drawing pieces into impostors (no mover) and the one of the eye pass
    /// (separated: the mover set), made once; the piece data they read is rewritten.
    build_group: wgpu::BindGroup,
    eye_group: wgpu::BindGroup,
    /// Impostor renders (one per impostor per round) since `prepare` (for tests).
    rebuilds: u32,
    /// Where the moving piece's centre was when the frame's update last ran (none before the
    /// first frame): what `rebuild_threshold` measures from.
    updated_at: Option<Vec3>,
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
        let mut p = vec![Param::new(
            "env_depth",
            s.env_depth as f64,
            (0.0, MAX_ENV_DEPTH as f64),
            true,
            "rounds of drawing the pieces into each other's impostors (0: diffuse scene only)",
        )];
        p.push(Param::new(
            "rebuild_threshold",
            s.rebuild_threshold as f64,
            (0.0, 10.0),
            false,
            "metres the moving piece travels before the impostors are updated again (0: every \
             frame)",
        ));
        p.extend(
            s.maps
                .params("cube face size of each piece's environment impostor (texels)"),
        );
        p
    }
    fn set_param(&mut self, name: &str, value: f64) -> TechniqueResult<()> {
        check_param(&self.id, &self.params(), name, value)?;
        let s = &mut self.settings;
        match name {
            "env_depth" => s.env_depth = value as u32,
            "rebuild_threshold" => s.rebuild_threshold = value as f32,
            name if s.maps.set(name, value) => {}
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
        let m = &s.maps;
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
        let bytes = 2 * CubeArray::bytes(m.env_resolution, n, MAP_FORMAT)
            + CubeArray::bytes(m.resolution, kinds.representative.len() as u32, MAP_FORMAT);
        if bytes > scene::technique::MAP_BUDGET_BYTES {
            return Err(TechniqueError::OverBudget(format!(
                "{}: {n} impostors at {} texels and the refractor maps need {:.2} GB, over the \
                 {} MB budget of per-object maps; lower `env_resolution`",
                self.id,
                m.env_resolution,
                bytes as f64 / 1e9,
                scene::technique::MAP_BUDGET_BYTES >> 20
            )));
        }
        let kind_cubes = render_kind_maps(frame, scene, &kinds, m.resolution)?;
        let kind_maps = CubeArray::new(
            ctx,
            m.resolution,
            kind_cubes.len() as u32,
            MAP_FORMAT,
            "refractor maps",
        )?;
        for (k, cube) in kind_cubes.iter().enumerate() {
            kind_maps.copy_from_cube(frame.encoder, cube, k as u32);
        }
        let source = format!(
            "{}\n{}\n{}\n{}\n{}\n{}",
            scene::SCENE_WGSL,
            scene::RASTER_WGSL,
            HIT_WGSL,
            layered_hit_wgsl(),
            crate::pieces::PIECES_WGSL,
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
        let impostors = |label| CubeArray::new(ctx, m.env_resolution, n, MAP_FORMAT, label);
        let centres = kinds
            .pieces
            .iter()
            .map(|&(o, _)| scene.scene.objects[o].center_at(time))
            .collect();
        let mut piece_of_object = vec![EMPTY; scene.scene.objects.len()];
        for (piece, &(object, _)) in kinds.pieces.iter().enumerate() {
            piece_of_object[object] = piece as u32;
        }
        let piece_of_object = storage(ctx, "piece of object", &piece_of_object);
        let pieces = writable_storage(ctx, "pieces", n as u64 * size_of::<PieceGpu>() as u64);
        let centre_buffer = writable_storage(ctx, "impostor centres", n as u64 * 16);
        let current = impostors("piece impostors")?;
        let mover = movers.first().copied();
        let group = |mover: Option<usize>| {
            let params = Uniform::new(
                ctx,
                "environment params",
                &EnvParamsGpu {
                    mover: mover.map_or(EMPTY, |m| m as u32),
                    iterations: m.iterations,
                    env_iterations: m.env_iterations,
                    epsilon: m.epsilon,
                },
            );
            bind::group(
                ctx,
                "environment pieces",
                &layout,
                &[
                    params.binding(),
                    pieces.as_entire_binding(),
                    centre_buffer.as_entire_binding(),
                    piece_of_object.as_entire_binding(),
                    bind::sampler_resource(&ctx.samplers.linear_clamp),
                    bind::view(&current.array_view),
                    bind::view(&kind_maps.array_view),
                ],
            )
        };
        // Static pieces look for the moving one (separated only).
        let build_group = group(None);
        let eye_group = group(mover.filter(|_| s.separated));
        let mut state = State {
            kinds,
            current,
            atlas: Atlas::new(ctx, m.env_resolution, n)?,
            impostor_centres: centres,
            mover,
            eye_pipeline: pipeline(gpu::HDR_FORMAT),
            cube_pipeline: pipeline(MAP_FORMAT),
            diffuse_pipeline: scene::scene_pipeline(
                ctx,
                "impostor diffuse",
                &pipeline_layout,
                &module,
                "raster_fs",
                MAP_FORMAT,
            ),
            pieces,
            centres: centre_buffer,
            build_group,
            eye_group,
            rebuilds: 0,
            updated_at: None,
        };
        if s.separated {
            // The static impostors, once: every piece but the moving one, all rounds.
            let statics: Vec<usize> = (0..state.kinds.pieces.len())
                .filter(|p| Some(*p) != state.mover)
                .collect();
            frame.timer.begin(frame.encoder, "static impostors");
            build_impostors(
                frame,
                scene,
                &mut state,
                &statics,
                &statics,
                s.env_depth,
                true,
            );
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
        let mover_now = mover_centre(scene, state);
        if !update_due(state.updated_at, mover_now, s.rebuild_threshold) {
            // Not far enough: this frame keeps the impostors as they are.
        } else if s.separated {
            state.updated_at = Some(mover_now);
            frame.timer.begin(frame.encoder, "update impostors");
            if let Some(mover) = state.mover {
                let statics: Vec<usize> = all.iter().copied().filter(|&p| p != mover).collect();
                let rounds = s.env_depth.min(1);
                build_impostors(frame, scene, state, &[mover], &statics, rounds, rounds == 0);
            }
            frame.timer.end(frame.encoder, "update impostors");
        } else {
            state.updated_at = Some(mover_now);
            frame.timer.begin(frame.encoder, "update impostors");
            build_impostors(frame, scene, state, &all, &all, s.env_depth, true);
            frame.timer.end(frame.encoder, "update impostors");
        }

        let ctx = frame.gpu;
        write_pieces(ctx, state, scene);
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
        pass.set_bind_group(2, &state.eye_group, &[]);
        scene.draw_objects(&mut pass, &ObjectFilter::Only(objects));
        Ok(())
    }
}

/// Builds the impostors of pieces `targets` as the paper's pseudo code does (section 5.1):
/// first the diffuse scene alone into each, from the piece's centre now; then `rounds` rounds,
/// each rendering the diffuse scene and every piece of `drawn` but the target itself, shaded
/// with the impostors of the round before. A round reads only the impostors of the pieces it
/// draws, so the moving piece's single round (separated) needs no diffuse start.
///
/// A round draws every face of every target into one atlas in one render pass (a viewport per
/// face), then copies the faces into the impostor array (when the targets do not fit one atlas
/// on the adapter, a round takes several passes and a later pass reads the impostors an
/// earlier one of the same round rewrote; 33 impostors of 512 texels fit 8192-texel textures): the software rasterizer spends about
/// 20 ms and keeps 2.5 MB, never returned, for every render pass that samples these maps,
/// which a pass per face (200 per round on chess) turned into 1 GB per frame.
fn build_impostors(
    frame: &mut Frame,
    scene: &GpuScene,
    state: &mut State,
    targets: &[usize],
    drawn: &[usize],
    rounds: u32,
    diffuse_start: bool,
) {
    let ctx = frame.gpu;
    let (pieces, _) = pieces_at(&scene.scene, &state.kinds, scene.time());
    for &t in targets {
        state.impostor_centres[t] = pieces_centre(&pieces[t]);
    }
    write_pieces(ctx, state, scene);
    let far = 2.0 * scene::BACKGROUND_DISTANCE;
    let size = state.current.size;
    let start = if diffuse_start || rounds == 0 { 1 } else { 0 };
    let specular: Vec<usize> = state.kinds.pieces.iter().map(|&(o, _)| o).collect();
    let diffuse = ObjectFilter::Except(specular);
    for round in 1 - start..=rounds {
        let drawn = if round == 0 { &[][..] } else { drawn };
        for chunk in targets.chunks(state.atlas.impostors as usize) {
            let faces: Vec<(usize, usize)> = chunk
                .iter()
                .flat_map(|&t| (0..6).map(move |f| (t, f)))
                .collect();
            let cameras: Vec<(glam::Mat4, wgpu::BindGroup)> = faces
                .iter()
                .map(|&(t, f)| {
                    let centre = state.impostor_centres[t];
                    let view_proj = cube_face_view_proj(f, centre, 0.01, far);
                    (view_proj, scene.camera_bind_group(ctx, view_proj, centre))
                })
                .collect();
            {
                let target = RasterTarget {
                    color: &state.atlas.color_view,
                    depth: &state.atlas.depth_view,
                    format: MAP_FORMAT,
                    clear: true,
                };
                let mut pass = scene::begin_scene_pass(
                    frame.encoder,
                    &target,
                    scene.scene.background,
                    "impostor round",
                );
                pass.set_bind_group(1, scene.bind_group(), &[]);
                pass.set_bind_group(2, &state.build_group, &[]);
                for (tile, (&(t, _), (_, camera))) in faces.iter().zip(&cameras).enumerate() {
                    let (x, y) = state.atlas.tile_origin(tile as u32);
                    pass.set_viewport(x as f32, y as f32, size as f32, size as f32, 0.0, 1.0);
                    pass.set_scissor_rect(x, y, size, size);
                    pass.set_bind_group(0, camera, &[]);
                    pass.set_pipeline(&state.diffuse_pipeline);
                    scene.draw_objects(&mut pass, &diffuse);
                    let others: Vec<usize> = drawn
                        .iter()
                        .filter(|&&p| p != t)
                        .map(|&p| state.kinds.pieces[p].0)
                        .collect();
                    if !others.is_empty() {
                        pass.set_pipeline(&state.cube_pipeline);
                        scene.draw_objects(&mut pass, &ObjectFilter::Only(others));
                    }
                }
            }
            for (tile, &(t, f)) in faces.iter().enumerate() {
                state.atlas.copy_tile(
                    frame.encoder,
                    tile as u32,
                    &state.current,
                    (6 * t + f) as u32,
                );
            }
            state.rebuilds += chunk.len() as u32;
        }
    }
}

/// One render target holding many cube faces side by side (one tile per face), so a round of
/// impostor building is one render pass.
struct Atlas {
    color: wgpu::Texture,
    color_view: wgpu::TextureView,
    depth_view: wgpu::TextureView,
    size: u32,
    columns: u32,
    /// Impostors (6 tiles each) one pass renders.
    impostors: u32,
}

impl Atlas {
    /// The atlas for `impostors` impostors of `size` texels, or as many as the adapter's
    /// texture size allows (at least one: six tiles), or an error when not even one fits.
    fn new(ctx: &Context, size: u32, impostors: u32) -> Result<Atlas, TechniqueError> {
        let max = ctx.device.limits().max_texture_dimension_2d;
        let per_side = (max / size).max(1);
        let wanted = 6 * impostors.max(1);
        let columns = ((wanted as f32).sqrt().ceil() as u32).clamp(1, per_side);
        let rows = wanted.div_ceil(columns).min(per_side);
        let fit = columns * rows / 6;
        if fit == 0 {
            return Err(TechniqueError::Unsupported(format!(
                "env_resolution {size} is too large: six faces of it do not fit this adapter's \
                 {max}-texel textures"
            )));
        }
        let color = ctx.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("impostor atlas"),
            size: wgpu::Extent3d {
                width: columns * size,
                height: rows * size,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: MAP_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let depth = gpu::depth_texture(ctx, columns * size, rows * size, 1, "impostor atlas");
        Ok(Atlas {
            color_view: color.create_view(&Default::default()),
            depth_view: depth.create_view(&Default::default()),
            color,
            size,
            columns,
            impostors: fit.min(impostors.max(1)),
        })
    }

    fn tile_origin(&self, tile: u32) -> (u32, u32) {
        (
            (tile % self.columns) * self.size,
            (tile / self.columns) * self.size,
        )
    }

    fn copy_tile(&self, encoder: &mut wgpu::CommandEncoder, tile: u32, to: &CubeArray, layer: u32) {
        let (x, y) = self.tile_origin(tile);
        encoder.copy_texture_to_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &self.color,
                mip_level: 0,
                origin: wgpu::Origin3d { x, y, z: 0 },
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::TexelCopyTextureInfo {
                texture: &to.color,
                mip_level: 0,
                origin: wgpu::Origin3d {
                    x: 0,
                    y: 0,
                    z: layer,
                },
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::Extent3d {
                width: self.size,
                height: self.size,
                depth_or_array_layers: 1,
            },
        );
    }
}

fn pieces_centre(p: &PieceGpu) -> Vec3 {
    Vec3::new(p.centre[0], p.centre[1], p.centre[2])
}

/// Writes the pieces at the scene's time and the impostors' reference points into the
/// buffers both bind groups read (before this frame's commands run).
fn write_pieces(ctx: &Context, state: &State, scene: &GpuScene) {
    let (pieces, _) = pieces_at(&scene.scene, &state.kinds, scene.time());
    let centres: Vec<[f32; 4]> = state
        .impostor_centres
        .iter()
        .map(|c| c.extend(0.0).to_array())
        .collect();
    ctx.queue
        .write_buffer(&state.pieces, 0, bytemuck::cast_slice(&pieces));
    ctx.queue
        .write_buffer(&state.centres, 0, bytemuck::cast_slice(&centres));
}

/// The moving piece's centre now (the origin in a scene without one: nothing moves, so the
/// impostors need updating only once).
fn mover_centre(scene: &GpuScene, state: &State) -> Vec3 {
    let Some(mover) = state.mover else {
        return Vec3::ZERO;
    };
    let (pieces, _) = pieces_at(&scene.scene, &state.kinds, scene.time());
    pieces_centre(&pieces[mover])
}

/// Whether this frame updates the impostors: every frame with no threshold, else the first
/// frame and whenever the moving piece is more than `threshold` from where it was at the
/// last update.
fn update_due(updated_at: Option<Vec3>, mover_now: Vec3, threshold: f32) -> bool {
    match updated_at {
        None => true,
        Some(_) if threshold <= 0.0 => true,
        Some(at) => at.distance(mover_now) > threshold,
    }
}

/// A storage buffer of `bytes` (at least 16) that the queue rewrites.
fn writable_storage(ctx: &Context, label: &str, bytes: u64) -> wgpu::Buffer {
    ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes.max(16),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_update_is_due_first_then_every_frame_or_past_the_threshold() {
        let at = Some(Vec3::ZERO);
        let moved = Vec3::new(0.0, 0.0, 0.3);
        assert!(update_due(None, moved, 1.0));
        assert!(update_due(at, Vec3::ZERO, 0.0));
        assert!(!update_due(at, moved, 0.5));
        assert!(update_due(at, moved, 0.25));
    }
}
