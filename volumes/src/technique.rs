//! The volume techniques of thesis section 6.3 behind the workspace's `Technique` trait.
//!
//! One frame:
//!
//! 1. (ray-traced volumes, unless `free_depth`; billboards and slices only with
//!    `depth_prepass`) the depth pre-pass of 6.3.3: the scene's distance from the eye into an
//!    R16Float texture, timed as the span `scene-depth`;
//! 2. the diffuse scene with `GpuScene::raster` into an Rgba16Float colour buffer, with the
//!    target's depth buffer;
//! 3. (8-bit slices) a full-screen copy of that colour into an Rgba8Unorm buffer: from here the
//!    slices blend at 8 bits per channel, as in a 2008 frame buffer;
//! 4. the volumes, sorted back to front, as camera-facing quads in one instanced draw, timed
//!    as the span `volumes`: billboards and slices depth-tested against the scene, ray-traced
//!    billboards without depth test reading the scene distance instead;
//! 5. a full-screen resolve of the colour buffer into the target (alpha 1).
//!
//! The target is `Rgba32Float`, which is not blendable without `FLOAT32_BLENDABLE` (the shared
//! context does not request it); the Rgba16Float buffer of steps 2-5 is the thesis's "floating
//! point colour buffer" (16 bits were enough, 6.3.2).

use crate::path_length::{
    OpacityFn, PATH_LENGTH_WGSL, Primitive, THICKNESS_TEXTURE_SIZE, bake_thickness,
};
use glam::Vec3;
use gpu::pass::{self, Load};
use gpu::wgpu::{self, util::DeviceExt};
use gpu::{Context, Target, bind};
use scene::Settings as _;
use scene::technique::{Declared, not_prepared, set_checked, setting_if};
use scene::{
    BACKGROUND_DISTANCE, Camera, Frame, GpuScene, ObjectFilter, Param, RasterTarget, Scene,
    Technique, TechniqueResult, View, Volume,
};

const VOLUMES_WGSL: &str = include_str!("shaders/volumes.wgsl");
const COPY_WGSL: &str = include_str!("shaders/copy.wgsl");
const SCENE_DISTANCE_WGSL: &str = include_str!("shaders/scene_distance.wgsl");

/// Colour buffer the scene and the volumes are composited in (the "floating point buffer").
pub const FLOAT_BUFFER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Colour buffer of the 8-bit slice variants.
pub const BYTE_BUFFER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
/// The depth pre-pass's distance texture: "a 16 bit floating point texture" (6.3.3).
pub const DISTANCE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R16Float;

/// Which volumes of a scene a variant draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum VolumeSet {
    /// The large volumes (`particle == false`): the thesis's "simple, large particle" that its
    /// 17 tests analyse.
    Single,
    /// Every volume (the particle-system versions).
    All,
}

impl VolumeSet {
    /// Whether a variant drawing this set draws volume `v`.
    pub fn includes(self, v: &Volume) -> bool {
        match self {
            VolumeSet::Single => !v.particle,
            VolumeSet::All => true,
        }
    }
}

/// Optical depth of a volume's chord through its centre, without its noise texture:
/// `density R integral_{-1}^{1} (1 - x^2)^k dx` (midpoint rule, 256 steps: exact to 1e-5 for
/// the profiles in use).
pub fn centre_optical_depth(v: &Volume) -> f32 {
    let n = 256;
    let smooth = scene::DensityProfile {
        noise: 0.0,
        ..v.profile
    };
    let shape: f32 = (0..n)
        .map(|i| {
            let x = -1.0 + (i as f32 + 0.5) * 2.0 / n as f32;
            smooth.shape(Vec3::new(x, 0.0, 0.0)) * 2.0 / n as f32
        })
        .sum();
    v.density * v.radius * shape
}

/// The opacity reached over one metre (the scale of the thesis's opacity functions) that
/// makes `opacity` give a volume's true centre opacity `1 - exp(-tau_c)` over its diameter,
/// tau_c = [`centre_optical_depth`]. This is how a variant reads the scene's density field
/// (an artist matching the smoke's look at its centre); away from the centre each opacity
/// function departs from Beer-Lambert in its own way, which is part of its error.
pub fn opacity_scale(v: &Volume, opacity: OpacityFn) -> f32 {
    let alpha = 1.0 - (-centre_optical_depth(v)).exp();
    opacity.scale_for(alpha, 2.0 * v.radius)
}

/// How a variant renders a volume.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    /// 6.3.1: one textured billboard, no volume.
    Billboard,
    /// 6.3.2: `count` parallel slices; `float_buffer` blends them in Rgba16Float instead of
    /// Rgba8Unorm.
    Slices {
        /// Number of slices (the thesis tests 5, 9, 19, 39 and 79).
        count: u32,
        /// Blend the slices in `FLOAT_BUFFER_FORMAT` (true) or `BYTE_BUFFER_FORMAT` (false).
        float_buffer: bool,
    },
    /// 6.3.3: a billboard that ray-traces a volume primitive against the scene distance.
    Raytraced(Primitive),
    /// Engine baseline: the depth-fade soft particle every engine ships: the textured
    /// billboard of `Billboard` without depth test, its opacity multiplied by
    /// `path_length::depth_fade` of the scene depth (the raster pass's depth buffer) behind it.
    DepthFade,
}

/// One technique variant: method, opacity function and which volumes it draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Variant {
    /// How each volume is drawn (billboard, slices, ray-traced primitive).
    pub method: Method,
    /// How the visible path length becomes opacity (thesis figure 6.21).
    pub opacity: OpacityFn,
    /// Which of the scene's volumes are drawn.
    pub set: VolumeSet,
}

impl Variant {
    /// `volumes/<name>`, `volumes/particles-<name>` for the particle-system versions.
    pub fn id(&self) -> String {
        let name = match self.method {
            Method::Billboard => "billboard".to_string(),
            Method::DepthFade => "depth-fade".to_string(),
            Method::Slices {
                count,
                float_buffer,
            } => {
                format!("slices-{count}{}", if float_buffer { "-float" } else { "" })
            }
            Method::Raytraced(Primitive::Constant) => "raytraced-constant".into(),
            Method::Raytraced(Primitive::Linear) => "raytraced-linear".into(),
            Method::Raytraced(Primitive::Texture) => "raytraced-thickness".into(),
            Method::Raytraced(Primitive::Sphere) => {
                format!("raytraced-sphere-{}", self.opacity.name())
            }
        };
        let suffix = match (self.method, self.opacity) {
            (Method::Raytraced(Primitive::Sphere), _) | (_, OpacityFn::Log) => String::new(),
            (_, f) => format!("-{}", f.name()),
        };
        let prefix = if self.set == VolumeSet::All {
            "particles-"
        } else {
            ""
        };
        format!("volumes/{prefix}{name}{suffix}")
    }

    /// The test number of the thesis's figure 6.23 this variant reproduces.
    pub fn thesis_test(&self) -> Option<u32> {
        if self.set != VolumeSet::Single {
            return None;
        }
        let slice_rank = |n: u32| {
            [5, 9, 19, 39, 79]
                .iter()
                .position(|&m| m == n)
                .map(|p| p as u32)
        };
        match (self.method, self.opacity) {
            (Method::Billboard, OpacityFn::Log) => Some(1),
            (
                Method::Slices {
                    count,
                    float_buffer,
                },
                OpacityFn::Log,
            ) => slice_rank(count).map(|r| if float_buffer { 7 + r } else { 2 + r }),
            (Method::Raytraced(Primitive::Constant), OpacityFn::Log) => Some(12),
            (Method::Raytraced(Primitive::Linear), OpacityFn::Log) => Some(13),
            (Method::Raytraced(Primitive::Sphere), OpacityFn::Log) => Some(14),
            (Method::Raytraced(Primitive::Sphere), OpacityFn::Linear) => Some(15),
            (Method::Raytraced(Primitive::Sphere), OpacityFn::Sqrt) => Some(16),
            (Method::Raytraced(Primitive::Texture), OpacityFn::Log) => Some(17),
            _ => None,
        }
    }

    fn description(&self) -> String {
        let what = match self.method {
            Method::Billboard => "simple billboard, no volume (6.3.1)".to_string(),
            Method::DepthFade => "engine baseline: depth-fade soft particle, the textured \
                                  billboard faded by (scene depth - billboard depth) / fade"
                .to_string(),
            Method::Slices {
                count,
                float_buffer,
            } => format!(
                "{count} camera-facing slices forming a sphere, perspective-corrected texture \
                 coordinates, {} colour buffer (6.3.2)",
                if float_buffer {
                    "16-bit float"
                } else {
                    "8-bit"
                }
            ),
            Method::Raytraced(p) => format!(
                "ray-traced {} against the scene depth (6.3.3)",
                match p {
                    Primitive::Constant => "constant-thickness volume",
                    Primitive::Linear => "linearly decreasing thickness volume",
                    Primitive::Sphere => "sphere",
                    Primitive::Texture => "thickness-texture volume",
                }
            ),
        };
        let set = match self.set {
            VolumeSet::Single => "the scene's large volumes",
            VolumeSet::All => "every volume as a particle system",
        };
        let test = self
            .thesis_test()
            .map(|t| format!(", thesis fig. 6.23 test {t}"))
            .unwrap_or_default();
        format!(
            "{what}; {} path-length-to-opacity; {set}{test}",
            self.opacity.name()
        )
    }
}

/// The 17 variants of the thesis's figure 6.23, in its order.
pub fn thesis_variants() -> Vec<Variant> {
    let single = |method, opacity| Variant {
        method,
        opacity,
        set: VolumeSet::Single,
    };
    let mut out = vec![single(Method::Billboard, OpacityFn::Log)];
    for float_buffer in [false, true] {
        for count in [5, 9, 19, 39, 79] {
            out.push(single(
                Method::Slices {
                    count,
                    float_buffer,
                },
                OpacityFn::Log,
            ));
        }
    }
    out.push(single(
        Method::Raytraced(Primitive::Constant),
        OpacityFn::Log,
    ));
    out.push(single(Method::Raytraced(Primitive::Linear), OpacityFn::Log));
    for f in [OpacityFn::Log, OpacityFn::Linear, OpacityFn::Sqrt] {
        out.push(single(Method::Raytraced(Primitive::Sphere), f));
    }
    out.push(single(
        Method::Raytraced(Primitive::Texture),
        OpacityFn::Log,
    ));
    out
}

/// The particle-system versions: every volume of the scene, sorted back to front.
pub fn particle_variants() -> Vec<Variant> {
    let all = |method| Variant {
        method,
        opacity: OpacityFn::Log,
        set: VolumeSet::All,
    };
    vec![
        all(Method::Billboard),
        all(Method::Slices {
            count: 9,
            float_buffer: false,
        }),
        all(Method::Slices {
            count: 9,
            float_buffer: true,
        }),
        all(Method::Raytraced(Primitive::Sphere)),
        all(Method::Raytraced(Primitive::Texture)),
    ]
}

/// The engine baseline: depth-fade soft particles on the large volumes and on every volume.
pub fn engine_variants() -> Vec<Variant> {
    [VolumeSet::Single, VolumeSet::All]
        .into_iter()
        .map(|set| Variant {
            method: Method::DepthFade,
            opacity: OpacityFn::Log,
            set,
        })
        .collect()
}

/// Every variant this crate registers.
pub fn all_variants() -> Vec<Variant> {
    let mut v = thesis_variants();
    v.extend(particle_variants());
    v.extend(engine_variants());
    v
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct GlobalsGpu {
    view_proj: [[f32; 4]; 4],
    inv_view_proj: [[f32; 4]; 4],
    eye: [f32; 4],
    viewport: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct VolumeGpu {
    center: [f32; 4],
    right: [f32; 4],
    up: [f32; 4],
    normal: [f32; 4],
    color: [f32; 4],
}

/// A volume placed for one frame, with its camera-facing billboard axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlacedVolume {
    /// Index of the volume in `Scene::volumes`.
    pub index: usize,
    /// World-space centre at the frame's time (motion applied).
    pub center: Vec3,
    /// Radius of the bounding sphere (metres).
    pub radius: f32,
    /// Linear RGB radiance of the medium where it is opaque (`Volume::color`).
    pub color: Vec3,
    /// [`opacity_scale`] with the logarithmic function; [`VolumeTechnique`] recomputes it
    /// for its own function.
    pub density: f32,
    /// Unit billboard right axis, in the plane (the camera's right made perpendicular to the
    /// normal).
    pub right: Vec3,
    /// Unit billboard up axis, in the plane.
    pub up: Vec3,
    /// Unit billboard normal, from the centre toward the eye.
    pub normal: Vec3,
    /// Distance from the eye to the centre (the sort key).
    pub distance: f32,
}

/// The volumes of `set` at `time`, with billboards facing `camera`'s eye, sorted back to
/// front (farthest centre first). A billboard's normal points from its centre to the eye;
/// its right axis is the camera's right made perpendicular to that normal, so billboards
/// keep the camera's roll. With the eye at the centre the normal is the camera's backward
/// axis.
pub fn placed_volumes(
    volumes: &[Volume],
    set: VolumeSet,
    camera: &Camera,
    time: f32,
) -> Vec<PlacedVolume> {
    let (forward, cam_right, cam_up) = camera.basis();
    let mut out: Vec<PlacedVolume> = volumes
        .iter()
        .enumerate()
        .filter(|(_, v)| set.includes(v))
        .map(|(index, v)| {
            let center = v.center + v.motion.offset(time);
            let to_eye = camera.eye - center;
            let distance = to_eye.length();
            let normal = if distance > 1e-6 * v.radius.max(1e-6) {
                to_eye / distance
            } else {
                -forward
            };
            let mut right = cam_right - normal * cam_right.dot(normal);
            if right.length_squared() < 1e-8 {
                right = cam_up.cross(normal);
            }
            let right = right.normalize();
            let up = normal.cross(right);
            let density = opacity_scale(v, OpacityFn::Log);
            PlacedVolume {
                index,
                center,
                radius: v.radius,
                color: v.color,
                density,
                right,
                up,
                normal,
                distance,
            }
        })
        .collect();
    out.sort_by(|a, b| b.distance.total_cmp(&a.distance));
    out
}

/// The parameters of a variant, each declared once ([`scene::Settings`]); which a variant
/// has follows its drawing method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// The variant's method (what decides which parameters it has).
    pub method: Method,
    /// Billboard half size in units of the volume radius (billboards and ray-traced).
    pub billboard_scale: f32,
    /// Ray-traced: size each billboard to the sphere's silhouette, and draw a screen-filling
    /// quad when the eye is inside or next to the sphere (a departure from the thesis, which
    /// accepts the cut-off, 6.3.3).
    pub fit_silhouette: bool,
    /// Ray-traced: read the raster pass's depth buffer instead of rendering the thesis's
    /// distance texture (the depth "already exists for other reasons").
    pub free_depth: bool,
    /// Billboards and slices: render the distance texture anyway (the thesis's measurement of
    /// what the depth texture costs, 6.4.3).
    pub depth_prepass: bool,
    /// Depth fade: the gap (units of the volume radius) over which a billboard fades in
    /// front of the scene (parameter `fade_distance`).
    pub fade_distance: f32,
}

impl Settings {
    fn raytraced(&self) -> bool {
        matches!(self.method, Method::Raytraced(_))
    }
    fn scaled(&self) -> bool {
        matches!(
            self.method,
            Method::Raytraced(_) | Method::DepthFade | Method::Billboard
        )
    }
}

impl scene::Settings for Settings {
    const DECLARED: &'static [Declared<Self>] = &[
        Declared::new(
            "billboard_scale",
            (1.0, 8.0),
            "billboard half size in units of the volume radius (the sphere is cut where its \
             silhouette leaves the billboard)",
            |s| setting_if(s.scaled(), &mut s.billboard_scale),
        ),
        Declared::new(
            "fit_silhouette",
            (0.0, 1.0),
            "1: size each billboard to cover the sphere's silhouette and fill the screen \
             when the eye is inside or next to the volume (not in the thesis); \
             0: billboard_scale times the radius, as the thesis",
            |s| setting_if(s.raytraced(), &mut s.fit_silhouette),
        ),
        Declared::new(
            "free_depth",
            (0.0, 1.0),
            "1: read the raster pass's depth buffer (the depth texture exists for other \
             reasons, its cost not charged); 0: render the thesis's R16Float distance texture",
            |s| setting_if(s.raytraced(), &mut s.free_depth),
        ),
        Declared::new(
            "fade_distance",
            (0.0, 10.0),
            "scene-to-billboard gap over which a particle fades in, in units of its \
             radius (0: a hard depth test)",
            |s| setting_if(s.method == Method::DepthFade, &mut s.fade_distance),
        ),
        Declared::new(
            "depth_prepass",
            (0.0, 1.0),
            "1: also render the (unused) scene distance texture, as the thesis did to \
             measure its cost (6.4.3)",
            |s| {
                let unused = matches!(s.method, Method::Billboard | Method::Slices { .. });
                setting_if(unused, &mut s.depth_prepass)
            },
        ),
    ];
}

/// One variant of the volume techniques.
pub struct VolumeTechnique {
    variant: Variant,
    settings: Settings,
    gpu: Option<Resources>,
    buffers: Option<FrameBuffers>,
}

/// The thickness texture baked from one volume of the scene (see [`bake_thickness`]).
struct Baked {
    /// Index in `Scene::volumes` of the volume it was baked from.
    volume: usize,
    /// The opacity scale that turns the texture back into that volume's opacity.
    scale: f32,
}

struct Resources {
    baked: Option<Baked>,
    /// The `free_depth` the volume pipeline was specialised for.
    free_depth: bool,
    /// The `fade_distance` the depth-fade pipeline was specialised for (override `FADE`).
    fade_distance: f32,
    volume_layout: wgpu::BindGroupLayout,
    copy_layout: wgpu::BindGroupLayout,
    volume_pipeline: wgpu::RenderPipeline,
    to_bytes_pipeline: Option<wgpu::RenderPipeline>,
    resolve_pipeline: wgpu::RenderPipeline,
    distance_pipeline: wgpu::RenderPipeline,
    thickness_view: wgpu::TextureView,
    dummy_distance_view: wgpu::TextureView,
    dummy_depth_view: wgpu::TextureView,
}

struct FrameBuffers {
    width: u32,
    height: u32,
    scene_color_view: wgpu::TextureView,
    bytes_view: Option<wgpu::TextureView>,
    distance_view: wgpu::TextureView,
    distance_depth_view: wgpu::TextureView,
    to_bytes_bind_group: Option<wgpu::BindGroup>,
    resolve_bind_group: wgpu::BindGroup,
}

impl VolumeTechnique {
    /// The technique of `variant` with the default parameters (`billboard_scale`
    /// [`DEFAULT_BILLBOARD_SCALE`], `fit_silhouette`, `free_depth` and `depth_prepass` off).
    pub fn new(variant: Variant) -> Self {
        let settings = Settings {
            method: variant.method,
            billboard_scale: DEFAULT_BILLBOARD_SCALE,
            fit_silhouette: false,
            free_depth: false,
            depth_prepass: false,
            fade_distance: DEFAULT_FADE_DISTANCE,
        };
        Self {
            variant,
            settings,
            gpu: None,
            buffers: None,
        }
    }

    /// The variant this technique renders.
    pub fn variant(&self) -> Variant {
        self.variant
    }

    /// Billboard, slices and the thickness-texture primitive read the thickness texture.
    fn uses_texture(&self) -> bool {
        !matches!(self.variant.method, Method::Raytraced(p) if p != Primitive::Texture)
    }

    fn is_raytraced(&self) -> bool {
        matches!(self.variant.method, Method::Raytraced(_))
    }

    /// Ray-traced volumes and depth-fade particles read the scene depth in the fragment
    /// shader instead of being depth tested.
    fn reads_scene_depth(&self) -> bool {
        self.is_raytraced() || self.variant.method == Method::DepthFade
    }

    /// Where the scene depth is read from: the depth buffer (depth fade, as engines do, and
    /// ray-traced volumes with `free_depth`) or the thesis's distance texture.
    fn reads_depth_buffer(&self) -> bool {
        self.variant.method == Method::DepthFade
            || (self.is_raytraced() && self.settings.free_depth)
    }

    fn slice_count(&self) -> u32 {
        match self.variant.method {
            Method::Slices { count, .. } => count,
            _ => 1,
        }
    }

    fn buffer_format(&self) -> wgpu::TextureFormat {
        match self.variant.method {
            Method::Slices {
                float_buffer: false,
                ..
            } => BYTE_BUFFER_FORMAT,
            _ => FLOAT_BUFFER_FORMAT,
        }
    }

    fn renders_distance(&self) -> bool {
        if self.variant.method == Method::DepthFade {
            false
        } else if self.is_raytraced() {
            !self.settings.free_depth
        } else {
            self.settings.depth_prepass
        }
    }

    fn ensure_buffers(&mut self, ctx: &Context, width: u32, height: u32) -> TechniqueResult<()> {
        if self
            .buffers
            .as_ref()
            .is_some_and(|b| b.width == width && b.height == height)
        {
            return Ok(());
        }
        let res = self.gpu.as_ref().ok_or_else(|| not_prepared(self))?;
        let texture = |label: &str, format: wgpu::TextureFormat| {
            ctx.device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: wgpu::Extent3d {
                        width,
                        height,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                        | wgpu::TextureUsages::TEXTURE_BINDING,
                    view_formats: &[],
                })
                .create_view(&Default::default())
        };
        let scene_color_view = texture("volumes scene colour (Rgba16Float)", FLOAT_BUFFER_FORMAT);
        let bytes_view = (self.buffer_format() == BYTE_BUFFER_FORMAT)
            .then(|| texture("volumes colour (Rgba8Unorm)", BYTE_BUFFER_FORMAT));
        let distance_view = texture("volumes scene distance (R16Float)", DISTANCE_FORMAT);
        let distance_depth_view =
            gpu::depth_texture(ctx, width, height, 1, "volumes depth pre-pass depth")
                .create_view(&Default::default());
        let copy_bind_group = |view: &wgpu::TextureView| {
            bind::group(ctx, "volumes copy", &res.copy_layout, &[bind::view(view)])
        };
        let to_bytes_bind_group = bytes_view
            .as_ref()
            .map(|_| copy_bind_group(&scene_color_view));
        let resolve_bind_group = copy_bind_group(bytes_view.as_ref().unwrap_or(&scene_color_view));
        self.buffers = Some(FrameBuffers {
            width,
            height,
            scene_color_view,
            bytes_view,
            distance_view,
            distance_depth_view,
            to_bytes_bind_group,
            resolve_bind_group,
        });
        Ok(())
    }
}

/// Default billboard half size in units of the volume radius: "the sphere is made only
/// slightly smaller than the billboard" (6.3.3).
pub const DEFAULT_BILLBOARD_SCALE: f32 = 1.1;
/// Default fade distance of the depth-fade particles, in units of the volume radius.
pub const DEFAULT_FADE_DISTANCE: f32 = 1.0;

impl Technique for VolumeTechnique {
    fn id(&self) -> String {
        self.variant.id()
    }

    /// The default compare shows one variant of each method and precision (billboard; 9,
    /// 19 and 39 slices; 19 float slices; three opacity functions of the ray-traced sphere)
    /// and three particle variants; the other slice counts and opacity functions are for
    /// `harness sweep` (or `compare --all-variants`).
    fn representative(&self) -> bool {
        let exhaustive = [
            "slices-5",
            "slices-79",
            "slices-5-float",
            "slices-9-float",
            "slices-39-float",
            "slices-79-float",
            "raytraced-linear",
            "raytraced-sphere-linear",
            "raytraced-sphere-sqrt",
            "particles-slices-9-float",
            "particles-raytraced-sphere-log",
        ];
        let id = self.id();
        !exhaustive.iter().any(|v| id == format!("volumes/{v}"))
    }

    fn description(&self) -> String {
        self.variant.description()
    }

    fn params(&self) -> Vec<Param> {
        self.settings.params()
    }

    fn set_param(&mut self, name: &str, value: f64) -> TechniqueResult<()> {
        set_checked(&self.id(), &mut self.settings, name, value)
    }

    fn supports(&self, scene: &Scene) -> bool {
        scene.volumes.iter().any(|v| self.variant.set.includes(v))
    }

    fn prepare(&mut self, frame: &mut Frame, scene: &GpuScene) -> TechniqueResult<()> {
        let ctx = frame.gpu;
        self.buffers = None;
        let resources = ctx.validated(|| self.create_resources(ctx, scene))?;
        self.gpu = Some(resources);
        Ok(())
    }

    fn render(
        &mut self,
        frame: &mut Frame,
        scene: &GpuScene,
        view: &View,
        target: &Target,
    ) -> TechniqueResult<()> {
        let ctx = frame.gpu;
        if self.gpu.as_ref().is_some_and(|r| {
            r.free_depth != self.settings.free_depth
                || r.fade_distance != self.settings.fade_distance
        }) {
            // `free_depth` or `fade_distance` changed after prepare: respecialise the pipelines.
            self.gpu = Some(ctx.validated(|| self.create_resources(ctx, scene))?);
            self.buffers = None;
        }
        self.ensure_buffers(ctx, target.width, target.height)?;
        let res = self.gpu.as_ref().ok_or_else(|| not_prepared(self))?;
        let buffers = self.buffers.as_ref().expect("ensure_buffers made them");
        let camera = &view.camera;
        let view_proj = camera.view_proj(target.width, target.height);

        // 1. The thesis's depth pre-pass (scene distance into an R16Float texture).
        if self.renders_distance() {
            frame.span("scene-depth", |frame| {
                let camera_group = scene.camera_bind_group(ctx, view_proj, camera.eye);
                let background = Load::Clear(wgpu::Color {
                    r: BACKGROUND_DISTANCE as f64,
                    g: 0.0,
                    b: 0.0,
                    a: 0.0,
                });
                let mut pass = pass::begin(
                    frame.encoder,
                    "volumes scene distance",
                    &[pass::color(&buffers.distance_view, background)],
                    Some(pass::depth(&buffers.distance_depth_view, pass::CLEAR_FAR)),
                    None,
                );
                pass.set_pipeline(&res.distance_pipeline);
                pass.set_bind_group(0, &camera_group, &[]);
                pass.set_bind_group(1, scene.bind_group(), &[]);
                scene.draw_objects(&mut pass, &ObjectFilter::All);
            });
        }

        // 2. The diffuse scene.
        let scene_target = RasterTarget {
            color: &buffers.scene_color_view,
            depth: &target.depth_view,
            format: FLOAT_BUFFER_FORMAT,
            clear: true,
        };
        scene.raster(
            frame,
            &scene_target,
            view_proj,
            camera.eye,
            &ObjectFilter::All,
            true,
        );

        // 3. 8-bit slices: from here on the frame is 8 bits per channel.
        if let (Some(bytes_view), Some(pipeline), Some(group)) = (
            &buffers.bytes_view,
            &res.to_bytes_pipeline,
            &buffers.to_bytes_bind_group,
        ) {
            let mut pass = pass::begin(
                frame.encoder,
                "volumes to 8-bit",
                &[pass::color(bytes_view, CLEAR_OPAQUE_BLACK)],
                None,
                None,
            );
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, group, &[]);
            gpu::fullscreen::draw(&mut pass);
        }
        let work_view = buffers
            .bytes_view
            .as_ref()
            .unwrap_or(&buffers.scene_color_view);

        // 4. The volumes, back to front.
        let placed = placed_volumes(&scene.scene.volumes, self.variant.set, camera, view.time);
        if !placed.is_empty() {
            let globals = GlobalsGpu {
                view_proj: view_proj.to_cols_array_2d(),
                inv_view_proj: view_proj.inverse().to_cols_array_2d(),
                eye: camera.eye.extend(1.0).to_array(),
                viewport: [target.width as f32, target.height as f32, 0.0, 0.0],
            };
            let records: Vec<VolumeGpu> = placed
                .iter()
                .map(|v| self.volume_record(v, &scene.scene.volumes))
                .collect();
            let globals = gpu::Uniform::new(ctx, "volumes globals", &globals);
            let volume_buffer = ctx
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("volumes"),
                    contents: bytemuck::cast_slice(&records),
                    usage: wgpu::BufferUsages::STORAGE,
                });
            let reads_depth = self.reads_scene_depth();
            let distance_view = if reads_depth && !self.reads_depth_buffer() {
                &buffers.distance_view
            } else {
                &res.dummy_distance_view
            };
            let depth_view = if self.reads_depth_buffer() {
                &target.depth_view
            } else {
                &res.dummy_depth_view
            };
            let group = bind::group(
                ctx,
                "volumes",
                &res.volume_layout,
                &[
                    globals.binding(),
                    volume_buffer.as_entire_binding(),
                    bind::view(&res.thickness_view),
                    bind::sampler_resource(&ctx.samplers.linear_clamp),
                    bind::view(distance_view),
                    bind::view(depth_view),
                ],
            );
            frame.span("volumes", |frame| {
                // Billboards and slices test against the scene's depth without writing it: a
                // read-only attachment (no depth ops), which `pass::depth` does not make.
                let depth_test = (!reads_depth).then_some(wgpu::RenderPassDepthStencilAttachment {
                    view: &target.depth_view,
                    depth_ops: None,
                    stencil_ops: None,
                });
                let mut pass = pass::begin(
                    frame.encoder,
                    "volumes",
                    &[pass::color(work_view, Load::Keep)],
                    depth_test,
                    None,
                );
                pass.set_pipeline(&res.volume_pipeline);
                pass.set_bind_group(0, &group, &[]);
                pass.draw(0..6, 0..placed.len() as u32 * self.slice_count());
            });
        }

        // 5. Into the HDR target.
        let mut pass = pass::begin(
            frame.encoder,
            "volumes resolve",
            &[pass::color(&target.color_view, CLEAR_OPAQUE_BLACK)],
            None,
            None,
        );
        pass.set_pipeline(&res.resolve_pipeline);
        pass.set_bind_group(0, &buffers.resolve_bind_group, &[]);
        gpu::fullscreen::draw(&mut pass);
        Ok(())
    }
}

impl VolumeTechnique {
    /// The thickness texture: baked from the first volume of the variant's set as seen from
    /// the scene's default camera at time 0 (the artist's view), or the plain sphere profile
    /// when the set is empty.
    fn bake(&self, scene: &Scene) -> (Vec<u8>, Option<Baked>) {
        if !self.uses_texture() {
            return (crate::path_length::thickness_texels(), None);
        }
        let placed = placed_volumes(&scene.volumes, self.variant.set, &scene.camera, 0.0);
        let Some(first) = placed.iter().min_by_key(|p| p.index) else {
            return (crate::path_length::thickness_texels(), None);
        };
        let volume = &scene.volumes[first.index];
        let (texels, scale) = bake_thickness(
            volume,
            [first.right, first.up, first.normal],
            self.variant.opacity,
        );
        (
            texels,
            Some(Baked {
                volume: first.index,
                scale,
            }),
        )
    }
}

/// Beyond this ratio of eye distance to radius a fitted billboard covers the silhouette;
/// closer, the ray-traced pass draws a screen-filling quad.
const FIT_MIN_DISTANCE: f32 = 1.05;

impl VolumeTechnique {
    /// The GPU record of a placed volume: billboard half size (metres) and whether to draw a
    /// screen-filling quad instead.
    fn volume_record(&self, v: &PlacedVolume, volumes: &[Volume]) -> VolumeGpu {
        let (half_size, screen) = billboard_extent(
            v,
            self.settings.billboard_scale,
            self.settings.fit_silhouette && self.is_raytraced(),
        );
        let baked = self
            .gpu
            .as_ref()
            .and_then(|r| r.baked.as_ref())
            .filter(|b| b.volume == v.index);
        let scale = match baked {
            Some(b) if self.uses_texture() => b.scale,
            _ => volumes
                .get(v.index)
                .map_or(v.density, |s| opacity_scale(s, self.variant.opacity)),
        };
        VolumeGpu {
            center: v.center.extend(v.radius).to_array(),
            right: v.right.extend(scale).to_array(),
            up: v.up.extend(half_size).to_array(),
            normal: v.normal.extend(if screen { 1.0 } else { 0.0 }).to_array(),
            color: v.color.extend(1.0).to_array(),
        }
    }
}

/// Half size (metres) of a volume's billboard, and whether a screen-filling quad replaces it.
/// Without `fit`: `scale * R` (thesis). With `fit`: the plane through the centre facing the eye
/// meets the silhouette cone of the sphere at radius `R D / sqrt(D^2 - R^2)` (D the eye
/// distance); 1% more covers it. Closer than `FIT_MIN_DISTANCE` (1.05) R (or inside) no billboard
/// through the centre can cover the sphere, so the whole screen is drawn.
pub fn billboard_extent(v: &PlacedVolume, scale: f32, fit: bool) -> (f32, bool) {
    let r = v.radius;
    if !fit {
        return (scale * r, false);
    }
    let d = v.distance;
    if d < FIT_MIN_DISTANCE * r {
        return (scale * r, true);
    }
    let cover = 1.01 * r * d / (d * d - r * r).sqrt();
    (cover.max(scale * r), false)
}

/// The clear of the full-screen copies' targets (which the copies then overwrite): opaque
/// black, not [`pass::CLEAR_BLACK`]'s transparent black.
const CLEAR_OPAQUE_BLACK: Load<wgpu::Color> = Load::Clear(wgpu::Color::BLACK);

/// Premultiplied "over" on rgb; the destination's alpha is kept. (Not wgpu's
/// `PREMULTIPLIED_ALPHA_BLENDING`, which also blends alpha.)
const PREMULTIPLIED_OVER_KEEP_ALPHA: wgpu::BlendState = wgpu::BlendState {
    color: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
        operation: wgpu::BlendOperation::Add,
    },
    alpha: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::Zero,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    },
};

impl VolumeTechnique {
    fn create_resources(&self, ctx: &Context, scene: &GpuScene) -> Resources {
        use wgpu::TextureViewDimension::D2;
        let device = &ctx.device;
        let fragment = bind::ShaderStages::FRAGMENT;
        let both = bind::ShaderStages::VERTEX_FRAGMENT;
        let volume_layout = bind::layout_with_stages(
            ctx,
            "volumes",
            &[
                (both, bind::uniform()),                     // globals
                (both, bind::storage(true)),                 // volumes
                (fragment, bind::texture_2d()),              // thickness_texture
                (fragment, bind::sampler()),                 // thickness_sampler
                (fragment, bind::texture_2d_unfilterable()), // scene_distance_texture
                (fragment, bind::depth_texture(D2)),         // scene_depth_texture
            ],
        );
        let copy_layout = bind::layout(
            ctx,
            "volumes copy",
            fragment,
            &[bind::texture_2d_unfilterable()], // copy_source
        );

        // The volume pass.
        let source = format!("{PATH_LENGTH_WGSL}\n{VOLUMES_WGSL}");
        let module = gpu::shader_with_prelude(ctx, "volumes", &source);
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("volumes"),
            bind_group_layouts: &[Some(&volume_layout)],
            immediate_size: 0,
        });
        let (fragment_entry, primitive) = match self.variant.method {
            Method::Billboard => ("billboard_fs", Primitive::Sphere),
            Method::Slices { .. } => ("slice_fs", Primitive::Sphere),
            Method::Raytraced(p) => ("raytraced_fs", p),
            Method::DepthFade => ("depth_fade_fs", Primitive::Sphere),
        };
        let constants = [
            ("SLICES", self.slice_count() as f64),
            ("OPACITY", self.variant.opacity.code() as f64),
            ("PRIMITIVE", primitive.code() as f64),
            (
                "DEPTH_SOURCE",
                if self.reads_depth_buffer() { 1.0 } else { 0.0 },
            ),
            ("FADE", self.settings.fade_distance as f64),
        ];
        let options = wgpu::PipelineCompilationOptions {
            constants: &constants,
            zero_initialize_workgroup_memory: true,
        };
        let depth_stencil = (!self.reads_scene_depth())
            .then(|| pass::depth_state(false, wgpu::CompareFunction::Less));
        let volume_pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("volumes"),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("volume_vs"),
                compilation_options: options.clone(),
                buffers: &[],
            },
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some(fragment_entry),
                compilation_options: options,
                targets: &[pass::color_target(
                    self.buffer_format(),
                    Some(PREMULTIPLIED_OVER_KEEP_ALPHA),
                )],
            }),
            primitive: wgpu::PrimitiveState {
                cull_mode: None,
                ..Default::default()
            },
            depth_stencil,
            multisample: Default::default(),
            multiview_mask: None,
            cache: ctx.pipeline_cache(),
        });

        // Full-screen copies.
        let copy_source =
            |keep_alpha: bool| format!("const COPY_ALPHA: bool = {keep_alpha};\n{COPY_WGSL}");
        let to_bytes_pipeline = (self.buffer_format() == BYTE_BUFFER_FORMAT).then(|| {
            gpu::fullscreen::pipeline(
                ctx,
                "volumes to 8-bit",
                &copy_source(true),
                &[Some(&copy_layout)],
                BYTE_BUFFER_FORMAT,
                None,
            )
        });
        let resolve_pipeline = gpu::fullscreen::pipeline(
            ctx,
            "volumes resolve",
            &copy_source(false),
            &[Some(&copy_layout)],
            gpu::HDR_FORMAT,
            None,
        );

        // The depth pre-pass.
        let distance_module = gpu::shader_with_prelude(
            ctx,
            "volumes scene distance",
            &format!("{}\n{SCENE_DISTANCE_WGSL}", scene::SCENE_WGSL),
        );
        let distance_layout = scene.pipeline_layout_with(ctx, &[]);
        let distance_pipeline = scene::scene_pipeline(
            ctx,
            "volumes scene distance",
            &distance_layout,
            &distance_module,
            "scene_distance_fs",
            DISTANCE_FORMAT,
        );

        // The thickness texture (the alpha of the billboard texture), read through the shared
        // bilinear clamp-to-edge sampler.
        let size = THICKNESS_TEXTURE_SIZE;
        let (texels, baked) = self.bake(&scene.scene);
        let thickness = device.create_texture_with_data(
            &ctx.queue,
            &wgpu::TextureDescriptor {
                label: Some("volumes thickness texture"),
                size: wgpu::Extent3d {
                    width: size,
                    height: size,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::Rgba8Unorm,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            &texels,
        );
        let dummy_distance_view = device
            .create_texture(&wgpu::TextureDescriptor {
                label: Some("volumes unused distance"),
                size: wgpu::Extent3d {
                    width: 1,
                    height: 1,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: DISTANCE_FORMAT,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            })
            .create_view(&Default::default());
        let dummy_depth_view = gpu::depth_texture(ctx, 1, 1, 1, "volumes unused depth")
            .create_view(&Default::default());
        Resources {
            baked,
            free_depth: self.settings.free_depth,
            fade_distance: self.settings.fade_distance,
            volume_layout,
            copy_layout,
            volume_pipeline,
            to_bytes_pipeline,
            resolve_pipeline,
            distance_pipeline,
            thickness_view: thickness.create_view(&Default::default()),
            dummy_distance_view,
            dummy_depth_view,
        }
    }
}
