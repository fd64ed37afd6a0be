//! Caustics (paper section 7): photon maps of the pieces from the light, photon hits on the
//! chessboard in texture space, Gaussian splats into two light maps.
//!
//! 1. *Photon map.* Every piece is drawn from each light into its own tile of one photon map
//!    (one render pass, a viewport per tile: see ARCHITECTURE.md on lavapipe's cost per pass).
//!    A pixel is one photon: rasterization finds where the light's ray meets the piece, the
//!    photon refracts in and leaves through the piece's refractor map (`photons.wgsl`, the
//!    tracer's own `chord()`), or reflects off a mirror piece, and lands on the *receiver*:
//!    the plane of the diffuse surface under the pieces (the chessboard). Its light-map
//!    address (atlas uv of the receiver's chart) and power are written; as in the paper the
//!    photon does not meet other pieces on its way.
//! 2. *Light maps.* `scene::lightmap::QuadSplatter` adds a Gaussian quad per photon into a
//!    light map with additive blending. There are two (section 7): the static pieces' light map
//!    is made once, in `prepare`; the moving piece's is cleared and made again every frame.
//!    With `caustics_separated = 0` every piece's photons are traced every frame instead (the
//!    full-update baseline of the light maps).
//! 3. *Apply.* After the pieces are drawn, the receiver is drawn again (depth equal, additive)
//!    adding `albedo / pi * E`, `E` the power per texel of both light maps over the texel's
//!    area (`caustics_apply.wgsl`).
//!
//! Shadows, which the paper also writes into the light map, come from the shared raster pass's
//! shadow maps (every piece casts one, re-rendered when the pawn moves): the reference's
//! shadows of glass are black, lit only by the caustic photons.

use crate::pieces::Kinds;
use glam::Vec3;
use gpu::pass::{self, ADD_RGB_KEEP_ALPHA, CLEAR_BLACK, CLEAR_FAR, Load};
use gpu::wgpu::{self, util::DeviceExt};
use gpu::{Context, Uniform, bind};
use scene::emission::{footprint_declared, jitter_declared};
use scene::lightmap::{ChartAtlas, ChartGpu, QuadSplatter};
use scene::technique::Declared;
use scene::{Frame, GpuScene, Material, ObjectFilter, Scene, TechniqueError};

/// The photon map's entry point, over the tracer's bindings (`scene::trace`, `scene::pieces`)
/// with the refractor-map search, importing `scene::chart` and `scene::receiver`.
pub const PHOTONS_WGSL: &str = include_str!("shaders/photons.wgsl");
const APPLY_WGSL: &str = include_str!("shaders/caustics_apply.wgsl");

/// Photon map targets (light-map address, power) and the light maps: 32-bit float, so that
/// additive blending keeps adding photons to a bright texel.
const PHOTON_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
const LIGHT_MAP_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

/// Caustic parameters (the `photons`, `lightmap_resolution`, `splat_radius` and
/// `caustics_separated` variant parameters).
#[derive(Clone, Debug, PartialEq)]
pub struct CausticSettings {
    /// Photon-map tile side: `photons` x `photons` photons per piece and light.
    pub photons: u32,
    /// Light-map side in texels (the receiver's chart fills it).
    pub lightmap_resolution: u32,
    /// Radius of a photon's Gaussian quad in light-map texels (sigma = radius / 2).
    pub splat_radius: f32,
    /// Static pieces' light map made once and the moving piece's every frame (section 7), or
    /// every piece's photons every frame.
    pub separated: bool,
    /// Each photon leaves from a random point of its photon-map pixel instead of the pixel
    /// centre (stratified jittered emission, `jittered_emission` in scene.wgsl).
    pub jitter: bool,
    /// Each photon's Gaussian widened to its lattice cell's footprint on the light map
    /// (`scene::lightmap::Footprint`).
    pub footprint: bool,
}

impl Default for CausticSettings {
    fn default() -> Self {
        Self {
            photons: 128,
            lightmap_resolution: 512,
            splat_radius: 3.0,
            separated: true,
            jitter: false,
            footprint: true,
        }
    }
}

/// The caustics' parameters, each declared once.
impl scene::Settings for CausticSettings {
    const DECLARED: &'static [Declared<Self>] = &[
        Declared::new(
            "photons",
            (4.0, 512.0),
            "photon-map tile side: photons x photons photons per piece and light",
            |s| Some(&mut s.photons),
        ),
        Declared::new(
            "lightmap_resolution",
            (16.0, 4096.0),
            "side of the caustic light maps (texels)",
            |s| Some(&mut s.lightmap_resolution),
        ),
        Declared::new(
            "splat_radius",
            (0.5, 16.0),
            "radius of a photon's Gaussian splat in light-map texels",
            |s| Some(&mut s.splat_radius),
        ),
        footprint_declared(|s| Some(&mut s.footprint)),
        jitter_declared(|s| Some(&mut s.jitter)),
        Declared::new(
            "caustics_separated",
            (0.0, 1.0),
            "1: static pieces' light map made once, the moving piece's every frame; 0: every \
             piece's photons every frame",
            |s| Some(&mut s.separated),
        ),
    ];
}

/// The surface the photons land on: a planar diffuse object.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Receiver {
    /// Scene object index.
    pub object: usize,
    /// World plane `dot(normal, x) = offset`, `normal` facing up toward the pieces.
    pub normal: Vec3,
    /// See `normal`.
    pub offset: f32,
}

/// The caustic receiver under `above` (the pieces' centre): of the diffuse objects that are
/// flat (every vertex on one plane), face up, lie below `above` and span it horizontally, the
/// highest. The chessboard on `chess` (not the table under it), the floor on `cornell-sphere`.
pub fn caustic_receiver(scene: &Scene, above: Vec3) -> Option<Receiver> {
    let mut best: Option<Receiver> = None;
    for (object, o) in scene.objects.iter().enumerate() {
        if !matches!(o.material, Material::Diffuse { .. }) || !o.motion.is_static() {
            continue;
        }
        let model = o.world_at(0.0);
        let world: Vec<Vec3> = o
            .mesh
            .positions
            .iter()
            .map(|&p| model.transform_point3(p))
            .collect();
        let Some(normal) = o.mesh.indices.chunks_exact(3).find_map(|t| {
            let [a, b, c] = [0, 1, 2].map(|k| world[t[k] as usize]);
            let n = (b - a).cross(c - a);
            (n.length_squared() > 1e-12).then(|| n.normalize())
        }) else {
            continue;
        };
        let normal = if normal.y < 0.0 { -normal } else { normal };
        let offset = normal.dot(world[0]);
        let flat = world.iter().all(|p| (normal.dot(*p) - offset).abs() < 1e-5);
        let (lo, hi) = world
            .iter()
            .fold((world[0], world[0]), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
        let spans = (lo.x..=hi.x).contains(&above.x) && (lo.z..=hi.z).contains(&above.z);
        let below = normal.dot(above) > offset;
        if flat && normal.y > 0.9 && spans && below && best.is_none_or(|b| offset > b.offset) {
            best = Some(Receiver {
                object,
                normal,
                offset,
            });
        }
    }
    best
}

/// The uniform block `PhotonParams` of photons.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct PhotonParamsGpu {
    chart: ChartGpu,
    plane: [f32; 4],
    object: u32,
    tile: u32,
    tiles_per_row: u32,
    chart_index: u32,
    jitter: u32,
    _pad: [u32; 3],
}

/// `struct PhotonTile` of photons.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct PhotonTileGpu {
    light: [f32; 4],
    intensity: [f32; 4],
    axis: [f32; 4],
}

/// The uniform block `ReceiverParams` of caustics_apply.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ReceiverParamsGpu {
    chart: ChartGpu,
    object: u32,
    side: f32,
    _pad: [u32; 2],
}

/// The splatter's slot of the static pieces' photon map, and of the moving pieces'.
const STATIC_SLOT: usize = 0;
const MOVING_SLOT: usize = 1;

/// One photon map: a tile per (light, piece), the pieces' photons written side by side.
struct PhotonMap {
    /// Tiles per row (and rows): the map is `tiles_per_row * photons` pixels square.
    tiles_per_row: u32,
    address: wgpu::TextureView,
    power: wgpu::TextureView,
    depth: wgpu::TextureView,
}

impl PhotonMap {
    fn new(ctx: &Context, tiles: usize, photons: u32, label: &str) -> Result<Self, TechniqueError> {
        let tiles_per_row = (tiles as f32).sqrt().ceil().max(1.0) as u32;
        let side = tiles_per_row * photons;
        let max = ctx.device.limits().max_texture_dimension_2d;
        if side > max {
            return Err(TechniqueError::Unsupported(format!(
                "a photon map of {tiles} tiles of {photons} pixels would be {side} pixels wide, \
                 more than the adapter's {max}: lower `photons`"
            )));
        }
        let view = |format, label: &str| {
            gpu::render_texture(
                ctx,
                label,
                (side, side, 1),
                format,
                wgpu::TextureUsages::empty(),
            )
            .create_view(&Default::default())
        };
        Ok(Self {
            tiles_per_row,
            address: view(PHOTON_FORMAT, label),
            power: view(PHOTON_FORMAT, label),
            depth: gpu::depth_texture(ctx, side, side, 1, label).create_view(&Default::default()),
        })
    }

    fn side(&self, photons: u32) -> u32 {
        self.tiles_per_row * photons
    }
}

/// A light map: the receiver's chart filling the texture.
struct LightMap {
    texture: wgpu::Texture,
    view: wgpu::TextureView,
}

/// The caustic passes of a refractor-maps variant and their maps.
pub(crate) struct Caustics {
    settings: CausticSettings,
    receiver: Receiver,
    photon_pipeline: wgpu::RenderPipeline,
    photon_layout: wgpu::BindGroupLayout,
    apply_pipeline: wgpu::RenderPipeline,
    apply_group: wgpu::BindGroup,
    splatter: QuadSplatter,
    atlas: ChartAtlas,
    charts: wgpu::Buffer,
    /// Pieces (indices into `Kinds::pieces`) whose photons go into the static light map
    /// (made once) and into the moving one (every frame).
    statics: Vec<usize>,
    movers: Vec<usize>,
    static_map: LightMap,
    moving_map: LightMap,
    static_photons: Option<PhotonMap>,
    moving_photons: Option<PhotonMap>,
}

impl Caustics {
    /// The caustic passes; `photon_module` is [`PHOTONS_WGSL`] composed over the tracer's
    /// bindings with its search (`scene::multi_object::driver_shader`), `tracer_layout` the
    /// tracer's `@group(2)`.
    pub(crate) fn new(
        ctx: &Context,
        scene: &GpuScene,
        kinds: &Kinds,
        photon_module: &wgpu::ShaderModule,
        tracer_layout: &wgpu::BindGroupLayout,
        settings: &CausticSettings,
        receiver: Receiver,
    ) -> Result<Self, TechniqueError> {
        ctx.require(wgpu::Features::FLOAT32_BLENDABLE)?;
        let frag = wgpu::ShaderStages::FRAGMENT;
        let photon_layout = bind::layout(
            ctx,
            "photon map",
            frag,
            &[bind::uniform(), bind::storage(true)],
        );
        let photon_pipeline = scene::scene_pipeline_with(
            ctx,
            "photon map",
            &scene.pipeline_layout_with(ctx, &[tracer_layout, &photon_layout]),
            photon_module,
            "photon_fs",
            &[
                pass::color_target(PHOTON_FORMAT, None),
                pass::color_target(PHOTON_FORMAT, None),
            ],
            (true, wgpu::CompareFunction::Less),
        );

        let atlas = ChartAtlas::of_objects(&scene.scene, settings.lightmap_resolution, |o| {
            o == receiver.object
        });
        let charts = ctx
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("caustic receiver charts"),
                contents: bytemuck::cast_slice(&atlas.gpu_charts()),
                usage: wgpu::BufferUsages::STORAGE,
            });
        let light_map = |label| {
            let side = settings.lightmap_resolution;
            let texture = gpu::render_texture(
                ctx,
                label,
                (side, side, 1),
                LIGHT_MAP_FORMAT,
                wgpu::TextureUsages::COPY_SRC,
            );
            let view = texture.create_view(&Default::default());
            LightMap { texture, view }
        };
        let static_map = light_map("static pieces' light map");
        let moving_map = light_map("moving piece's light map");

        let maps = [&static_map, &moving_map];
        let (apply_pipeline, apply_group) =
            apply_pass(ctx, scene, settings, &atlas, receiver, maps)?;

        let (movers, statics): (Vec<usize>, Vec<usize>) = (0..kinds.pieces.len())
            .partition(|&p| !scene.scene.objects[kinds.pieces[p].0].motion.is_static());
        let (statics, movers) = if settings.separated {
            (statics, movers)
        } else {
            (vec![], (0..kinds.pieces.len()).collect())
        };
        let lights = scene.scene.lights.len();
        let photon_map = |pieces: &[usize], label| {
            (!pieces.is_empty() && lights > 0)
                .then(|| PhotonMap::new(ctx, pieces.len() * lights, settings.photons, label))
                .transpose()
        };
        Ok(Self {
            static_photons: photon_map(&statics, "static pieces' photon map")?,
            moving_photons: photon_map(&movers, "moving piece's photon map")?,
            settings: settings.clone(),
            receiver,
            photon_pipeline,
            photon_layout,
            apply_pipeline,
            apply_group,
            splatter: QuadSplatter::new(ctx, LIGHT_MAP_FORMAT),
            atlas,
            charts,
            statics,
            movers,
            static_map,
            moving_map,
        })
    }

    /// GPU bytes of the caustic maps with these settings for `pieces` pieces and `lights`
    /// lights, at most (for the map budget): a photon map is a square of tiles, so the static
    /// pieces' holds up to the next square number of tiles, and the moving pieces' is counted
    /// as large again.
    pub(crate) fn bytes(settings: &CausticSettings, pieces: usize, lights: usize) -> u64 {
        let tiles = (pieces * lights.max(1)) as f64;
        let square = tiles.sqrt().ceil().powi(2) as u64;
        let photon_pixels = 2 * square * (settings.photons as u64).pow(2);
        let light_map = (settings.lightmap_resolution as u64).pow(2) * 16;
        photon_pixels * (2 * 16 + 4) + 2 * light_map
    }

    /// The static pieces' light map (once, in `prepare`) and a black moving one.
    /// `tracer_group` is the tracer's `@group(2)` at the scene's time.
    pub(crate) fn build_static(
        &self,
        frame: &mut Frame,
        scene: &GpuScene,
        kinds: &Kinds,
        tracer_group: &wgpu::BindGroup,
    ) {
        clear(frame.encoder, &self.static_map.view);
        clear(frame.encoder, &self.moving_map.view);
        if let Some(map) = &self.static_photons {
            self.photons(frame, scene, kinds, tracer_group, &self.statics, map);
            self.splat(frame, STATIC_SLOT, map, &self.static_map);
        }
    }

    /// The moving pieces' light map (every piece's without separation), this frame.
    pub(crate) fn update(
        &self,
        frame: &mut Frame,
        scene: &GpuScene,
        kinds: &Kinds,
        tracer_group: &wgpu::BindGroup,
    ) {
        if let Some(map) = &self.moving_photons {
            clear(frame.encoder, &self.moving_map.view);
            self.photons(frame, scene, kinds, tracer_group, &self.movers, map);
            self.splat(frame, MOVING_SLOT, map, &self.moving_map);
        }
    }

    /// Adds the caustics to the receiver in the finished image (`target`'s depth holds the
    /// pieces drawn over it).
    pub(crate) fn apply(
        &self,
        frame: &mut Frame,
        scene: &GpuScene,
        camera: &wgpu::BindGroup,
        target: &gpu::Target,
    ) {
        let mut pass = gpu::pass::begin(
            frame.encoder,
            "caustics apply",
            &[pass::color(&target.color_view, Load::Keep)],
            Some(pass::depth(&target.depth_view, Load::Keep)),
            frame.timer.render_pass("caustics apply"),
        );
        pass.set_pipeline(&self.apply_pipeline);
        pass.set_bind_group(0, camera, &[]);
        pass.set_bind_group(1, scene.bind_group(), &[]);
        pass.set_bind_group(2, &self.apply_group, &[]);
        scene.draw_objects(&mut pass, &ObjectFilter::Only(vec![self.receiver.object]));
    }

    /// The light maps (static pieces, moving piece) for tests and images.
    pub(crate) fn light_maps(&self) -> (&wgpu::Texture, &wgpu::Texture) {
        (&self.static_map.texture, &self.moving_map.texture)
    }

    /// Draws each of `pieces` from each light into its tile of `map`.
    fn photons(
        &self,
        frame: &mut Frame,
        scene: &GpuScene,
        kinds: &Kinds,
        tracer_group: &wgpu::BindGroup,
        pieces: &[usize],
        map: &PhotonMap,
    ) {
        let ctx = frame.gpu;
        let time = scene.time();
        let size = self.settings.photons;
        let mut tiles = Vec::new();
        let mut cameras = Vec::new();
        for light in &scene.scene.lights {
            for &p in pieces {
                let o = &scene.scene.objects[kinds.pieces[p].0];
                let (tile, view_proj) =
                    tile_view(light, o.center_at(time), o.bounding_radius_at(time), size);
                tiles.push(tile);
                cameras.push((
                    kinds.pieces[p].0,
                    scene.camera_bind_group(ctx, view_proj, light.position),
                ));
            }
        }
        let chart = receiver_chart(&self.atlas, self.receiver.object)
            .expect("the atlas was made for the receiver");
        let params = Uniform::new(
            ctx,
            "photon params",
            &PhotonParamsGpu {
                chart,
                plane: self.receiver.normal.extend(self.receiver.offset).to_array(),
                object: self.receiver.object as u32,
                tile: size,
                tiles_per_row: map.tiles_per_row,
                chart_index: 0,
                jitter: self.settings.jitter as u32,
                _pad: [0; 3],
            },
        );
        let tile_buffer = scene::multi_object::storage(ctx, "photon tiles", &tiles);
        let group = bind::group(
            ctx,
            "photon map",
            &self.photon_layout,
            &[params.binding(), tile_buffer.as_entire_binding()],
        );
        let mut pass = gpu::pass::begin(
            frame.encoder,
            "photon map",
            &[
                pass::color(&map.address, CLEAR_BLACK),
                pass::color(&map.power, CLEAR_BLACK),
            ],
            Some(pass::depth(&map.depth, CLEAR_FAR)),
            None,
        );
        pass.set_pipeline(&self.photon_pipeline);
        pass.set_bind_group(1, scene.bind_group(), &[]);
        pass.set_bind_group(2, tracer_group, &[]);
        pass.set_bind_group(3, &group, &[]);
        for (i, (object, camera)) in cameras.iter().enumerate() {
            let (x, y) = (i as u32 % map.tiles_per_row, i as u32 / map.tiles_per_row);
            let s = size as f32;
            pass.set_viewport(x as f32 * s, y as f32 * s, s, s, 0.0, 1.0);
            pass.set_bind_group(0, camera, &[]);
            scene.draw_objects(&mut pass, &ObjectFilter::Only(vec![*object]));
        }
    }

    /// Splats `map` into `into`; `slot` is the photon map's (the splatter keeps a bind group
    /// per photon map).
    fn splat(&self, frame: &mut Frame, slot: usize, map: &PhotonMap, into: &LightMap) {
        self.splatter.splat(
            frame,
            slot,
            &into.view,
            self.settings.lightmap_resolution,
            &map.address,
            &map.power,
            &self.charts,
            map.side(self.settings.photons),
            // One lattice per tile: a piece seen from a light.
            if self.settings.footprint {
                self.settings.photons
            } else {
                0
            },
            self.settings.splat_radius,
        );
    }
}

/// One photon landed on the receiver: its light-map address (atlas uv) and power (W).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Landing {
    /// Atlas uv of the landing point in the receiver's chart.
    pub uv: glam::Vec2,
    /// Power per channel (W).
    pub power: Vec3,
}

/// Power and landing place of a set of photons on the receiver.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PhotonSum {
    /// Total power landed (W per channel).
    pub power: Vec3,
    /// Power-weighted mean of the landing points' light-map uv (weights: the channels' sum).
    pub uv_centroid: glam::Vec2,
    /// Photons landed (or texels lit, for a light map).
    pub count: usize,
}

impl PhotonSum {
    /// The sum of `landings`.
    pub fn of(landings: &[Landing]) -> Self {
        let power: Vec3 = landings.iter().map(|l| l.power).sum();
        let weight = power.element_sum();
        let uv = landings
            .iter()
            .map(|l| l.uv * l.power.element_sum())
            .sum::<glam::Vec2>();
        Self {
            power,
            uv_centroid: if weight > 0.0 {
                uv / weight
            } else {
                glam::Vec2::ZERO
            },
            count: landings.len(),
        }
    }
}

/// How far off a surface a photon's next ray starts (metres).
const SURFACE_OFFSET: f32 = 1e-4;
/// Chords a photon follows inside a glass piece (photons.wgsl's).
const PHOTON_CHORDS: usize = 3;

/// A photon refracted into a glass piece of index `ior` at `origin` along `d` leaves it: up to
/// [`PHOTON_CHORDS`] chords, reflecting totally inside. The point just outside the exit, the
/// leaving direction and the transmittance through the exit; `None` if it does not leave.
fn leave_glass(
    on_piece: &impl Fn(Vec3, Vec3) -> Option<scene::bvh::Hit>,
    mut origin: Vec3,
    mut d: Vec3,
    ior: f32,
) -> Option<(Vec3, Vec3, f32)> {
    use gpu::prelude::{fresnel_dielectric, reflect_dir, refract_dir};
    for _ in 0..PHOTON_CHORDS {
        let exit = on_piece(origin, d)?;
        // Outward normal agreeing with the leaving ray.
        let out_n = if exit.normal.dot(d) < 0.0 {
            -exit.normal
        } else {
            exit.normal
        };
        let out = refract_dir(d, -out_n, ior);
        if out.w > 0.5 {
            let transmitted = 1.0 - fresnel_dielectric(d.dot(out_n), 1.0 / ior);
            return Some((
                exit.position + out_n * SURFACE_OFFSET,
                out.truncate(),
                transmitted,
            ));
        }
        d = reflect_dir(d, -out_n);
        origin = exit.position - out_n * SURFACE_OFFSET;
    }
    None
}

/// The photons `photons.wgsl` writes for one piece and light, traced through the piece's exact
/// mesh instead of its refractor map: the same tile view and pixel lattice, the same Fresnel
/// weights, chords (`PHOTON_CHORDS`) and landing rule on the receiver's plane and chart. The
/// yardstick of the GPU's light maps (tests/caustics.rs): their difference is the refractor
/// map's approximation of the exit and the splats clipped at the chart's border.
pub fn exact_photons(
    scene: &Scene,
    bvh: &scene::bvh::SceneBvh,
    piece_object: usize,
    receiver: &Receiver,
    chart: &scene::lightmap::Chart,
    light: &scene::Light,
    photons: u32,
    time: f32,
) -> Vec<Landing> {
    use gpu::prelude::{fresnel_dielectric, fresnel_nk, ray_plane, reflect_dir, refract_dir};
    let o = &scene.objects[piece_object];
    let (tile, view_proj) = tile_view(
        light,
        o.center_at(time),
        o.bounding_radius_at(time),
        photons,
    );
    let inverse = view_proj.inverse();
    let on_piece = |origin: Vec3, dir: Vec3| {
        bvh.closest_hit_where(origin, dir, f32::INFINITY, |i| i == piece_object)
    };
    let to_local = scene.objects[receiver.object].world_at(time).inverse();
    let axis = Vec3::from_slice(&tile.axis[..3]);
    let mut landings = Vec::new();
    for j in 0..photons {
        for i in 0..photons {
            // The pixel centre's ray from the light (row 0 at the top, as the rasterizer).
            let x = (i as f32 + 0.5) / photons as f32 * 2.0 - 1.0;
            let y = 1.0 - (j as f32 + 0.5) / photons as f32 * 2.0;
            let far = inverse.project_point3(Vec3::new(x, y, 1.0));
            let dir = (far - light.position).normalize();
            let Some(entry) = on_piece(light.position, dir) else {
                continue;
            };
            // specular_event: the authored normal turned to face the light's ray.
            let n = if entry.normal.dot(dir) > 0.0 {
                -entry.normal
            } else {
                entry.normal
            };
            let cos_i = -dir.dot(n);
            let (origin, d, mut weight) = match o.material {
                Material::Metal { n: eta, k } => (
                    entry.position + n * SURFACE_OFFSET,
                    reflect_dir(dir, n),
                    fresnel_nk(cos_i, eta, k),
                ),
                Material::Glass { ior } => {
                    let entering = entry.normal.dot(dir) < 0.0;
                    let eta_rel = if entering { ior } else { 1.0 / ior };
                    let t = refract_dir(dir, n, 1.0 / eta_rel);
                    if t.w < 0.5 {
                        continue;
                    }
                    let inside = entry.position - n * SURFACE_OFFSET;
                    let Some((origin, d, out)) = leave_glass(&on_piece, inside, t.truncate(), ior)
                    else {
                        continue;
                    };
                    let weight = Vec3::splat((1.0 - fresnel_dielectric(cos_i, eta_rel)) * out);
                    (origin, d, weight)
                }
                Material::Diffuse { .. } => continue,
            };
            if d.dot(receiver.normal) >= 0.0 {
                continue;
            }
            let s = ray_plane(origin, d, receiver.normal, receiver.offset);
            if s <= 0.0 {
                continue;
            }
            let local = to_local.transform_point3(origin + d * s);
            let (a, b) = chart.plane_axes();
            let side = chart.side();
            let c = (glam::Vec2::new(local[a], local[b]) - chart.min) / side;
            let limit = chart.extent / side;
            if c.x < 0.0 || c.y < 0.0 || c.x > limit.x || c.y > limit.y {
                continue;
            }
            let cos_axis = (entry.position - light.position).normalize().dot(axis);
            weight *= tile.axis[3] * cos_axis.powi(3);
            landings.push(Landing {
                uv: chart.uv(local),
                power: light.intensity * weight,
            });
        }
    }
    landings
}

/// The receiver's chart (its lit face) in an atlas made for it alone.
fn receiver_chart(atlas: &ChartAtlas, object: usize) -> Result<ChartGpu, TechniqueError> {
    let index = (0..6)
        .find_map(|axis| atlas.chart(object, axis).map(|_| axis))
        .ok_or_else(|| {
            TechniqueError::Unsupported("the caustic receiver has no light-map chart".into())
        })?;
    let i = atlas.chart_of[6 * object + index as usize] as usize;
    Ok(atlas.gpu_charts()[i])
}

/// A tile's view from `light` holding the sphere (`centre`, `radius`)
/// (`scene::lightmap::LightView`) and its [`PhotonTileGpu`] (the flux a pixel carries:
/// intensity times its solid angle).
fn tile_view(
    light: &scene::Light,
    centre: Vec3,
    radius: f32,
    size: u32,
) -> (PhotonTileGpu, glam::Mat4) {
    let view = scene::lightmap::LightView::of_sphere(light.position, centre, radius, size);
    let tile = PhotonTileGpu {
        light: light.position.extend(1.0).to_array(),
        intensity: light.intensity.extend(0.0).to_array(),
        axis: view.axis.extend(view.pixel_area).to_array(),
    };
    (tile, view.view_proj)
}

fn clear(encoder: &mut wgpu::CommandEncoder, view: &wgpu::TextureView) {
    gpu::pass::begin(
        encoder,
        "clear light map",
        &[pass::color(view, CLEAR_BLACK)],
        None,
        None,
    );
}

/// The caustics' apply pass: the receiver drawn again adding the static and the moving
/// pieces' light maps. Its pipeline and its one bind group (the receiver's chart and both
/// maps).
fn apply_pass(
    ctx: &Context,
    scene: &GpuScene,
    settings: &CausticSettings,
    atlas: &ChartAtlas,
    receiver: Receiver,
    [static_map, moving_map]: [&LightMap; 2],
) -> Result<(wgpu::RenderPipeline, wgpu::BindGroup), TechniqueError> {
    let frag = wgpu::ShaderStages::FRAGMENT;
    let apply_layout = bind::layout(
        ctx,
        "caustics apply",
        frag,
        &[
            bind::uniform(),    // ReceiverParams
            bind::texture_2d(), // static light map
            bind::texture_2d(), // moving light map
            bind::sampler(),
        ],
    );
    let module = scene::shader(ctx, "caustics apply", APPLY_WGSL);
    let apply_pipeline = scene::scene_pipeline_with(
        ctx,
        "caustics apply",
        &scene.pipeline_layout_with(ctx, &[&apply_layout]),
        &module,
        "caustics_apply_fs",
        &[pass::color_target(
            gpu::HDR_FORMAT,
            Some(ADD_RGB_KEEP_ALPHA),
        )],
        (false, wgpu::CompareFunction::LessEqual),
    );
    let chart = receiver_chart(atlas, receiver.object)?;
    let params = Uniform::new(
        ctx,
        "caustic receiver",
        &ReceiverParamsGpu {
            chart,
            object: receiver.object as u32,
            side: settings.lightmap_resolution as f32,
            _pad: [0; 2],
        },
    );
    let apply_group = bind::group(
        ctx,
        "caustics apply",
        &apply_layout,
        &[
            params.binding(),
            bind::view(&static_map.view),
            bind::view(&moving_map.view),
            bind::sampler_resource(&ctx.samplers.linear_clamp),
        ],
    );
    Ok((apply_pipeline, apply_group))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_chessboard_receives_the_caustics_not_the_table_under_it() {
        let scene = scene::load("chess").unwrap();
        let board = scene
            .objects
            .iter()
            .position(|o| o.name == "board")
            .unwrap();
        let r = caustic_receiver(&scene, Vec3::new(0.0, 0.1, 0.0)).unwrap();
        assert_eq!(r.object, board);
        assert!((r.normal - Vec3::Y).length() < 1e-6 && r.offset.abs() < 1e-6);
    }

    #[test]
    fn the_cornell_floor_receives_the_caustics() {
        let scene = scene::load("cornell-sphere").unwrap();
        let centre = scene
            .objects
            .iter()
            .find(|o| !matches!(o.material, Material::Diffuse { .. }))
            .unwrap()
            .center_at(0.0);
        let r = caustic_receiver(&scene, centre).unwrap();
        let floor = &scene.objects[r.object];
        assert!(floor.name.contains("floor"), "{}", floor.name);
        assert!(r.normal.y > 0.99);
    }

    #[test]
    fn a_tile_holds_its_piece_and_carries_the_lights_flux() {
        let light = scene::Light {
            name: "lamp".into(),
            position: Vec3::new(0.5, 2.2, 0.9),
            intensity: Vec3::splat(9.0),
            kind: scene::LightKind::Point,
        };
        let (centre, radius, size) = (Vec3::new(0.1, 0.05, -0.3), 0.05, 64);
        let (tile, view_proj) = tile_view(&light, centre, radius, size);
        // The centre projects to the tile's middle, the sphere stays inside it.
        let c = view_proj.project_point3(centre);
        assert!(c.x.abs() < 1e-4 && c.y.abs() < 1e-4 && c.z > 0.0 && c.z < 1.0);
        let side = (centre - light.position).cross(Vec3::Y).normalize() * radius;
        let edge = view_proj.project_point3(centre + side);
        assert!(edge.x.abs().max(edge.y.abs()) < 1.0);
        // Summed over the tile, the pixels' solid angles (area * cos^3) cover the view's
        // pyramid: 4 asin(sin(a)^2) for a square of half-angle a.
        let a = tile.axis[3].sqrt() * size as f32 / 2.0;
        let mut sum = 0.0f64;
        for j in 0..size {
            for i in 0..size {
                let u = ((i as f32 + 0.5) / size as f32 * 2.0 - 1.0) * a;
                let v = ((j as f32 + 0.5) / size as f32 * 2.0 - 1.0) * a;
                let cos = 1.0 / (1.0 + u * u + v * v).sqrt();
                sum += (tile.axis[3] * cos * cos * cos) as f64;
            }
        }
        let half = a.atan();
        let exact = 4.0 * (half.sin() * half.sin()).asin();
        assert!((sum as f32 / exact - 1.0).abs() < 2e-3, "{sum} vs {exact}");
    }
}
