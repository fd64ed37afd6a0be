//! The GPU side of section 2.2: per refractor, the rectangles standing in for the nearby
//! objects ([`crate::nearby::Rect`]), their textures rendered every frame by a parallel
//! projection (colour + depth, one layer of two texture arrays per rectangle), and the
//! `@group(3)` that `shaders/nearby.wgsl` reads.

use crate::nearby::Rect;
use glam::{Mat4, Vec3};
use gpu::wgpu;
use gpu::{Context, Uniform, bind};
use scene::{Frame, GpuScene, Object, ObjectFilter, RasterTarget};

/// Colour format of the impostor textures (the shared raster pass and the refractor's
/// pipeline both draw into it).
pub const COLOR_FORMAT: wgpu::TextureFormat = gpu::HDR_FORMAT;
/// Most rectangles per refractor; farther objects stay in the environment map.
pub const MAX_RECTS: usize = 32;

/// The WGSL `Rect`.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct RectGpu {
    centre: [f32; 4],
    axis_u: [f32; 4],
    axis_v: [f32; 4],
    direction: [f32; 4],
    origin: [f32; 4],
}

impl RectGpu {
    /// `rect` at texture array layer `layer`.
    pub fn new(rect: &Rect, layer: u32) -> Self {
        Self {
            centre: rect.centre.extend(rect.half_u).to_array(),
            axis_u: rect.axis_u.extend(rect.half_v).to_array(),
            axis_v: rect.axis_v.extend(rect.near).to_array(),
            direction: rect.direction.extend(rect.far).to_array(),
            origin: rect.origin.extend(layer as f32).to_array(),
        }
    }
}

/// The WGSL `NearbyParams`.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct NearbyParamsGpu {
    /// Rectangles in the table.
    pub count: u32,
    /// 1: figures 16-17's corrected lookup.
    pub corrected: u32,
    /// Seeds of figure 17.
    pub seeds: u32,
    /// Corrections of figure 16.
    pub iterations: u32,
    /// Depth tolerance of the corrections (m).
    pub tolerance: f32,
    _pad: [f32; 3],
}

impl NearbyParamsGpu {
    /// The parameters of a table of `count` rectangles.
    pub fn new(count: u32, corrected: bool, seeds: u32, iterations: u32, tolerance: f32) -> Self {
        Self {
            count,
            corrected: u32::from(corrected),
            seeds,
            iterations,
            tolerance,
            _pad: [0.0; 3],
        }
    }
}

/// How an object becomes a rectangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// A planar rectangle (a `mesh::quad`): corner and edges in object space.
    Planar {
        /// First vertex.
        corner: Vec3,
        /// Edge to the second vertex.
        u: Vec3,
        /// Edge to the fourth vertex.
        v: Vec3,
    },
    /// The paper's square perpendicular to the refractor-to-object direction.
    Square,
}

/// The rectangle shape of `object`: planar when its mesh is one rectangle (four vertices
/// `c, c + u, c + u + v, c + v` with `u` perpendicular to `v`), a square otherwise.
pub fn shape_of(object: &Object) -> Shape {
    let p = &object.mesh.positions;
    if p.len() == 4 && object.morph.is_none() {
        let (u, v) = (p[1] - p[0], p[3] - p[0]);
        let scale = u.length().max(v.length()).max(1e-6);
        let closes = (p[0] + u + v - p[2]).length() < 1e-4 * scale;
        let square_corner = u.dot(v).abs() < 1e-4 * u.length() * v.length();
        if closes && square_corner && u.cross(v).length() > 0.0 {
            return Shape::Planar { corner: p[0], u, v };
        }
    }
    Shape::Square
}

/// One nearby object of a refractor.
#[derive(Clone, Copy, Debug)]
pub struct Member {
    /// Scene object index.
    pub object: usize,
    /// Its rectangle's shape.
    pub shape: Shape,
}

impl Member {
    /// The object's rectangle at `time`, seen from the refractor's centre `from`.
    pub fn rect(&self, object: &Object, time: f32, from: Vec3) -> Rect {
        let world = object.world_at(time);
        match self.shape {
            Shape::Planar { corner, u, v } => Rect::planar(
                world.transform_point3(corner),
                world.transform_vector3(u),
                world.transform_vector3(v),
                from,
            ),
            Shape::Square => Rect::square(
                from,
                object.center_at(time),
                object.bounding_radius_at(time),
            ),
        }
    }
}

/// The nearby objects of refractor `refractor` at time 0: every other object that is a
/// planar rectangle, or whose bounding sphere leaves out the refractor's centre (a room
/// around it stays in the environment map), nearest first, at most [`MAX_RECTS`].
pub fn members(scene: &scene::Scene, refractor: usize) -> Vec<Member> {
    let from = scene.objects[refractor].center_at(0.0);
    let mut members: Vec<(f32, Member)> = scene
        .objects
        .iter()
        .enumerate()
        .filter(|&(i, _)| i != refractor)
        .filter_map(|(i, o)| {
            let shape = shape_of(o);
            let centre = o.center_at(0.0);
            let outside = centre.distance(from) > o.bounding_radius_at(0.0);
            (matches!(shape, Shape::Planar { .. }) || outside)
                .then_some((centre.distance(from), Member { object: i, shape }))
        })
        .collect();
    members.sort_by(|a, b| a.0.total_cmp(&b.0));
    members
        .into_iter()
        .take(MAX_RECTS)
        .map(|(_, m)| m)
        .collect()
}

/// The parallel projection of a rectangle's texture (figure 13's `glOrtho` along the
/// projection direction, up = the rectangle's v axis), depth in [0, 1] from `near` to `far`.
pub fn projection(rect: &Rect) -> Mat4 {
    let view = glam::camera::rh::view::look_to_mat4(rect.origin, rect.direction, rect.axis_v);
    let proj = glam::camera::rh::proj::directx::orthographic(
        -rect.half_u,
        rect.half_u,
        -rect.half_v,
        rect.half_v,
        rect.near,
        rect.far,
    );
    proj * view
}

/// A refractor's rectangles: its members, their layers and the `@group(3)` reading them.
pub struct RefractorRects {
    /// The refractor (scene object index).
    pub refractor: usize,
    /// Its nearby objects, layer `first_layer + i` each.
    pub members: Vec<Member>,
    /// The first texture array layer of its rectangles.
    pub first_layer: u32,
    pub(crate) rects: wgpu::Buffer,
    /// Kept alive for `group`, which binds it.
    _params: Uniform<NearbyParamsGpu>,
    /// `@group(3)` of nearby.wgsl.
    pub group: wgpu::BindGroup,
    /// The rectangles as last placed (for tests and the caustic mapping).
    pub placed: Vec<Rect>,
}

/// Every refractor's rectangles and the two texture arrays.
pub struct Rectangles {
    /// Side of each impostor texture.
    pub resolution: u32,
    /// The refractors' rectangle tables.
    pub refractors: Vec<RefractorRects>,
    /// Impostor colours, one layer per rectangle.
    pub color: wgpu::Texture,
    /// Impostor depths (normalized, 1 where empty), one layer per rectangle.
    pub depth: wgpu::Texture,
    color_layers: Vec<wgpu::TextureView>,
    depth_layers: Vec<wgpu::TextureView>,
}

/// `@group(3)` of nearby.wgsl.
pub fn group_layout(ctx: &Context) -> wgpu::BindGroupLayout {
    bind::layout(
        ctx,
        "nearby rectangles",
        wgpu::ShaderStages::FRAGMENT,
        &[
            bind::storage(true),                                       // rects
            bind::uniform(),                                           // nearby
            bind::texture(wgpu::TextureViewDimension::D2Array, false), // impostor_color
            bind::depth_texture(wgpu::TextureViewDimension::D2Array),  // impostor_depth
        ],
    )
}

impl Rectangles {
    /// The rectangles of each refractor in `refractors`, textures of `resolution` texels,
    /// looked up as `params` says (its count is set per refractor).
    pub fn new(
        ctx: &Context,
        scene: &scene::Scene,
        refractors: &[usize],
        resolution: u32,
        params: NearbyParamsGpu,
    ) -> Self {
        let layout = group_layout(ctx);
        let all: Vec<(usize, Vec<Member>)> =
            refractors.iter().map(|&r| (r, members(scene, r))).collect();
        let layers = all.iter().map(|(_, m)| m.len()).sum::<usize>().max(1) as u32;
        let color = gpu::render_texture(
            ctx,
            "impostor colours",
            (resolution, resolution, layers),
            COLOR_FORMAT,
            wgpu::TextureUsages::COPY_SRC,
        );
        let depth = gpu::depth_texture(ctx, resolution, resolution, layers, "impostor depths");
        let color_layers = (0..layers).map(|l| gpu::layer_view(&color, l)).collect();
        let depth_layers = (0..layers).map(|l| gpu::layer_view(&depth, l)).collect();
        let array = |t: &wgpu::Texture| {
            t.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                ..Default::default()
            })
        };
        let (color_array, depth_array) = (array(&color), array(&depth));
        let mut first_layer = 0;
        let mut tables = Vec::new();
        for (refractor, members) in all {
            let count = members.len();
            let rects = ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("nearby rectangles"),
                size: (count.max(1) * std::mem::size_of::<RectGpu>()) as u64,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let params = Uniform::new(
                ctx,
                "nearby params",
                &NearbyParamsGpu {
                    count: count as u32,
                    ..params
                },
            );
            let group = bind::group(
                ctx,
                "nearby rectangles",
                &layout,
                &[
                    rects.as_entire_binding(),
                    params.binding(),
                    bind::view(&color_array),
                    bind::view(&depth_array),
                ],
            );
            tables.push(RefractorRects {
                refractor,
                members,
                first_layer,
                rects,
                _params: params,
                group,
                placed: Vec::new(),
            });
            first_layer += count as u32;
        }
        Self {
            resolution,
            refractors: tables,
            color,
            depth,
            color_layers,
            depth_layers,
        }
    }

    /// Every object that some refractor sees as a rectangle (left out of the environment maps).
    pub fn objects(&self) -> Vec<usize> {
        let mut all: Vec<usize> = self
            .refractors
            .iter()
            .flat_map(|r| r.members.iter().map(|m| m.object))
            .collect();
        all.sort_unstable();
        all.dedup();
        all
    }

    /// Places every rectangle at the scene's time and uploads the tables.
    pub fn place(&mut self, ctx: &Context, scene: &GpuScene) {
        let time = scene.time();
        for table in &mut self.refractors {
            let from = scene.scene.objects[table.refractor].center_at(time);
            table.placed = table
                .members
                .iter()
                .map(|m| m.rect(&scene.scene.objects[m.object], time, from))
                .collect();
            let gpu: Vec<RectGpu> = table
                .placed
                .iter()
                .enumerate()
                .map(|(i, r)| RectGpu::new(r, table.first_layer + i as u32))
                .collect();
            if !gpu.is_empty() {
                ctx.queue
                    .write_buffer(&table.rects, 0, bytemuck::cast_slice(&gpu));
            }
        }
    }

    /// Renders every rectangle's texture: diffuse objects by the shared raster pass; a
    /// specular object by `draw_specular` (the recursive variant's own shading), or as the
    /// raster pass's plain grey when that is `None`.
    pub fn render(
        &self,
        frame: &mut Frame,
        scene: &GpuScene,
        mut draw_specular: Option<&mut dyn FnMut(&mut Frame, usize, Mat4, Vec3, RasterTarget)>,
    ) {
        for table in &self.refractors {
            // Every texture is seen from the refractor: the raster pass turns surfaces and the
            // recursive shading reflects toward its centre.
            let from = scene.scene.objects[table.refractor].center_at(scene.time());
            for (i, (member, rect)) in table.members.iter().zip(&table.placed).enumerate() {
                let layer = (table.first_layer + i as u32) as usize;
                let target = RasterTarget {
                    color: &self.color_layers[layer],
                    depth: &self.depth_layers[layer],
                    format: COLOR_FORMAT,
                    clear: true,
                };
                let view_proj = projection(rect);
                let specular = scene.scene.objects[member.object].material.is_specular();
                match (&mut draw_specular, specular) {
                    (Some(draw), true) => {
                        // Clear the layer with an empty raster draw, then the object's shading.
                        scene.raster(
                            frame,
                            &target,
                            view_proj,
                            from,
                            &ObjectFilter::Only(vec![]),
                            false,
                        );
                        draw(
                            frame,
                            member.object,
                            view_proj,
                            from,
                            RasterTarget {
                                clear: false,
                                ..target
                            },
                        );
                    }
                    _ => scene.raster(
                        frame,
                        &target,
                        view_proj,
                        from,
                        &ObjectFilter::Only(vec![member.object]),
                        true,
                    ),
                }
            }
        }
    }
}
