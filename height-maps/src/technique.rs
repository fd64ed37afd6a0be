//! The height-map technique: [`HeightMaps`], configured as each variant.
//!
//! `prepare` renders one refractor height map per kind of piece (`scene::Kinds`: same mesh
//! and scale) and never again: pieces only translate, and the billboards turn in the shader.
//! Each frame:
//!
//! 1. the environment impostor: the diffuse scene as a distance impostor (rgb radiance, alpha
//!    distance) from the centre of the pieces' bounds, timed as "environment";
//! 2. the shared raster pass for the diffuse objects;
//! 3. every piece's proxy box, turned to face the eye, drawn with `billboard_fs`: the search
//!    from outside in the kind's height map, then reflection and one or two refractions
//!    (billboard.wgsl), timed as "billboards".

use crate::map::{map_bounds, render_height_maps, upright};
use crate::search::{SEARCH, Steps};
use gpu::wgpu::{self, util::DeviceExt};
use gpu::{Context, Target, Uniform, bind};
use scene::multi_object::{EnvironmentImpostor, raster_diffuse};
use scene::technique::{Declared, declared_params, declared_set};
use scene::{
    Frame, GpuScene, Kinds, Param, Scene, Technique, TechniqueError, TechniqueResult, View,
};

const BILLBOARD_WGSL: &str = include_str!("shaders/billboard.wgsl");
/// The billboard's proxy box (turned to face the eye): the module `height_maps::billboard_box`.
pub(crate) const BILLBOARD_BOX_WGSL: &str = include_str!("shaders/billboard_box.wgsl");
/// [`BILLBOARD_BOX_WGSL`] as a module, which both billboard shaders import.
pub static BILLBOARD_BOX: gpu::wgsl::Module = gpu::wgsl::Module::new(
    BILLBOARD_BOX_WGSL,
    "height-maps/src/shaders/billboard_box.wgsl",
    &[&SEARCH, &scene::SHADING],
);
/// Vertices of a billboard's box (`BOX_CORNERS` in billboard_box.wgsl): 12 triangles.
pub(crate) const BILLBOARD_BOX_VERTICES: u32 = 36;

/// What the refracted ray does after the first surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Refraction {
    /// It takes the diffuse environment at once (one interface).
    Single,
    /// It leaves the piece through the second search in the height map first (double
    /// refraction, total internal reflection followed for up to `chords` chords).
    Double,
}

/// The height maps and their searches: what every variant of the crate declares.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapSettings {
    /// The searches' steps (the binary search's halvings, the optional linear bracket).
    pub steps: Steps,
    /// Side of each kind's height map (texels).
    pub resolution: u32,
    /// Cube face size of the environment impostor.
    pub env_resolution: u32,
    /// Hit() refinement steps in the environment impostor.
    pub env_iterations: u32,
}

impl Default for MapSettings {
    fn default() -> Self {
        Self {
            steps: Steps::paper(8),
            resolution: 256,
            env_resolution: 256,
            env_iterations: 4,
        }
    }
}

impl scene::Settings for MapSettings {
    const DECLARED: &'static [Declared<Self>] = &[
        Declared::new(
            "steps",
            (0.0, 32.0),
            "halvings of each binary search in the height map",
            |s| Some(&mut s.steps.binary),
        ),
        Declared::new(
            "linear_steps",
            (0.0, 256.0),
            "even samples along a segment before the binary search (0: the paper's binary \
             search alone; more: relief mapping's linear bracket, not in the paper)",
            |s| Some(&mut s.steps.linear),
        ),
        Declared::new(
            "resolution",
            (4.0, 4096.0),
            "side of each kind's height map (texels)",
            |s| Some(&mut s.resolution),
        ),
        Declared::new(
            "env_resolution",
            (4.0, 4096.0),
            "cube face size of the diffuse environment impostor (texels)",
            |s| Some(&mut s.env_resolution),
        ),
        Declared::new(
            "env_iterations",
            (0.0, 64.0),
            "Hit() refinement steps in the environment impostor",
            |s| Some(&mut s.env_iterations),
        ),
    ];
}

/// Parameters of a [`HeightMaps`] variant (settable by name through
/// [`Technique::set_param`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// After the first surface.
    pub refraction: Refraction,
    /// The maps and their searches.
    pub maps: MapSettings,
    /// Chords a refracted ray follows inside a piece (double refraction).
    pub chords: u32,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            refraction: Refraction::Double,
            maps: MapSettings::default(),
            chords: 3,
        }
    }
}

impl scene::Settings for Settings {
    const DECLARED: &'static [Declared<Self>] = &[Declared::new(
        "chords",
        (1.0, 8.0),
        "chords a refracted ray follows inside a piece (double refraction)",
        |s| Some(&mut s.chords),
    )];
    fn params(&self) -> Vec<Param> {
        let mut params = self.maps.params();
        params.extend(declared_params(self));
        params
    }
    fn set(&mut self, name: &str, value: f64) -> bool {
        self.maps.set(name, value) || declared_set(self, name, value)
    }
}

/// A height-map technique variant.
pub struct HeightMaps {
    id: String,
    description: String,
    representative: bool,
    /// The variant's parameters.
    pub settings: Settings,
    /// The formats of the targets the billboards are drawn into (the harness's, or a
    /// renderer's own: [`HeightMaps::for_targets`]).
    formats: gpu::TargetFormats,
    state: Option<State>,
}

struct State {
    kinds: Kinds,
    maps: wgpu::Texture,
    maps_view: wgpu::TextureView,
    env: EnvironmentImpostor,
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
}

/// The uniform block `BillboardParams` of billboard.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ParamsGpu {
    env_reference: [f32; 4],
    linear_steps: u32,
    steps: u32,
    refraction: u32,
    env_iterations: u32,
    chords: u32,
    _pad: [u32; 3],
}

/// `PieceGpu` of billboard.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct PieceGpu {
    centre: [f32; 4],
    bounds: [f32; 4],
    object: [u32; 4],
}

impl HeightMaps {
    /// A variant named `id` (`height-maps/<variant>`).
    pub fn new(id: &str, description: &str, representative: bool, settings: Settings) -> Self {
        Self {
            id: id.into(),
            description: description.into(),
            representative,
            settings,
            formats: gpu::TargetFormats::HDR,
            state: None,
        }
    }

    /// The variant drawing its billboards into targets of `formats` (a renderer's own).
    pub fn for_targets(mut self, formats: gpu::TargetFormats) -> Self {
        self.formats = formats;
        self.state = None;
        self
    }

    /// The prepared height maps (a layer per kind, in kind order), for tests and images.
    pub fn height_maps(&self) -> Option<&wgpu::Texture> {
        self.state.as_ref().map(|s| &s.maps)
    }
}

/// Every variant of this crate.
pub fn variants() -> Vec<Box<dyn Technique>> {
    let s = Settings::default();
    let v = |id: &str, description: &str, settings: Settings| {
        Box::new(HeightMaps::new(
            &format!("height-maps/{id}"),
            description,
            true,
            settings,
        )) as Box<dyn Technique>
    };
    vec![
        v(
            "single",
            "the first surface by binary search in the piece's height map on a billboard facing \
             the eye; reflected and refracted rays take the diffuse environment (one interface)",
            Settings {
                refraction: Refraction::Single,
                ..s.clone()
            },
        ),
        v(
            "double-refraction",
            "as single, and the refracted ray leaves the piece through a second search in its \
             height map (section 6's double refraction, total internal reflection followed)",
            s,
        ),
    ]
}

impl Technique for HeightMaps {
    scene::named_variant!();
    scene::declared_params!(settings, state);
    fn supports(&self, scene: &Scene) -> bool {
        unsupported(&self.id, scene).is_none()
    }
    fn prepare(&mut self, frame: &mut Frame, scene: &GpuScene) -> TechniqueResult<()> {
        let ctx = frame.gpu;
        if let Some(why) = unsupported(&self.id, &scene.scene) {
            return Err(TechniqueError::Unsupported(why));
        }
        let kinds = Kinds::of(&scene.scene);
        let s = &self.settings.maps;
        scene::technique::check_map_budget(
            &self.id,
            kinds.representative.len(),
            (s.resolution as u64).pow(2) * 16,
            "resolution",
        )?;
        let module = scene::shader_importing(ctx, &self.id, BILLBOARD_WGSL, &[&BILLBOARD_BOX]);
        let layout = bind::layout(
            ctx,
            "height-map billboards",
            wgpu::ShaderStages::VERTEX_FRAGMENT,
            &[
                bind::uniform(),
                bind::storage(true),
                bind::texture(wgpu::TextureViewDimension::D2Array, false),
                bind::texture_cube(),
                bind::sampler(),
            ],
        );
        let pipeline = scene::proxy_pipeline_for(
            ctx,
            &self.id,
            &scene.pipeline_layout_with(ctx, &[&layout]),
            &module,
            ("billboard_vs", "billboard_fs"),
            self.formats,
        );
        let maps = render_height_maps(frame, scene, &kinds.representative, s.resolution)?;
        let maps_view = maps.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let env = EnvironmentImpostor::new(ctx, &scene.scene, &kinds, s.env_resolution)?;
        self.state = Some(State {
            kinds,
            maps,
            maps_view,
            env,
            layout,
            pipeline,
        });
        Ok(())
    }
    fn render(
        &mut self,
        frame: &mut Frame,
        scene: &GpuScene,
        view: &View,
        target: &Target,
    ) -> TechniqueResult<()> {
        let state = self
            .state
            .as_ref()
            .ok_or_else(|| TechniqueError::NotPrepared(self.id.clone()))?;
        let ctx = frame.gpu;
        let time = scene.time();

        let specular: Vec<usize> = state.kinds.pieces.iter().map(|&(o, _)| o).collect();
        state.env.capture(frame, scene, &specular);
        let view_proj = raster_diffuse(frame, scene, view, target, &specular);
        let group = frame_group(ctx, state, &self.settings, &scene.scene, time);
        let camera = scene.camera_bind_group(ctx, view_proj, view.camera.eye);
        let targets = (&target.color_view, &target.depth_view);
        draw_billboards(frame, scene, state, (&camera, &group), targets, &self.id);
        Ok(())
    }
}

/// Every piece's billboard box drawn with `billboard_fs` into `color` and `depth` (loaded),
/// timed as "billboards".
fn draw_billboards(
    frame: &mut Frame,
    scene: &GpuScene,
    state: &State,
    (camera, group): (&wgpu::BindGroup, &wgpu::BindGroup),
    (color, depth): (&wgpu::TextureView, &wgpu::TextureView),
    label: &str,
) {
    let drawn = (&state.pipeline, camera);
    let mut pass = scene.pass_over(frame, label, (color, depth), "billboards", drawn);
    pass.set_bind_group(2, group, &[]);
    pass.draw(
        0..BILLBOARD_BOX_VERTICES,
        0..state.kinds.pieces.len() as u32,
    );
}

impl scene::hosted::DrawOver for HeightMaps {
    /// The pieces of `pieces` (a renderer's objects, uploaded alone) drawn over `color` and
    /// `depth` (targets of the formats of [`HeightMaps::for_targets`], holding the renderer's
    /// frame): the environment impostor asked of `host` from the centre of the pieces where
    /// they now stand, then the billboards, depth-tested against what is there.
    fn draw_over(
        &mut self,
        frame: &mut Frame,
        (pieces, host): (&GpuScene, &dyn gpu::DrawScene),
        view: &gpu::EyeView,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
    ) -> TechniqueResult<()> {
        let state = self
            .state
            .as_mut()
            .ok_or_else(|| TechniqueError::NotPrepared(self.id.clone()))?;
        state.env.follow(&pieces.scene, &state.kinds);
        let specular: Vec<usize> = state.kinds.pieces.iter().map(|&(o, _)| o).collect();
        state.env.capture(frame, host, &specular);
        let group = frame_group(frame.gpu, state, &self.settings, &pieces.scene, 0.0);
        let camera = pieces.camera_bind_group(frame.gpu, view.view_proj(), view.eye());
        draw_billboards(
            frame,
            pieces,
            state,
            (&camera, &group),
            (color, depth),
            &self.id,
        );
        Ok(())
    }
}

/// Why `scene` cannot be rendered by a variant named `id`, if it cannot: it needs specular
/// objects, each standing upright (the billboard turns about the vertical).
pub(crate) fn unsupported(id: &str, scene: &Scene) -> Option<String> {
    let specular = scene.specular_objects();
    if specular.is_empty() {
        return Some(format!(
            "{id} renders specular objects and this scene has none"
        ));
    }
    specular
        .iter()
        .find(|&&o| !upright(&scene.objects[o]))
        .map(|&o| {
            format!(
                "{id} stands each specular object's height map upright on a billboard turning \
                 about the vertical, and `{}` does not keep its mesh's y axis vertical",
                scene.objects[o].name
            )
        })
}

/// This frame's `@group(2)`: parameters, pieces, height maps, environment impostor.
fn frame_group(
    ctx: &Context,
    state: &State,
    settings: &Settings,
    scene: &Scene,
    time: f32,
) -> wgpu::BindGroup {
    let params = ParamsGpu {
        env_reference: state.env.reference.extend(0.0).to_array(),
        linear_steps: settings.maps.steps.linear,
        steps: settings.maps.steps.binary,
        refraction: match settings.refraction {
            Refraction::Single => 0,
            Refraction::Double => 1,
        },
        env_iterations: settings.maps.env_iterations,
        chords: settings.chords,
        _pad: [0; 3],
    };
    let pieces: Vec<PieceGpu> = state
        .kinds
        .pieces
        .iter()
        .map(|&(object, kind)| {
            let o = &scene.objects[object];
            let b = map_bounds(o);
            PieceGpu {
                centre: o.center_at(time).extend(kind as f32).to_array(),
                bounds: [b.half_width, b.v_min, b.v_max, b.height],
                object: [object as u32, 0, 0, 0],
            }
        })
        .collect();
    let uniform = Uniform::new(ctx, "billboard params", &params);
    let piece_buffer = ctx
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("height-map pieces"),
            contents: bytemuck::cast_slice(&pieces),
            usage: wgpu::BufferUsages::STORAGE,
        });
    bind::group(
        ctx,
        "height-map billboards",
        &state.layout,
        &[
            uniform.binding(),
            piece_buffer.as_entire_binding(),
            bind::view(&state.maps_view),
            bind::view(state.env.view()),
            bind::sampler_resource(&ctx.samplers.linear_clamp),
        ],
    )
}
