//! Multi-bounce rays with per-piece environment distance impostors (paper section 5):
//! [`PieceImpostors`], the driver of `refractor-maps/{full-update,separated}` and
//! `height-maps/{full-update,separated}`, parameterised, like the tracer, by an
//! [`ObjectSearch`] (section 6: "in the algorithm described in 5.2, the refractor distance map
//! can be replaced by the refractor height map").
//!
//! Every piece keeps an environment impostor (a cube of radiance + distance taken from its
//! centre). A pixel of a piece needs three searches: the exit through its own map (the
//! search's `chord`) and `Hit()` in its impostor along the reflected and the exit rays
//! (`shaders/environment_pieces.wgsl`). The impostors hold multi-bounce radiance because they
//! are built in rounds (section 5.1): the diffuse scene first, then, `env_depth` times, every
//! other piece drawn into each impostor with the same shading and the impostors of the round
//! before.
//!
//! - full update rebuilds every impostor, all rounds, every frame: the paper's first test
//!   (1.8 FPS on its scene).
//! - separated (section 5.2) builds the static pieces' impostors once, in
//!   [`PieceImpostors::new`], without the moving piece; only the moving piece's impostor is
//!   rebuilt each frame (the diffuse scene and the static pieces drawn into it), and a static
//!   piece finds the moving one by searching its map from outside (the search's `piece_hit`)
//!   along each lookup ray (11.3 FPS in the paper, "approximately 6 times faster").
//!
//! How a piece's first hit is found is the caller's [`PieceSurface`]: its mesh rasterized
//! (refractor distance maps, sections 3-5) or a proxy drawn by the caller's own WGSL that finds
//! the hit itself (refractor height maps on billboards, section 6: the billboard decides
//! visibility), both in the eye pass and when pieces are drawn into each other's impostors.

use super::grid::EMPTY;
use super::pieces::{PIECES, PieceGpu, pieces_at};
use super::tracer::{ObjectSearch, driver_entries, driver_shader, storage};
use crate::kinds::Kinds;
use crate::technique::{Declared, MAP_BUDGET_BYTES, Settings, setting_if};
use crate::{
    Frame, GpuScene, ObjectFilter, RasterTarget, Scene, TechniqueError, TechniqueResult, View,
};
use glam::Vec3;
use gpu::cube::{CubeArray, cube_face_view_proj};
use gpu::pass::{self, Load};
use gpu::wgpu;
use gpu::{Context, Target, Uniform, bind};

/// The section-5 driver's bindings and shading (`shade_piece`), the module
/// `scene::environment_pieces` ([`ENVIRONMENT_PIECES`]).
pub const ENVIRONMENT_PIECES_WGSL: &str = include_str!("../shaders/environment_pieces.wgsl");
/// [`ENVIRONMENT_PIECES_WGSL`] as a module.
pub static ENVIRONMENT_PIECES: gpu::wgsl::Module = gpu::wgsl::Module::new(
    ENVIRONMENT_PIECES_WGSL,
    "scene/src/shaders/environment_pieces.wgsl",
    &[&PIECES, &crate::SHADING],
);
/// The pieces' meshes shaded by [`ENVIRONMENT_PIECES`]: `environment_piece_fs`.
pub const ENVIRONMENT_PIECE_FS_WGSL: &str = include_str!("../shaders/environment_piece_fs.wgsl");

/// The help of a section-5 variant's `env_resolution`: each piece's impostor (a search's maps
/// declare it for the tracer's one impostor of the diffuse scene).
pub const PIECE_IMPOSTOR_HELP: &str =
    "cube face size of each piece's environment impostor (texels)";

/// `params` with `env_resolution`'s help naming each piece's impostor
/// ([`PIECE_IMPOSTOR_HELP`]): what the section-5 settings list of their maps.
pub fn piece_impostor_help(params: Vec<crate::Param>) -> Vec<crate::Param> {
    params
        .into_iter()
        .map(|mut param| {
            if param.name == "env_resolution" {
                param.help = PIECE_IMPOSTOR_HELP;
            }
            param
        })
        .collect()
}

/// Format of the impostors (radiance + distance).
pub const IMPOSTOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// Deepest multi-bounce build of the impostors (`env_depth`).
pub const MAX_ENV_DEPTH: u32 = 8;

/// The impostors' own parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImpostorSettings {
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
    /// Cube face size of each piece's impostor (declared with a technique's other maps: see
    /// [`ImpostorSettings::with_maps`]).
    pub env_resolution: u32,
    /// Hit() refinement steps in the impostors (likewise).
    pub env_iterations: u32,
    /// Separated: whether the static pieces search for the moving one from outside along
    /// their lookup rays (section 5.2). Off, they show their static impostors alone, which
    /// lack the moving piece: the ablation that shows what the search from outside adds.
    pub find_mover: bool,
}

impl ImpostorSettings {
    /// The separated defaults: two rounds, updated every frame, 128-texel impostors searched
    /// with 4 steps.
    pub fn separated() -> Self {
        Self {
            separated: true,
            env_depth: 2,
            rebuild_threshold: 0.0,
            env_resolution: 128,
            env_iterations: 4,
            find_mover: true,
        }
    }

    /// These settings with the impostors' size and search steps of a technique's map
    /// settings, which declare them beside their other maps'.
    pub fn with_maps(self, env_resolution: u32, env_iterations: u32) -> Self {
        Self {
            env_resolution,
            env_iterations,
            ..self
        }
    }
}

impl Settings for ImpostorSettings {
    /// The parameters both families declare (`env_resolution` and `env_iterations` are
    /// declared with their other maps'; `find_mover` by separated variants only).
    const DECLARED: &'static [Declared<Self>] = &[
        Declared::new(
            "env_depth",
            (0.0, MAX_ENV_DEPTH as f64),
            "rounds of drawing the pieces into each other's impostors (0: diffuse scene \
             only)",
            |s| Some(&mut s.env_depth),
        ),
        Declared::new(
            "rebuild_threshold",
            (0.0, 10.0),
            "metres the moving piece travels before the impostors are updated again (0: \
             every frame)",
            |s| Some(&mut s.rebuild_threshold),
        ),
        Declared::new(
            "find_mover",
            (0.0, 1.0),
            "separated: 1, the static pieces find the moving one from outside (section \
             5.2); 0, they show their static impostors alone, without it",
            |s| setting_if(s.separated, &mut s.find_mover),
        ),
    ];
}

/// How a piece's first hit is found, in the eye pass and when pieces are drawn into
/// impostors.
#[derive(Clone, Copy, Debug)]
pub enum PieceSurface {
    /// The piece's mesh is rasterized (`environment_piece_fs`).
    Mesh,
    /// `vertices` vertices per piece (instance = piece index) of the caller's entry points,
    /// drawn without a vertex buffer: the fragment finds the hit (discarding a miss), writes
    /// its depth and returns `shade_piece`'s answer.
    Proxy {
        /// The entry points' WGSL, importing from `scene::environment_pieces`,
        /// `scene::pieces`, the search's module and `imports`.
        source: &'static str,
        /// Modules of the caller's own that `source` imports.
        imports: &'static [&'static gpu::wgsl::Module],
        /// The vertex entry point.
        vertex: &'static str,
        /// The fragment entry point.
        fragment: &'static str,
        /// Vertices per piece.
        vertices: u32,
    },
}

/// The uniform block `EnvParams` of environment_pieces.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct EnvParamsGpu {
    mover: u32,
    env_iterations: u32,
    _pad: [u32; 2],
}

/// The per-piece impostors of one scene, prepared for one [`ObjectSearch`] and
/// [`PieceSurface`].
pub struct PieceImpostors {
    kinds: Kinds,
    surface: PieceSurface,
    /// The impostor of piece p (in `kinds.pieces` order) is cube p; a round renders into the
    /// atlas while reading `current`, then copies its faces over.
    current: CubeArray,
    atlas: Atlas,
    /// The point each impostor was taken from.
    impostor_centres: Vec<Vec3>,
    /// The moving piece (separated: its impostor is rebuilt each frame, the others never).
    mover: Option<usize>,
    shading: Shading,
    /// The pieces now and each impostor's reference point, rewritten each frame.
    pieces: wgpu::Buffer,
    centres: wgpu::Buffer,
    /// The bind group drawing pieces into impostors (no mover) and the one of the eye pass
    /// (separated: the mover set), made once; the piece data they read is rewritten.
    build_group: wgpu::BindGroup,
    eye_group: wgpu::BindGroup,
    /// Impostor renders (one per impostor per round) since `new` (for tests).
    rebuilds: u32,
    /// Where the moving piece's centre was when the frame's update last ran (none before the
    /// first frame): what `rebuild_threshold` measures from.
    updated_at: Option<Vec3>,
}

impl PieceImpostors {
    /// GPU memory of the impostors of `pieces` pieces at `resolution` texels (two arrays: the
    /// impostors and the atlas a round renders into).
    pub fn bytes(resolution: u32, pieces: usize) -> u64 {
        2 * CubeArray::bytes(resolution, pieces as u32, IMPOSTOR_FORMAT)
    }

    /// Fails, before anything is rendered, where [`PieceImpostors::new`] would: separated
    /// with more than one moving piece, or the impostors and the caller's own maps
    /// (`map_bytes`) over [`MAP_BUDGET_BYTES`]. Callers run it before rendering their maps.
    pub fn check(
        scene: &Scene,
        kinds: &Kinds,
        settings: &ImpostorSettings,
        map_bytes: u64,
        label: &str,
    ) -> TechniqueResult<()> {
        let movers = movers(scene, kinds);
        if settings.separated && movers.len() > 1 {
            return Err(TechniqueError::Unsupported(format!(
                "{label} separates one moving piece from the static ones (as a chess move \
                 does); this scene has {} moving specular objects",
                movers.len()
            )));
        }
        let n = kinds.pieces.len();
        let bytes = Self::bytes(settings.env_resolution, n) + map_bytes;
        if bytes > MAP_BUDGET_BYTES {
            return Err(TechniqueError::OverBudget(format!(
                "{label}: {n} impostors at {} texels and the pieces' maps need {:.2} GB, over \
                 the {} MB budget of per-object maps; lower `env_resolution`",
                settings.env_resolution,
                bytes as f64 / 1e9,
                MAP_BUDGET_BYTES >> 20
            )));
        }
        Ok(())
    }

    /// The impostors of `scene`'s specular objects (`kinds`), shaded through `search`, the
    /// pieces drawn as `surface`; separated, the static impostors are built here, timed as "static impostors".
    /// `map_bytes` is what the caller's own maps take (see [`PieceImpostors::check`]).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        frame: &mut Frame,
        scene: &GpuScene,
        kinds: Kinds,
        search: &dyn ObjectSearch,
        surface: PieceSurface,
        settings: &ImpostorSettings,
        map_bytes: u64,
        label: &str,
    ) -> TechniqueResult<Self> {
        Self::check(&scene.scene, &kinds, settings, map_bytes, label)?;
        let ctx = frame.gpu;
        let n = kinds.pieces.len();
        let shading = Shading::new(ctx, scene, search, surface, label);
        let time = scene.time();
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
        let pieces = writable_storage(ctx, "pieces", (n * size_of::<PieceGpu>()) as u64);
        let centre_buffer = writable_storage(ctx, "impostor centres", n as u64 * 16);
        let current = CubeArray::new(
            ctx,
            settings.env_resolution,
            n as u32,
            IMPOSTOR_FORMAT,
            "piece impostors",
        )?;
        let mover = movers(&scene.scene, &kinds).first().copied();
        let group = |mover: Option<usize>| {
            let params = Uniform::new(
                ctx,
                "environment params",
                &EnvParamsGpu {
                    mover: mover.map_or(EMPTY, |m| m as u32),
                    env_iterations: settings.env_iterations,
                    _pad: [0; 2],
                },
            );
            let mut resources = vec![
                params.binding(),
                pieces.as_entire_binding(),
                centre_buffer.as_entire_binding(),
                piece_of_object.as_entire_binding(),
                bind::sampler_resource(&ctx.samplers.linear_clamp),
                bind::view(&current.array_view),
            ];
            resources.extend(search.resources());
            bind::group(ctx, "environment pieces", &shading.layout, &resources)
        };
        // Static pieces look for the moving one (separated only).
        let build_group = group(None);
        let eye_group = group(mover.filter(|_| settings.separated && settings.find_mover));
        let mut impostors = PieceImpostors {
            surface,
            current,
            atlas: Atlas::new(ctx, settings.env_resolution, n as u32)?,
            impostor_centres: centres,
            mover,
            shading,
            pieces,
            centres: centre_buffer,
            build_group,
            eye_group,
            rebuilds: 0,
            updated_at: None,
            kinds,
        };
        if settings.separated {
            // The static impostors, once: every piece but the moving one, all rounds.
            let statics: Vec<usize> = (0..n).filter(|p| Some(*p) != impostors.mover).collect();
            frame.span("static impostors", |frame| {
                impostors.build(frame, scene, &statics, &statics, settings.env_depth, true)
            });
        }
        Ok(impostors)
    }

    /// The specular objects and their kinds.
    pub fn kinds(&self) -> &Kinds {
        &self.kinds
    }

    /// Impostor renders (one per impostor per round) since [`PieceImpostors::new`] (for
    /// tests).
    pub fn rebuilds(&self) -> u32 {
        self.rebuilds
    }

    /// Records a frame: the impostors' update when one is due (timed as "update impostors"),
    /// the shared raster pass for the diffuse objects, then the pieces shaded through their
    /// impostors (timed as "pieces"). `settings` are those of [`PieceImpostors::new`].
    pub fn render(
        &mut self,
        frame: &mut Frame,
        scene: &GpuScene,
        view: &View,
        target: &Target,
        settings: &ImpostorSettings,
        label: &str,
    ) {
        self.update(frame, scene, settings);
        let ctx = frame.gpu;
        self.write_pieces(ctx, scene);
        let view_proj = view.camera.view_proj(view.width, view.height);
        let main = RasterTarget::of(target, true);
        let all: Vec<usize> = (0..self.kinds.pieces.len()).collect();
        let objects = self.objects(&all);
        scene.raster(
            frame,
            &main,
            view_proj,
            view.camera.eye,
            &ObjectFilter::Except(objects),
            false,
        );
        let camera = scene.camera_bind_group(ctx, view_proj, view.camera.eye);
        let mut pass = gpu::pass::begin(
            frame.encoder,
            label,
            &[pass::color(&target.color_view, Load::Keep)],
            Some(pass::depth(&target.depth_view, Load::Keep)),
            frame.timer.render_pass("pieces"),
        );
        pass.set_pipeline(&self.shading.eye);
        pass.set_bind_group(0, &camera, &[]);
        pass.set_bind_group(1, scene.bind_group(), &[]);
        pass.set_bind_group(2, &self.eye_group, &[]);
        self.draw_pieces(&mut pass, scene, &all);
    }

    /// This frame's update of the impostors, when one is due: separated, the moving piece's
    /// (one round over the static pieces, whose impostors hold the rest); full update, every
    /// impostor, all rounds.
    fn update(&mut self, frame: &mut Frame, scene: &GpuScene, settings: &ImpostorSettings) {
        let mover_now = self.mover_centre(scene);
        if !update_due(self.updated_at, mover_now, settings.rebuild_threshold) {
            // Not far enough: this frame keeps the impostors as they are.
            return;
        }
        self.updated_at = Some(mover_now);
        let all: Vec<usize> = (0..self.kinds.pieces.len()).collect();
        frame.span("update impostors", |frame| {
            if !settings.separated {
                self.build(frame, scene, &all, &all, settings.env_depth, true);
            } else if let Some(mover) = self.mover {
                let statics: Vec<usize> = all.iter().copied().filter(|&p| p != mover).collect();
                let rounds = settings.env_depth.min(1);
                self.build(frame, scene, &[mover], &statics, rounds, rounds == 0);
            }
        });
    }

    /// The scene objects of pieces `pieces`.
    fn objects(&self, pieces: &[usize]) -> Vec<usize> {
        pieces.iter().map(|&p| self.kinds.pieces[p].0).collect()
    }

    /// Draws pieces `pieces` (ascending) with the bound pipeline: their meshes, or their
    /// proxies, one draw per run of consecutive pieces.
    fn draw_pieces(&self, pass: &mut wgpu::RenderPass<'_>, scene: &GpuScene, pieces: &[usize]) {
        match self.surface {
            PieceSurface::Mesh => {
                scene.draw_objects(pass, &ObjectFilter::Only(self.objects(pieces)));
            }
            PieceSurface::Proxy { vertices, .. } => {
                for run in pieces.chunk_by(|a, b| b == &(a + 1)) {
                    let first = run[0] as u32;
                    pass.draw(0..vertices, first..first + run.len() as u32);
                }
            }
        }
    }

    /// Builds the impostors of pieces `targets` as the paper's pseudo code does (section
    /// 5.1): first the diffuse scene alone into each, from the piece's centre now; then
    /// `rounds` rounds, each rendering the diffuse scene and every piece of `drawn` but the
    /// target itself, shaded with the impostors of the round before. A round reads only the
    /// impostors of the pieces it draws, so the moving piece's single round (separated) needs
    /// no diffuse start.
    ///
    /// A round draws every face of every target into one atlas in one render pass (a viewport
    /// per face), then copies the faces into the impostor array (when the targets do not fit
    /// one atlas on the adapter, a round takes several passes and a later pass reads the
    /// impostors an earlier one of the same round rewrote; 33 impostors of 512 texels fit
    /// 8192-texel textures): the software rasterizer spends about 20 ms and keeps 2.5 MB,
    /// never returned, for every render pass that samples these maps, which a pass per face
    /// (200 per round on chess) turned into 1 GB per frame.
    fn build(
        &mut self,
        frame: &mut Frame,
        scene: &GpuScene,
        targets: &[usize],
        drawn: &[usize],
        rounds: u32,
        diffuse_start: bool,
    ) {
        let ctx = frame.gpu;
        let (pieces, _) = pieces_at(&scene.scene, &self.kinds, scene.time());
        for &t in targets {
            self.impostor_centres[t] = centre_of(&pieces[t]);
        }
        self.write_pieces(ctx, scene);
        let start = if diffuse_start || rounds == 0 { 1 } else { 0 };
        for round in 1 - start..=rounds {
            let drawn = if round == 0 { &[][..] } else { drawn };
            for chunk in targets.chunks(self.atlas.impostors as usize) {
                self.build_round(frame, scene, chunk, drawn);
                self.rebuilds += chunk.len() as u32;
            }
        }
    }

    /// One round of [`PieceImpostors::build`] for the impostors `targets` (fitting one atlas):
    /// every face drawn into its atlas tile, then copied into the impostor array.
    fn build_round(&self, frame: &mut Frame, scene: &GpuScene, targets: &[usize], drawn: &[usize]) {
        let ctx = frame.gpu;
        let far = 2.0 * crate::BACKGROUND_DISTANCE;
        let size = self.current.size;
        let all: Vec<usize> = (0..self.kinds.pieces.len()).collect();
        let diffuse = ObjectFilter::Except(self.objects(&all));
        let faces: Vec<(usize, usize)> = targets
            .iter()
            .flat_map(|&t| (0..6).map(move |f| (t, f)))
            .collect();
        let cameras: Vec<wgpu::BindGroup> = faces
            .iter()
            .map(|&(t, f)| {
                let centre = self.impostor_centres[t];
                let view_proj = cube_face_view_proj(f, centre, 0.01, far);
                scene.camera_bind_group(ctx, view_proj, centre)
            })
            .collect();
        {
            let target = RasterTarget {
                color: &self.atlas.color_view,
                depth: &self.atlas.depth_view,
                format: IMPOSTOR_FORMAT,
                clear: true,
            };
            let mut pass = crate::begin_scene_pass(
                frame.encoder,
                &target,
                scene.scene.background,
                "impostor round",
            );
            pass.set_bind_group(1, scene.bind_group(), &[]);
            pass.set_bind_group(2, &self.build_group, &[]);
            for (tile, (&(t, _), camera)) in faces.iter().zip(&cameras).enumerate() {
                let (x, y) = self.atlas.tile_origin(tile as u32);
                pass.set_viewport(x as f32, y as f32, size as f32, size as f32, 0.0, 1.0);
                pass.set_scissor_rect(x, y, size, size);
                pass.set_bind_group(0, camera, &[]);
                pass.set_pipeline(&self.shading.diffuse);
                scene.draw_objects(&mut pass, &diffuse);
                let others: Vec<usize> = drawn.iter().copied().filter(|&p| p != t).collect();
                if !others.is_empty() {
                    pass.set_pipeline(&self.shading.cube);
                    self.draw_pieces(&mut pass, scene, &others);
                }
            }
        }
        for (tile, &(t, f)) in faces.iter().enumerate() {
            self.atlas.copy_tile(
                frame.encoder,
                tile as u32,
                &self.current,
                (6 * t + f) as u32,
            );
        }
    }

    /// Writes the pieces at the scene's time and the impostors' reference points into the
    /// buffers both bind groups read (before this frame's commands run).
    fn write_pieces(&self, ctx: &Context, scene: &GpuScene) {
        let (pieces, _) = pieces_at(&scene.scene, &self.kinds, scene.time());
        let centres: Vec<[f32; 4]> = self
            .impostor_centres
            .iter()
            .map(|c| c.extend(0.0).to_array())
            .collect();
        ctx.queue
            .write_buffer(&self.pieces, 0, bytemuck::cast_slice(&pieces));
        ctx.queue
            .write_buffer(&self.centres, 0, bytemuck::cast_slice(&centres));
    }

    /// The moving piece's centre now (the origin in a scene without one: nothing moves, so
    /// the impostors need updating only once).
    fn mover_centre(&self, scene: &GpuScene) -> Vec3 {
        let Some(mover) = self.mover else {
            return Vec3::ZERO;
        };
        let (pieces, _) = pieces_at(&scene.scene, &self.kinds, scene.time());
        centre_of(&pieces[mover])
    }
}

/// The pieces' shading: the pieces' shader (their meshes' `environment_piece_fs`, or a
/// proxy's entry points, over `scene::environment_pieces` with the search's overrides:
/// `driver_shader`), its `@group(2)` layout and the three pipelines.
struct Shading {
    layout: wgpu::BindGroupLayout,
    /// The pieces into the frame's target.
    eye: wgpu::RenderPipeline,
    /// The pieces into the impostor atlas.
    cube: wgpu::RenderPipeline,
    /// The shared raster pass's shading (`raster_fs`) for the diffuse objects in the atlas.
    diffuse: wgpu::RenderPipeline,
}

impl Shading {
    fn new(
        ctx: &Context,
        scene: &GpuScene,
        search: &dyn ObjectSearch,
        surface: PieceSurface,
        label: &str,
    ) -> Self {
        let (source, imports) = match surface {
            PieceSurface::Mesh => (ENVIRONMENT_PIECE_FS_WGSL, &[][..]),
            PieceSurface::Proxy {
                source, imports, ..
            } => (source, imports),
        };
        let module = driver_shader(ctx, label, source, imports, search);
        // The diffuse objects drawn into the atlas: the shared raster pass's shading.
        let raster = crate::shader(ctx, "impostor diffuse", crate::RASTER_WGSL);
        let mut entries =
            driver_entries(bind::texture(wgpu::TextureViewDimension::CubeArray, true));
        entries.extend(search.binding_types());
        // The vertex stage too: a proxy's vertex entry reads the piece table and the search's
        // bounds.
        let layout = bind::layout(
            ctx,
            "environment pieces",
            wgpu::ShaderStages::VERTEX_FRAGMENT,
            &entries,
        );
        let pipeline_layout = scene.pipeline_layout_with(ctx, &[&layout]);
        let pipeline = |format| match surface {
            PieceSurface::Mesh => crate::scene_pipeline(
                ctx,
                label,
                &pipeline_layout,
                &module,
                "environment_piece_fs",
                format,
            ),
            PieceSurface::Proxy {
                vertex, fragment, ..
            } => crate::proxy_pipeline(
                ctx,
                label,
                &pipeline_layout,
                &module,
                (vertex, fragment),
                format,
            ),
        };
        Self {
            eye: pipeline(gpu::HDR_FORMAT),
            cube: pipeline(IMPOSTOR_FORMAT),
            diffuse: crate::scene_pipeline(
                ctx,
                "impostor diffuse",
                &pipeline_layout,
                &raster,
                "raster_fs",
                IMPOSTOR_FORMAT,
            ),
            layout,
        }
    }
}

/// The pieces (indices into `kinds.pieces`) that move over the scene's time.
fn movers(scene: &Scene, kinds: &Kinds) -> Vec<usize> {
    kinds
        .pieces
        .iter()
        .enumerate()
        .filter(|(_, (o, _))| !scene.objects[*o].motion.is_static())
        .map(|(p, _)| p)
        .collect()
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
            format: IMPOSTOR_FORMAT,
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

fn centre_of(p: &PieceGpu) -> Vec3 {
    Vec3::new(p.centre[0], p.centre[1], p.centre[2])
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
