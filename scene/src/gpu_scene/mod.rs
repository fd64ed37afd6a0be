//! The scene on the GPU and the shared raster pass.
//!
//! `GpuScene` uploads every object once (object-space vertices, those of a deforming object
//! rewritten at each new time; one index range per object; a storage buffer of per-object
//! transforms and materials; the lights; the diffuse textures as one texture array) and owns
//! one distance shadow map per light: a cube map around a point or spot light inside (or near)
//! the scene's bounding sphere, or one 2D map fitted to that sphere for one farther than 1.5
//! radii from its centre, and for a directional light an orthographic one along its direction
//! (`FittedShadow`). Its raster pass
//! shades diffuse surfaces exactly like the CPU reference (`shaders/scene.wgsl`), so every
//! technique differs from the reference only where its special objects are.
//!
//! Techniques reuse the same bindings: their shaders are their own fragment entry points,
//! importing what they use from the WGSL module `scene::shading` ([`crate::SHADING`], composed
//! by [`crate::shader`]) and drawn with `scene_vs` ([`crate::SCENE_VS_WGSL`]), with the camera
//! at `@group(0)` and the scene data at `@group(1)` (see [`GpuScene::pipeline_layout_with`]).

use crate::shading::{RASTER_WGSL, scene_pipeline, shader};
use crate::{Frame, Light, LightKind, Material, Object, Scene, SceneError};
use glam::{Mat4, Vec3, Vec4};
use gpu::cube::CubeTarget;
use gpu::pass::{self, Load};
use gpu::wgpu::{self, util::DeviceExt};
use gpu::{Context, Uniform, Vertex, bind};

mod host;
mod shadows;
mod upload;
pub use shadows::*;
pub use upload::*;

/// Resolution of each face of the shadow cube maps, and of each fitted 2D shadow map, while
/// the lights' maps fit [`SHADOW_BUDGET_BYTES`].
pub const SHADOW_MAP_SIZE: u32 = 1024;
/// GPU memory the shadow maps of all lights may take together (a cube map of six R32Float
/// faces and one fitted 2D map per light). Past it the maps get coarser, halving their side
/// down to [`MIN_SHADOW_MAP_SIZE`]: 1024 texels per side up to 18 lights, 128 for 300.
pub const SHADOW_BUDGET_BYTES: u64 = 512 << 20;
/// The coarsest shadow map side; a scene needing coarser maps is refused (see
/// [`shadow_map_size`]).
pub const MIN_SHADOW_MAP_SIZE: u32 = 64;

/// The side of the shadow maps for `lights` lights on a device whose texture arrays
/// hold at most `max_layers` layers: the largest power of two up to [`SHADOW_MAP_SIZE`] whose
/// maps fit [`SHADOW_BUDGET_BYTES`]. Fails, naming the limit, when even
/// [`MIN_SHADOW_MAP_SIZE`] does not fit or the cube maps need more layers than the device has
/// (six per light): the GPU techniques then cannot render the scene, while the CPU reference,
/// which traces shadow rays, has no such limit. A scene without lights (a renderer's object
/// uploaded alone, `crate::hosted`) gets 1 x 1 maps: nothing reads them.
pub fn shadow_map_size(lights: usize, max_layers: u32) -> Result<u32, SceneError> {
    if lights == 0 {
        return Ok(1);
    }
    let bytes = |size: u64| lights.max(1) as u64 * 7 * 4 * size * size;
    let max_lights = (max_layers / 6) as usize;
    let mut size = SHADOW_MAP_SIZE;
    while size > MIN_SHADOW_MAP_SIZE && bytes(size as u64) > SHADOW_BUDGET_BYTES {
        size /= 2;
    }
    if lights > max_lights || bytes(size as u64) > SHADOW_BUDGET_BYTES {
        let by_budget = SHADOW_BUDGET_BYTES / (7 * 4 * (MIN_SHADOW_MAP_SIZE as u64).pow(2));
        return Err(SceneError::Invalid(format!(
            "the scene has {lights} lights; the GPU scene keeps a shadow cube map per \
             light and takes at most {} on this adapter ({max_layers} texture array layers, \
             six per light; {} MB of shadow maps at {MIN_SHADOW_MAP_SIZE} texels per side); \
             the CPU reference has no such limit",
            max_lights.min(by_budget as usize),
            SHADOW_BUDGET_BYTES >> 20
        )));
    }
    Ok(size)
}
const SHADOW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;
/// Distance written for texels that see no geometry (must match scene.wgsl): the hosts'
/// contract, `gpu::host::BACKGROUND_DISTANCE`.
pub const BACKGROUND_DISTANCE: f32 = gpu::host::BACKGROUND_DISTANCE;

/// Which objects a draw call includes.
#[derive(Clone, Debug, PartialEq)]
pub enum ObjectFilter {
    All,
    /// Objects without special roles and with diffuse materials.
    Diffuse,
    /// Every object except these indices.
    Except(Vec<usize>),
    /// Only these indices.
    Only(Vec<usize>),
}

impl ObjectFilter {
    pub fn includes(&self, index: usize, object: &Object) -> bool {
        match self {
            ObjectFilter::All => true,
            ObjectFilter::Diffuse => {
                object.roles.is_empty() && matches!(object.material, Material::Diffuse { .. })
            }
            ObjectFilter::Except(list) => !list.contains(&index),
            ObjectFilter::Only(list) => list.contains(&index),
        }
    }
}

/// Where a raster pass draws: a colour view of a known format, a depth view, and whether to
/// clear them first (to the background radiance and [`BACKGROUND_DISTANCE`]).
pub struct RasterTarget<'a> {
    pub color: &'a wgpu::TextureView,
    pub depth: &'a wgpu::TextureView,
    pub format: wgpu::TextureFormat,
    pub clear: bool,
}

impl<'a> RasterTarget<'a> {
    /// The frame's own target: `target`'s colour (`gpu::HDR_FORMAT`) and depth, cleared first
    /// or drawn over.
    pub fn of(target: &'a gpu::Target, clear: bool) -> Self {
        Self {
            color: &target.color_view,
            depth: &target.depth_view,
            format: gpu::HDR_FORMAT,
            clear,
        }
    }
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct CameraGpu {
    view_proj: [[f32; 4]; 4],
    eye: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ObjectGpu {
    model: [[f32; 4]; 4],
    normal_matrix: [[f32; 4]; 4],
    albedo: [f32; 4],
    material: [f32; 4],
    n: [f32; 4],
    k: [f32; 4],
    emission: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct LightGpu {
    position: [f32; 4],
    intensity: [f32; 4],
    shadow_view_proj: [[f32; 4]; 4],
    shadow_params: [f32; 4],
    direction: [f32; 4],
    cone: [f32; 4],
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct SceneInfoGpu {
    light_count: u32,
    shadow_size: f32,
    specular_as_diffuse: u32,
    _pad: u32,
    background: [f32; 4],
    medium: crate::medium::MediumGpu,
}

/// One object's slice of the shared vertex and index buffers.
#[derive(Clone, Copy, Debug)]
pub struct DrawRange {
    pub first_index: u32,
    pub index_count: u32,
    pub base_vertex: i32,
}

/// The uploaded scene.
pub struct GpuScene {
    /// The CPU scene this was made from (techniques read materials, roles, positions).
    pub scene: Scene,
    pub vertex_buffer: wgpu::Buffer,
    pub index_buffer: wgpu::Buffer,
    pub draws: Vec<DrawRange>,
    pub camera_layout: wgpu::BindGroupLayout,
    pub scene_layout: wgpu::BindGroupLayout,
    scene_bind_group: wgpu::BindGroup,
    raster_bind_group: wgpu::BindGroup,
    shadow_bind_group: wgpu::BindGroup,
    object_buffer: wgpu::Buffer,
    light_buffer: wgpu::Buffer,
    info_buffer: Uniform<SceneInfoGpu>,
    raster_info_buffer: Uniform<SceneInfoGpu>,
    /// The lights' shadow maps (every object a caster).
    shadows: ShadowTextures,
    /// Per light: the fitted 2D shadow map's projection, for lights outside the scene.
    fitted: Vec<Option<FittedShadow>>,
    raster_pipelines: Vec<(wgpu::TextureFormat, wgpu::RenderPipeline)>,
    shadow_pipeline: wgpu::RenderPipeline,
    time: Option<f32>,
    cameras: std::sync::Mutex<CameraCache>,
    /// Per object: its bounding sphere where the shadow maps last saw it (moving and deforming
    /// objects only; see [`GpuScene::set_time`]).
    shadow_spheres: Vec<Option<(Vec3, f32)>>,
}

/// The camera bind groups of the views a scene was drawn from, by their contents: a view seen
/// again (the same cube face of an object that did not move, the same light's shadow face, the
/// same eye) reuses its uniform and bind group instead of creating both again, so a technique
/// that draws hundreds of cube faces a frame creates none once its objects stand still. A
/// group's contents never change after it is made, so a technique may keep one across frames.
/// Views not drawn for [`CameraCache::KEEP_FRAMES`] frames are let go once the cache holds
/// more than [`CameraCache::MAX_ENTRIES`].
#[derive(Default)]
struct CameraCache {
    /// Key: the bits of the uniform's contents (`CameraGpu`).
    entries: std::collections::HashMap<[u32; 20], (wgpu::BindGroup, u64)>,
    /// Frames begun ([`GpuScene::set_time`] calls).
    frame: u64,
}

impl CameraCache {
    const MAX_ENTRIES: usize = 2048;
    const KEEP_FRAMES: u64 = 2;

    fn key(data: &CameraGpu) -> [u32; 20] {
        let mut key = [0u32; 20];
        for (k, v) in key
            .iter_mut()
            .zip(data.view_proj.iter().flatten().chain(&data.eye))
        {
            *k = v.to_bits();
        }
        key
    }

    /// A new frame: views unused for a while are dropped when the cache is full.
    fn next_frame(&mut self) {
        self.frame += 1;
        if self.entries.len() > Self::MAX_ENTRIES {
            let frame = self.frame;
            self.entries
                .retain(|_, (_, used)| frame - *used <= Self::KEEP_FRAMES);
        }
    }

    /// Views the cache holds (for tests).
    fn len(&self) -> usize {
        self.entries.len()
    }
}

impl GpuScene {
    /// Uploads `scene` (validated first).
    pub fn new(ctx: &Context, scene: &Scene) -> Result<Self, SceneError> {
        scene.validate()?;
        let shadow_size = shadow_map_size(
            scene.lights.len(),
            ctx.device.limits().max_texture_array_layers,
        )?;
        ctx.allocating("uploading the scene", || {
            Self::upload(ctx, scene, shadow_size)
        })?
    }

    fn upload(ctx: &Context, scene: &Scene, shadow_size: u32) -> Result<Self, SceneError> {
        let device = &ctx.device;
        let (vertex_buffer, index_buffer, object_buffer, draws) = mesh_buffers(ctx, scene);
        let fitted = fitted_shadows(scene);
        let (lights, light_count) = light_records(scene, &fitted);
        let light_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("scene lights"),
            contents: bytemuck::cast_slice(&lights),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        });
        let info = |specular_as_diffuse: u32| SceneInfoGpu {
            light_count,
            shadow_size: shadow_size as f32,
            specular_as_diffuse,
            _pad: 0,
            background: scene.background.extend(0.0).to_array(),
            medium: crate::Medium::gpu(scene.medium.as_ref()),
        };
        let info_buffer = Uniform::new(ctx, "scene info", &info(0));
        let raster_info_buffer = Uniform::new(ctx, "scene info (specular as diffuse)", &info(1));

        let albedo_view = upload_textures(ctx, scene)?;
        let shadows = ShadowTextures::new(
            ctx,
            lights.len(),
            fitted.iter().any(Option::is_some),
            shadow_size,
            "shadow maps",
        );
        let camera_layout = camera_bind_group_layout(ctx);
        let scene_layout = scene_bind_group_layout(ctx);
        let samplers = &ctx.samplers;
        // The resources of `surface_bindings` (upload.rs), which both groups start with.
        let surfaces = || {
            [
                object_buffer.as_entire_binding(),
                light_buffer.as_entire_binding(),
                bind::view(&albedo_view),
                bind::sampler_resource(&samplers.linear_repeat),
            ]
        };
        let bind = |info: &Uniform<SceneInfoGpu>| {
            let mut resources = surfaces().to_vec();
            resources.extend([
                bind::view(&shadows.cube_view),
                bind::sampler_resource(&samplers.nearest_clamp),
                info.binding(),
                bind::view(&shadows.fitted_array_view),
            ]);
            bind::group(ctx, "scene", &scene_layout, &resources)
        };
        let scene_bind_group = bind(&info_buffer);
        let raster_bind_group = bind(&raster_info_buffer);

        let layout = pipeline_layout(ctx, &camera_layout, &scene_layout, &[]);
        let module = shader(ctx, "raster", RASTER_WGSL);
        let raster_pipelines = [gpu::HDR_FORMAT, wgpu::TextureFormat::Rgba16Float]
            .into_iter()
            .map(|f| {
                (
                    f,
                    scene_pipeline(ctx, "raster", &layout, &module, "raster_fs", f),
                )
            })
            .collect();
        // The shadow pass writes the shadow maps, so it must not bind them: its group 1 holds
        // only the objects, lights and albedo textures (all that scene_vs and shadow_fs read).
        let surfaces_layout = surfaces_only_layout(ctx);
        let shadow_bind_group =
            bind::group(ctx, "scene surfaces only", &surfaces_layout, &surfaces());
        let shadow_layout = pipeline_layout(ctx, &camera_layout, &surfaces_layout, &[]);
        let shadow_pipeline = scene_pipeline(
            ctx,
            "shadow",
            &shadow_layout,
            &module,
            "shadow_fs",
            SHADOW_FORMAT,
        );

        Ok(Self {
            scene: scene.clone(),
            vertex_buffer,
            index_buffer,
            draws,
            camera_layout,
            scene_layout,
            scene_bind_group,
            raster_bind_group,
            shadow_bind_group,
            object_buffer,
            light_buffer,
            info_buffer,
            raster_info_buffer,
            shadows,
            fitted,
            raster_pipelines,
            shadow_pipeline,
            time: None,
            cameras: Default::default(),
            shadow_spheres: vec![None; scene.objects.len()],
        })
    }

    /// The shadow cube maps' distances, layer by layer (six per light), read back: what a test
    /// compares.
    pub fn read_shadow_maps(&self, ctx: &Context) -> Result<Vec<Vec<u8>>, gpu::GpuError> {
        self.shadows.read(ctx)
    }

    /// The scene's own shadow maps (cube array, fitted 2D array): what `@group(1)` binds as
    /// `shadow_maps` and `fitted_shadow_maps`, for a pass that reads them through
    /// `light_visibility_in` beside other casters' maps ([`CasterShadowMaps`]).
    pub fn shadow_views(&self) -> (&wgpu::TextureView, &wgpu::TextureView) {
        (&self.shadows.cube_view, &self.shadows.fitted_array_view)
    }

    /// The scene bind group (`@group(1)`) for technique pipelines.
    pub fn bind_group(&self) -> &wgpu::BindGroup {
        &self.scene_bind_group
    }

    /// A camera bind group (`@group(0)`) for one view: world-to-clip matrix and eye position.
    /// Made once per distinct view and kept while the view is drawn (see `CameraCache`), so
    /// drawing the same view again creates no GPU object.
    pub fn camera_bind_group(&self, ctx: &Context, view_proj: Mat4, eye: Vec3) -> wgpu::BindGroup {
        let data = CameraGpu {
            view_proj: view_proj.to_cols_array_2d(),
            eye: eye.extend(1.0).to_array(),
        };
        let key = CameraCache::key(&data);
        let mut cache = self.cameras.lock().unwrap_or_else(|e| e.into_inner());
        let frame = cache.frame;
        if let Some((group, used)) = cache.entries.get_mut(&key) {
            *used = frame;
            return group.clone();
        }
        let camera = Uniform::new(ctx, "camera", &data);
        let group = bind::group(ctx, "camera", &self.camera_layout, &[camera.binding()]);
        cache.entries.insert(key, (group.clone(), frame));
        group
    }

    /// Distinct views whose camera bind groups the scene holds.
    pub fn cached_cameras(&self) -> usize {
        self.cameras.lock().map(|c| c.len()).unwrap_or(0)
    }

    /// A pipeline layout with the camera at group 0, the scene at group 1 and `extra` after.
    pub fn pipeline_layout_with(
        &self,
        ctx: &Context,
        extra: &[&wgpu::BindGroupLayout],
    ) -> wgpu::PipelineLayout {
        pipeline_layout(ctx, &self.camera_layout, &self.scene_layout, extra)
    }

    /// Moves objects to `time` (transforms uploaded), deforms the deforming ones (their
    /// vertices at `time`, [`Object::positions_at`] and [`Object::normals_at`], rewritten in
    /// their range of [`Self::vertex_buffer`]) and re-renders the shadow maps when anything
    /// moved or deformed, recording into `frame`: call once per frame before drawing. The
    /// writes are queue writes, applied when the frame is submitted, before its passes.
    pub fn set_time(&mut self, frame: &mut Frame, time: f32) {
        self.cameras
            .get_mut()
            .unwrap_or_else(|e| e.into_inner())
            .next_frame();
        let moving = self
            .scene
            .objects
            .iter()
            .any(|o| !o.motion.is_static() || o.is_deforming());
        if self.time == Some(time) || (self.time.is_some() && !moving) {
            return;
        }
        frame.gpu.queue.write_buffer(
            &self.object_buffer,
            0,
            bytemuck::cast_slice(&object_records(&self.scene, time)),
        );
        for (o, draw) in self.scene.objects.iter().zip(&self.draws) {
            if o.is_deforming() {
                let offset = draw.base_vertex as u64 * std::mem::size_of::<Vertex>() as u64;
                frame.gpu.queue.write_buffer(
                    &self.vertex_buffer,
                    offset,
                    bytemuck::cast_slice(&object_vertices(o, time)),
                );
            }
        }
        let first = self.time.is_none();
        self.time = Some(time);
        let moved = self.moved_spheres(time);
        self.render_shadows(frame, (!first).then_some(moved.as_slice()));
    }

    /// Places object `index` by `transform` (its base transform, before its motion) and rewrites
    /// the objects' records and the shadow maps now, recording into `frame`: how a renderer's
    /// object uploaded alone (`crate::hosted`) follows the renderer, frame by frame.
    pub fn set_transform(&mut self, frame: &mut Frame, index: usize, transform: Mat4) {
        self.set_transforms(frame, &[(index, transform)]);
    }

    /// [`GpuScene::set_transform`] of several objects at once: the records and the shadow maps
    /// are rewritten once.
    pub fn set_transforms(&mut self, frame: &mut Frame, placed: &[(usize, Mat4)]) {
        for &(index, transform) in placed {
            self.scene.objects[index].transform = transform;
        }
        let time = self.time();
        frame.gpu.queue.write_buffer(
            &self.object_buffer,
            0,
            bytemuck::cast_slice(&object_records(&self.scene, time)),
        );
        self.render_shadows(frame, None);
    }

    /// The bounding spheres of every moving or deforming object where the shadow maps last saw
    /// it and where it is at `time` (both: the old shadow goes, the new one comes), noted as
    /// seen.
    fn moved_spheres(&mut self, time: f32) -> Vec<(Vec3, f32)> {
        let mut spheres = Vec::new();
        for (o, seen) in self.scene.objects.iter().zip(&mut self.shadow_spheres) {
            if o.motion.is_static() && !o.is_deforming() {
                continue;
            }
            let now = (o.center_at(time), o.bounding_radius_at(time) * 1.01 + 1e-4);
            spheres.extend(seen.replace(now));
            spheres.push(now);
        }
        spheres
    }

    /// The time the GPU transforms were last set to.
    pub fn time(&self) -> f32 {
        self.time.unwrap_or(0.0)
    }

    /// Renders the shadow maps: every face, or (`moved`: the spheres of what moved) only the
    /// cube faces one of them reaches: a face no moving object enters or leaves holds the same
    /// distances as before, so drawing it again would write what it holds. The fitted 2D map
    /// of a light outside the scene is one face, drawn again whenever anything moved.
    fn render_shadows(&self, frame: &mut Frame, moved: Option<&[(Vec3, f32)]>) {
        self.render_shadow_faces(frame, &self.shadows, &ObjectFilter::All, moved);
    }

    /// Draws the casters `filter` selects into `maps` (laid out as the scene's own), every
    /// face or those `moved` reaches (see [`Self::render_shadows`]).
    fn render_shadow_faces(
        &self,
        frame: &mut Frame,
        maps: &ShadowTextures,
        filter: &ObjectFilter,
        moved: Option<&[(Vec3, f32)]>,
    ) {
        for (l, light) in self.scene.lights.iter().enumerate() {
            // A light outside the scene renders one 2D map fitted to it; others six cube faces.
            let faces: Vec<(usize, Mat4, &wgpu::TextureView)> = match &self.fitted[l] {
                Some(f) => vec![(0, f.view_proj, &maps.fitted_views[l])],
                None => (0..6)
                    .filter(|&face| {
                        moved.is_none_or(|spheres| {
                            spheres
                                .iter()
                                .any(|&(c, r)| sphere_meets_cube_face(c - light.position, r, face))
                        })
                    })
                    .map(|face| {
                        let vp = gpu::cube::cube_face_view_proj(
                            face,
                            light.position,
                            0.01,
                            2.0 * BACKGROUND_DISTANCE,
                        );
                        (face, vp, &maps.face_views[6 * l + face])
                    })
                    .collect(),
            };
            for (face, view_proj, view) in faces {
                // An orthographic map measures distances from its own eye.
                let eye = self.fitted[l].and_then(|f| f.eye).unwrap_or(light.position);
                let camera = self.camera_bind_group(frame.gpu, view_proj, eye);
                let writes = frame.timer.render_pass("shadow maps");
                let far = wgpu::Color {
                    r: 2.0 * BACKGROUND_DISTANCE as f64,
                    g: 0.0,
                    b: 0.0,
                    a: 0.0,
                };
                let mut pass = gpu::pass::begin(
                    frame.encoder,
                    "shadow face",
                    &[pass::color(view, Load::Clear(far))],
                    Some(pass::depth(&maps.depth_views[face], pass::CLEAR_FAR)),
                    writes,
                );
                pass.set_pipeline(&self.shadow_pipeline);
                pass.set_bind_group(0, &camera, &[]);
                pass.set_bind_group(1, &self.shadow_bind_group, &[]);
                self.draw_objects(&mut pass, filter);
            }
        }
    }

    /// Renders the six faces of `cube` as seen from `center`, the loop every cube map in the
    /// workspace shares (distance and refractor maps, environment maps, caustic receivers):
    /// for each face, `draw_face` gets the face's projection (near plane `near`, far plane
    /// beyond the background sphere), its camera bind group and the face's colour and depth
    /// views as a cleared [`RasterTarget`].
    pub fn render_cube(
        &self,
        frame: &mut Frame,
        cube: &CubeTarget,
        center: Vec3,
        near: f32,
        mut draw_face: impl FnMut(&mut Frame, &CubeFace),
    ) {
        for index in 0..6 {
            let view_proj =
                gpu::cube::cube_face_view_proj(index, center, near, 2.0 * BACKGROUND_DISTANCE);
            let face = CubeFace {
                index,
                view_proj,
                eye: center,
                camera: self.camera_bind_group(frame.gpu, view_proj, center),
                target: RasterTarget {
                    color: &cube.face_views[index],
                    depth: &cube.depth_face_views[index],
                    format: cube.format,
                    clear: true,
                },
            };
            draw_face(frame, &face);
        }
    }

    /// The shared raster pass into every face of `cube` from `center`: an environment map
    /// of the objects `filter` selects, radiance in rgb and the distance from `center` in
    /// alpha (a distance impostor's map).
    pub fn raster_cube(
        &self,
        frame: &mut Frame,
        cube: &CubeTarget,
        center: Vec3,
        filter: &ObjectFilter,
        specular_as_diffuse: bool,
    ) {
        self.render_cube(frame, cube, center, 0.01, |frame, face| {
            self.raster(
                frame,
                &face.target,
                face.view_proj,
                face.eye,
                filter,
                specular_as_diffuse,
            );
        });
    }

    /// A pass that draws over `color` and `depth` (both kept) with `pipeline`, the camera at
    /// `@group(0)` and the scene at `@group(1)` (the caller binds its own from `@group(2)` and
    /// draws), timed as `span` (pass timestamps): how a technique draws its objects over the
    /// frame, the harness's or a renderer's.
    pub fn pass_over<'f>(
        &self,
        frame: &'f mut Frame,
        label: &str,
        (color, depth): (&wgpu::TextureView, &wgpu::TextureView),
        span: &str,
        (pipeline, camera): (&wgpu::RenderPipeline, &wgpu::BindGroup),
    ) -> wgpu::RenderPass<'f> {
        let mut pass = gpu::pass::begin(
            frame.encoder,
            label,
            &[pass::color(color, Load::Keep)],
            Some(pass::depth(depth, Load::Keep)),
            frame.timer.render_pass(span),
        );
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, camera, &[]);
        pass.set_bind_group(1, self.bind_group(), &[]);
        pass
    }

    /// Draws the objects `filter` selects with `pipeline` (camera at `@group(0)`, the scene at
    /// `@group(1)`, `extra` groups from `@group(2)`) into every face of `cube` from `center`:
    /// how a technique renders its own per-object cube map (a refractor's distance and
    /// normal map, for example).
    #[allow(clippy::too_many_arguments)]
    pub fn draw_cube(
        &self,
        frame: &mut Frame,
        cube: &CubeTarget,
        center: Vec3,
        near: f32,
        pipeline: &wgpu::RenderPipeline,
        extra: &[&wgpu::BindGroup],
        filter: &ObjectFilter,
        label: &str,
    ) {
        self.render_cube(frame, cube, center, near, |frame, face| {
            let mut pass = begin_scene_pass(frame.encoder, &face.target, Vec3::ZERO, label);
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &face.camera, &[]);
            pass.set_bind_group(1, self.bind_group(), &[]);
            for (i, group) in extra.iter().enumerate() {
                pass.set_bind_group(2 + i as u32, *group, &[]);
            }
            self.draw_objects(&mut pass, filter);
        });
    }

    /// The shared raster pass: draws the objects selected by `filter` into `target` with the
    /// reference's diffuse shading. With `specular_as_diffuse`, metals and glass are drawn
    /// as plain grey diffuse (the `raster` technique); otherwise they are skipped here and
    /// left to the technique.
    pub fn raster(
        &self,
        frame: &mut Frame,
        target: &RasterTarget,
        view_proj: Mat4,
        eye: Vec3,
        filter: &ObjectFilter,
        specular_as_diffuse: bool,
    ) {
        let Some((_, pipeline)) = self
            .raster_pipelines
            .iter()
            .find(|(f, _)| *f == target.format)
        else {
            panic!(
                "raster pass supports Rgba32Float and Rgba16Float targets, not {:?}",
                target.format
            );
        };
        let camera = self.camera_bind_group(frame.gpu, view_proj, eye);
        let mut pass = begin_scene_pass(frame.encoder, target, self.scene.background, "raster");
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &camera, &[]);
        pass.set_bind_group(
            1,
            if specular_as_diffuse {
                &self.raster_bind_group
            } else {
                &self.scene_bind_group
            },
            &[],
        );
        let keep_specular = specular_as_diffuse;
        let scene = &self.scene;
        self.draw_filtered(&mut pass, |i| {
            let o = &scene.objects[i];
            filter.includes(i, o) && (keep_specular || !o.material.is_specular())
        });
    }

    /// Records indexed draws of the objects `filter` selects (vertex/index buffers set here;
    /// the caller has set its pipeline and bind groups).
    pub fn draw_objects(&self, pass: &mut wgpu::RenderPass<'_>, filter: &ObjectFilter) {
        let scene = &self.scene;
        self.draw_filtered(pass, |i| filter.includes(i, &scene.objects[i]));
    }

    /// The arguments of every object's indexed draw as `draw_indexed_indirect` reads them
    /// (`index_count, instance_count, first_index, base_vertex, first_instance`), one instance
    /// each, the object's index as the instance (what `scene_vs` reads): the initial contents of
    /// an indirect buffer a GPU pass then edits (the depth peeler's layer count).
    pub fn indirect_draw_args(&self) -> Vec<[u32; 5]> {
        self.draws
            .iter()
            .enumerate()
            .map(|(i, d)| {
                [
                    d.index_count,
                    1,
                    d.first_index,
                    d.base_vertex as u32,
                    i as u32,
                ]
            })
            .collect()
    }

    /// [`GpuScene::draw_objects`] from an indirect buffer laid out as
    /// [`GpuScene::indirect_draw_args`], starting at byte `offset`. The device must have
    /// `INDIRECT_FIRST_INSTANCE` (the object index is the first instance).
    pub fn draw_objects_indirect(
        &self,
        pass: &mut wgpu::RenderPass<'_>,
        filter: &ObjectFilter,
        args: &wgpu::Buffer,
        offset: u64,
    ) {
        pass.set_vertex_buffer(0, self.vertex_buffer.slice(..));
        pass.set_index_buffer(self.index_buffer.slice(..), wgpu::IndexFormat::Uint32);
        let stride = std::mem::size_of::<[u32; 5]>() as u64;
        for (i, d) in self.draws.iter().enumerate() {
            if filter.includes(i, &self.scene.objects[i]) && d.index_count > 0 {
                pass.draw_indexed_indirect(args, offset + i as u64 * stride);
            }
        }
    }

    fn draw_filtered(&self, pass: &mut wgpu::RenderPass<'_>, include: impl Fn(usize) -> bool) {
        pass.set_vertex_buffer(0, self.vertex_buffer.slice(..));
        pass.set_index_buffer(self.index_buffer.slice(..), wgpu::IndexFormat::Uint32);
        for (i, d) in self.draws.iter().enumerate() {
            if include(i) && d.index_count > 0 {
                let instance = i as u32;
                pass.draw_indexed(
                    d.first_index..d.first_index + d.index_count,
                    d.base_vertex,
                    instance..instance + 1,
                );
            }
        }
    }

    /// Keeps the light and info buffers alive and documents that they exist for techniques
    /// that bind them directly.
    pub fn light_buffer(&self) -> &wgpu::Buffer {
        &self.light_buffer
    }
    pub fn object_buffer(&self) -> &wgpu::Buffer {
        &self.object_buffer
    }
    pub fn info_buffers(&self) -> (&wgpu::Buffer, &wgpu::Buffer) {
        (self.info_buffer.buffer(), self.raster_info_buffer.buffer())
    }
}

/// One face of a cube map being rendered by [`GpuScene::render_cube`].
pub struct CubeFace<'a> {
    /// Layer 0..6: +X, -X, +Y, -Y, +Z, -Z.
    pub index: usize,
    /// World to clip for this face ([`gpu::cube::cube_face_view_proj`]).
    pub view_proj: Mat4,
    /// The cube's centre, the eye of every face.
    pub eye: Vec3,
    /// The camera bind group (`@group(0)`) of this face.
    pub camera: wgpu::BindGroup,
    /// The face's colour and depth views, cleared when the pass begins.
    pub target: RasterTarget<'a>,
}

/// Begins a render pass on `target` (cleared to the background and its distance if asked).
pub fn begin_scene_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    target: &RasterTarget,
    background: Vec3,
    label: &str,
) -> wgpu::RenderPass<'e> {
    let (color, depth) = if target.clear {
        let background = wgpu::Color {
            r: background.x as f64,
            g: background.y as f64,
            b: background.z as f64,
            a: BACKGROUND_DISTANCE as f64,
        };
        (Load::Clear(background), pass::CLEAR_FAR)
    } else {
        (Load::Keep, Load::Keep)
    };
    gpu::pass::begin(
        encoder,
        label,
        &[pass::color(target.color, color)],
        Some(pass::depth(target.depth, depth)),
        None,
    )
}
