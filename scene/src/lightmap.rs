//! Light-map charts of the caustic receivers (paper section 5, "light maps").
//!
//! The paper splats photon hits into the *light maps* of the surfaces they land on, addressed
//! by a texture id and `(u, v)` read from a *uvmap*. Our scenes carry no light-map
//! parameterisation, so one is made here: every diffuse object is cut by the signed dominant
//! axis of its triangles' normals (in object space) into at most six *charts*, each a
//! parallel projection onto the two other axes. A chart is injective wherever no two of its
//! triangles overlap along its axis — true for planes, boxes and the rooms of our scenes, not
//! for general concave meshes (a known limit, see README.md). The charts are packed into one
//! square atlas of equal cells; a chart keeps its aspect ratio (one texel size per chart) and
//! a one-texel gutter inside its cell, so bilinear lookups never read a neighbour.
//!
//! The GPU side is `shaders/chart.wgsl` ([`CHART_WGSL`]: `chart_uv`, same axis rule, same
//! mapping) and `shaders/receiver.wgsl` ([`RECEIVER_WGSL`]: object-space addressing, a
//! texel's area on the surface, the power read back). [`QuadSplatter`] adds photons to the atlas as small Gaussian quads (the paper's
//! light-map splatting), reading a photon map of light-map addresses and powers; it lives
//! here, beside the charts, so that every technique that gathers photons into light maps
//! (caustics of distance impostors, screen-space photons) shares one splat.

use crate::{Frame, Material, Scene};
use glam::{Mat4, Vec2, Vec3};
use gpu::pass::{self, Load};
use gpu::wgpu;
use gpu::{Context, bind};

/// `struct Chart` and `chart_uv` in WGSL: the module `scene::chart` ([`CHART`]; no bindings).
pub const CHART_WGSL: &str = include_str!("shaders/chart.wgsl");
/// [`CHART_WGSL`] as a module (always available to [`crate::shader`]).
pub static CHART: gpu::wgsl::Module =
    gpu::wgsl::Module::new(CHART_WGSL, "scene/src/shaders/chart.wgsl", &[]);
/// `world_to_local`, `normal_to_local`, `texel_area` and `light_map_power` in WGSL: a
/// receiver's light-map texel area and the power read back from an atlas, the module
/// `scene::receiver` ([`RECEIVER`]; imports `scene::shading` and `scene::chart`; no bindings of
/// its own: the light map is passed in).
pub const RECEIVER_WGSL: &str = include_str!("shaders/receiver.wgsl");
/// [`RECEIVER_WGSL`] as a module (always available to [`crate::shader`]).
pub static RECEIVER: gpu::wgsl::Module = gpu::wgsl::Module::new(
    RECEIVER_WGSL,
    "scene/src/shaders/receiver.wgsl",
    &[&crate::SHADING, &CHART],
);
const SPLAT_QUADS_WGSL: &str = include_str!("shaders/splat_quads.wgsl");
/// `footprint_covariance` and `footprint_cut2` in WGSL, the twin of [`Footprint`]: the module
/// `scene::footprint` ([`FOOTPRINT`]; no bindings), which splat_quads.wgsl and screen-photons'
/// splats import.
pub const FOOTPRINT_WGSL: &str = include_str!("shaders/footprint.wgsl");
/// [`FOOTPRINT_WGSL`] as a module (always available to [`crate::shader`]).
pub static FOOTPRINT: gpu::wgsl::Module =
    gpu::wgsl::Module::new(FOOTPRINT_WGSL, "scene/src/shaders/footprint.wgsl", &[]);

/// No chart for this (object, axis): `chart_of` entry.
pub const NO_CHART: i32 = -1;

/// One chart: the triangles of `object` whose normal's dominant component is `axis` (0..6:
/// +x, -x, +y, -y, +z, -z), projected onto the two other object-space axes `a`, `b`.
#[derive(Clone, Debug, PartialEq)]
pub struct Chart {
    pub object: usize,
    pub axis: u32,
    /// Object-space lower corner of the projected triangles on axes (a, b).
    pub min: Vec2,
    /// Object-space extent on (a, b).
    pub extent: Vec2,
    /// Atlas rectangle the chart may write and read, in atlas uv (u0, v0, u1, v1): the cell
    /// less a one-texel gutter.
    pub rect: [f32; 4],
}

impl Chart {
    /// The two object-space axes of the projection.
    pub fn plane_axes(&self) -> (usize, usize) {
        projection_axes(self.axis)
    }

    /// Object-space length mapped onto the rectangle's longer edge.
    pub fn side(&self) -> f32 {
        self.extent.max_element().max(1e-9)
    }

    /// Object-space edge of one texel (texels are square: the chart keeps its aspect).
    pub fn texel_size(&self, atlas_size: u32) -> f32 {
        let [u0, v0, u1, v1] = self.rect;
        self.side() / ((u1 - u0).max(v1 - v0) * atlas_size as f32)
    }

    /// Atlas uv of an object-space point of this chart (clamped into the rectangle). Same
    /// formula as `chart_uv` in lightmap.wgsl.
    pub fn uv(&self, local: Vec3) -> Vec2 {
        let (a, b) = self.plane_axes();
        let side = self.extent.max_element().max(1e-9);
        let s = ((Vec2::new(local[a], local[b]) - self.min) / side).clamp(Vec2::ZERO, Vec2::ONE);
        let [u0, v0, u1, v1] = self.rect;
        Vec2::new(u0 + s.x * (u1 - u0), v0 + s.y * (v1 - v0))
    }
}

/// The signed dominant axis of `n`: 0 +x, 1 -x, 2 +y, 3 -y, 4 +z, 5 -z (ties go to the lower
/// axis, as in lightmap.wgsl).
pub fn signed_axis(n: Vec3) -> u32 {
    let a = n.abs();
    let i = if a.x >= a.y && a.x >= a.z {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    };
    2 * i + u32::from(n[i as usize] < 0.0)
}

fn projection_axes(axis: u32) -> (usize, usize) {
    match axis / 2 {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    }
}

/// Every receiver's charts and the table `(object, axis) -> chart`.
#[derive(Clone, Debug)]
pub struct ChartAtlas {
    /// Atlas side in texels.
    pub size: u32,
    pub charts: Vec<Chart>,
    /// `chart_of[6 * object + axis]`: index into `charts`, or [`NO_CHART`].
    pub chart_of: Vec<i32>,
}

impl ChartAtlas {
    /// Charts for every diffuse object of `scene` in a `size` x `size` atlas.
    pub fn new(scene: &Scene, size: u32) -> Self {
        Self::of_objects(scene, size, |_| true)
    }

    /// Charts for the diffuse objects of `scene` that `receives` accepts (by index): a
    /// technique whose photons land on a few known receivers (the chessboard) gives them the
    /// whole atlas. Charts are precomputed from the base meshes: a deforming receiver
    /// ([`crate::Object::is_deforming`]) invalidates its charts (they do not follow its
    /// [`crate::Morph`]).
    pub fn of_objects(scene: &Scene, size: u32, receives: impl Fn(usize) -> bool) -> Self {
        let mut charts = Vec::new();
        let mut chart_of = vec![NO_CHART; 6 * scene.objects.len()];
        for (object, o) in scene.objects.iter().enumerate() {
            if !matches!(o.material, Material::Diffuse { .. }) || !receives(object) {
                continue;
            }
            let mut bounds: [Option<(Vec2, Vec2)>; 6] = [None; 6];
            for tri in o.mesh.indices.chunks_exact(3) {
                let p = [0, 1, 2].map(|k| o.mesh.positions[tri[k] as usize]);
                let ng = (p[1] - p[0]).cross(p[2] - p[0]);
                if ng.length_squared() < 1e-20 {
                    continue;
                }
                // The authored normals say which side is the front; the geometric normal says
                // which axis the triangle faces (same rule as the shader).
                let shading: Vec3 = tri.iter().map(|&i| o.mesh.normals[i as usize]).sum();
                let facing = if ng.dot(shading) < 0.0 { -ng } else { ng };
                let axis = signed_axis(facing);
                let (a, b) = projection_axes(axis);
                for q in p {
                    let q2 = Vec2::new(q[a], q[b]);
                    let entry = bounds[axis as usize].get_or_insert((q2, q2));
                    entry.0 = entry.0.min(q2);
                    entry.1 = entry.1.max(q2);
                }
            }
            for (axis, b) in bounds.iter().enumerate() {
                if let Some((lo, hi)) = b {
                    chart_of[6 * object + axis] = charts.len() as i32;
                    charts.push(Chart {
                        object,
                        axis: axis as u32,
                        min: *lo,
                        extent: *hi - *lo,
                        rect: [0.0; 4],
                    });
                }
            }
        }
        // Equal square cells in a k x k grid; a chart uses the square of its larger extent.
        let k = (charts.len() as f32).sqrt().ceil().max(1.0) as u32;
        let cell = size / k;
        for (i, c) in charts.iter_mut().enumerate() {
            let (ci, cj) = (i as u32 % k, i as u32 / k);
            let gutter = 1.0;
            let (x0, y0) = ((ci * cell) as f32 + gutter, (cj * cell) as f32 + gutter);
            let side = (cell as f32 - 2.0 * gutter).max(1.0);
            let n = c.extent / c.extent.max_element().max(1e-9);
            let s = size as f32;
            c.rect = [x0 / s, y0 / s, (x0 + side * n.x) / s, (y0 + side * n.y) / s];
        }
        Self {
            size,
            charts,
            chart_of,
        }
    }

    /// Chart of `object`'s triangles facing `axis`, if any.
    pub fn chart(&self, object: usize, axis: u32) -> Option<&Chart> {
        let i = *self.chart_of.get(6 * object + axis as usize)?;
        (i >= 0).then(|| &self.charts[i as usize])
    }

    /// The `Chart` array of lightmap.wgsl.
    pub fn gpu_charts(&self) -> Vec<ChartGpu> {
        let mut v: Vec<ChartGpu> = self
            .charts
            .iter()
            .map(|c| {
                let (a, b) = c.plane_axes();
                ChartGpu {
                    rect: c.rect,
                    bounds: [c.min.x, c.min.y, c.side(), c.texel_size(self.size)],
                    axes: [a as u32, b as u32, c.axis, c.object as u32],
                }
            })
            .collect();
        // Storage buffers may not be empty.
        if v.is_empty() {
            v.push(ChartGpu::zeroed());
        }
        v
    }
}

/// `struct Chart` of lightmap.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ChartGpu {
    pub rect: [f32; 4],
    /// min a, min b, side (the larger extent), object-space texel edge.
    pub bounds: [f32; 4],
    /// axis a, axis b, signed axis, object.
    pub axes: [u32; 4],
}

impl ChartGpu {
    fn zeroed() -> Self {
        bytemuck::Zeroable::zeroed()
    }
}

/// The uniform block `SplatQuadParams` of splat_quads.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct SplatQuadGpu {
    atlas: [f32; 4],
    size: u32,
    tile: u32,
    _pad: [u32; 2],
}

/// A lattice cell's width in standard deviations of its photon's footprint
/// (`FOOTPRINT_CELL_SIGMA` in splat_quads.wgsl).
pub const FOOTPRINT_CELL_SIGMA: f32 = 0.6;
/// The largest half extent of a footprint's quad in texels (`MAX_FOOTPRINT`).
pub const MAX_FOOTPRINT: f32 = 64.0;
/// Squared Mahalanobis distances at which the fixed quad (its disc R = 2 sigma0) and a
/// footprint much larger than it (three standard deviations) are cut (`FIXED_CUT2`,
/// `FOOTPRINT_CUT2`).
const FIXED_CUT2: f32 = 4.0;
const FOOTPRINT_CUT2: f32 = 9.0;

/// A photon's Gaussian on the atlas, in texels: the twin of `footprint_covariance` and of the
/// weights `splat_quad_fs` adds (splat_quads.wgsl, which derives it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Footprint {
    /// Covariance (xx, xy, yy).
    pub covariance: [f32; 3],
    /// Squared Mahalanobis distance of the cut.
    pub cut2: f32,
}

impl Footprint {
    /// The paper's fixed quad of radius `radius`: sigma = R / 2, cut at R.
    pub fn fixed(radius: f32) -> Self {
        Self::new(radius, Vec2::ZERO, Vec2::ZERO, FIXED_CUT2)
    }

    /// The fixed Gaussian widened by the photon's lattice cell with edges `ex`, `ey` on the
    /// atlas (zero where a neighbour is missing), cut between the fixed quad's two standard
    /// deviations (no cell) and three (a cell much larger than the quad): `footprint_cut2`.
    pub fn of_cell(radius: f32, ex: Vec2, ey: Vec2) -> Self {
        let s0 = 0.25 * radius * radius;
        let cell = FOOTPRINT_CELL_SIGMA.powi(2) * ex.length_squared().max(ey.length_squared());
        let cut2 = FIXED_CUT2 + (FOOTPRINT_CUT2 - FIXED_CUT2) * cell / (s0 + cell);
        Self::new(radius, ex, ey, cut2)
    }

    /// Covariance `sigma0^2 I + c^2 (ex ex^T + ey ey^T)`, shrunk so that the quad's half
    /// extents stay within [`MAX_FOOTPRINT`].
    fn new(radius: f32, ex: Vec2, ey: Vec2, cut2: f32) -> Self {
        let s0 = 0.25 * radius * radius;
        let c2 = FOOTPRINT_CELL_SIGMA * FOOTPRINT_CELL_SIGMA;
        let mut cov = [
            s0 + c2 * (ex.x * ex.x + ey.x * ey.x),
            c2 * (ex.x * ex.y + ey.x * ey.y),
            s0 + c2 * (ex.y * ex.y + ey.y * ey.y),
        ];
        let half_extent = (cut2 * cov[0].max(cov[2])).sqrt();
        if half_extent > MAX_FOOTPRINT {
            let shrink = (MAX_FOOTPRINT / half_extent).powi(2);
            cov = cov.map(|c| c * shrink);
        }
        Self {
            covariance: cov,
            cut2,
        }
    }

    /// Half extents of the photon's quad (texels).
    pub fn half_extents(&self) -> Vec2 {
        Vec2::new(self.covariance[0], self.covariance[2]).map(|v| (self.cut2 * v).sqrt())
    }

    /// The weight the photon adds at offset `d` (texels) from its landing point: 0 beyond the
    /// cut; the weights integrate to 1 over the plane.
    pub fn weight(&self, d: Vec2) -> f32 {
        let [xx, xy, yy] = self.covariance;
        let det = xx * yy - xy * xy;
        let q = (yy * d.x * d.x - 2.0 * xy * d.x * d.y + xx * d.y * d.y) / det;
        if q > self.cut2 {
            return 0.0;
        }
        let norm = 2.0 * std::f32::consts::PI * det.sqrt() * (1.0 - (-0.5 * self.cut2).exp());
        (-0.5 * q).exp() / norm
    }
}

/// The paper's light-map splatting: one quad per photon-map texel, centred at the photon's
/// light-map address, weighted by a Gaussian and added into the atlas (the vertex stage
/// reads the photon map: the paper's vertex texture fetch).
///
/// The photon map is two `size` x `size` textures: the *address* (atlas u, v, chart index,
/// w = 1 where a photon landed) and the *power* (rgb).
pub struct QuadSplatter {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    /// One bind group per photon map the caller splats (its `slot`), made once.
    groups: gpu::bind::UniformGroups<SplatQuadGpu>,
}

impl QuadSplatter {
    /// A splatter that adds into an atlas of `format` (needs additive blending of it:
    /// `FLOAT32_BLENDABLE` for 32-bit float atlases).
    pub fn new(ctx: &Context, format: wgpu::TextureFormat) -> Self {
        let vert = wgpu::ShaderStages::VERTEX;
        let photons = bind::texture_2d_unfilterable();
        let layout = bind::layout_with_stages(
            ctx,
            "light-map splat quads",
            &[
                (vert, photons),
                (vert, photons),
                (vert, bind::storage(true)),
                (vert | wgpu::ShaderStages::FRAGMENT, bind::uniform()),
            ],
        );
        let module = crate::shader(ctx, "light-map splat quads", SPLAT_QUADS_WGSL);
        // Adds rgb; alpha is unused.
        let add = wgpu::BlendState {
            color: wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::One,
                dst_factor: wgpu::BlendFactor::One,
                operation: wgpu::BlendOperation::Add,
            },
            alpha: wgpu::BlendComponent::REPLACE,
        };
        let pipeline_layout = ctx
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("light-map splat quads"),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
        let pipeline = ctx
            .device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("light-map splat quads"),
                layout: Some(&pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("splat_quad_vs"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some("splat_quad_fs"),
                    compilation_options: Default::default(),
                    targets: &[pass::color_target(format, Some(add))],
                }),
                primitive: Default::default(),
                depth_stencil: None,
                multisample: Default::default(),
                multiview_mask: None,
                cache: ctx.pipeline_cache(),
            });
        Self {
            pipeline,
            layout,
            groups: gpu::bind::UniformGroups::new("splat quad params"),
        }
    }

    /// Adds every photon of the `size` x `size` photon map (`address`, `power`) into `atlas`
    /// (side `atlas_side` texels) as a Gaussian quad, clipped to the photon's own chart
    /// (`charts` holds the [`ChartGpu`]s): of radius `radius` texels, or, with `tile` > 0, that
    /// Gaussian widened to the photon's [`Footprint`], its lattice cell measured among the
    /// neighbours in its own `tile` x `tile` block of the map (one lattice per caster and
    /// light). `slot` names the photon map: its bind group is made the first time and kept (the
    /// same slot must always come with the same `address`, `power` and `charts`).
    #[allow(clippy::too_many_arguments)]
    pub fn splat(
        &self,
        frame: &mut Frame,
        slot: usize,
        atlas: &wgpu::TextureView,
        atlas_side: u32,
        address: &wgpu::TextureView,
        power: &wgpu::TextureView,
        charts: &wgpu::Buffer,
        size: u32,
        tile: u32,
        radius: f32,
    ) {
        let ctx = frame.gpu;
        let params = SplatQuadGpu {
            atlas: [atlas_side as f32, radius, 0.0, 0.0],
            size,
            tile,
            _pad: [0; 2],
        };
        let group = self.groups.get(ctx, slot, &params, |uniform| {
            bind::group(
                ctx,
                "light-map splat quads",
                &self.layout,
                &[
                    bind::view(address),
                    bind::view(power),
                    charts.as_entire_binding(),
                    uniform.binding(),
                ],
            )
        });
        let mut pass = gpu::pass::begin(
            frame.encoder,
            "light-map splat quads",
            &[pass::color(atlas, Load::Keep)],
            None,
            None,
        );
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.draw(0..6, 0..size * size);
    }
}

/// A point light's square perspective view holding a sphere: what a photon pass draws from
/// the light (refractor-maps' photon-map tiles, screen-photons' transfer map). The sphere is
/// grown 5% so that its silhouette stays inside; near and far planes bracket it (from half
/// the distance to its front to its back plus a radius).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightView {
    /// World to clip, depth in [0, 1].
    pub view_proj: Mat4,
    /// Unit axis of the view, from the light to the sphere's centre.
    pub axis: Vec3,
    /// Area of one pixel on the image plane at unit distance, `(2 tan(fov / 2) / pixels)^2`:
    /// a pixel's solid angle is this times `cos^3` of its angle off the axis.
    pub pixel_area: f32,
    /// Distance from the light to the sphere's centre.
    pub distance: f32,
}

impl LightView {
    /// The view from `light` of the sphere (`centre`, `radius`), `pixels` on a side. The light
    /// must lie outside the sphere (else the view is the 5% grown sphere's tangent cone from a
    /// point just outside it).
    pub fn of_sphere(light: Vec3, centre: Vec3, radius: f32, pixels: u32) -> Self {
        let radius = radius * 1.05;
        let to = centre - light;
        let distance = to.length().max(radius * 1.001);
        let axis = to / to.length().max(1e-9);
        let half = (radius / distance).clamp(-1.0, 1.0).asin();
        let up = if axis.y.abs() > 0.9 { Vec3::X } else { Vec3::Y };
        let view = glam::camera::rh::view::look_at_mat4(light, centre, up);
        let proj = glam::camera::rh::proj::directx::perspective(
            2.0 * half,
            1.0,
            ((distance - radius) * 0.5).max(1e-3),
            distance + 2.0 * radius,
        );
        Self {
            view_proj: proj * view,
            axis,
            pixel_area: (2.0 * half.tan() / pixels as f32).powi(2),
            distance,
        }
    }

    /// The width of one pixel at the sphere's centre (m): the spacing of photons there.
    pub fn spacing(&self) -> f32 {
        self.pixel_area.sqrt() * self.distance
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn atlas(name: &str) -> (Scene, ChartAtlas) {
        let scene = crate::load(name).unwrap();
        let atlas = ChartAtlas::new(&scene, 1024);
        (scene, atlas)
    }

    /// Sum at `at` of footprints of photons landing on the lattice `origin + i ex + j ey`.
    fn lattice_sum(ex: Vec2, ey: Vec2, at: Vec2, footprint: &Footprint) -> f32 {
        let mut total = 0.0;
        for j in -12..=12 {
            for i in -12..=12 {
                total += footprint.weight(at - (ex * i as f32 + ey * j as f32));
            }
        }
        total
    }

    /// Ratio of the largest to the smallest lattice sum over one cell.
    fn ripple(ex: Vec2, ey: Vec2, footprint: &Footprint) -> f32 {
        let sums: Vec<f32> = (0..8)
            .flat_map(|b| (0..8).map(move |a| (a as f32 / 8.0, b as f32 / 8.0)))
            .map(|(a, b)| lattice_sum(ex, ey, ex * a + ey * b, footprint))
            .collect();
        let (lo, hi) = sums
            .iter()
            .fold((f32::MAX, 0.0f32), |(lo, hi), &v| (lo.min(v), hi.max(v)));
        hi / lo
    }

    #[test]
    fn the_fixed_footprint_is_the_papers_quad() {
        // sigma = R / 2, cut at R, normalised over the disc (the splat before footprints).
        let r = 3.0f32;
        let f = Footprint::fixed(r);
        let k = 1.0 / (2.0 * (0.5 * r).powi(2));
        let norm = 1.0 / (std::f32::consts::PI / k * (1.0 - (-r * r * k).exp()));
        for d in [Vec2::ZERO, Vec2::new(1.0, 0.5), Vec2::new(0.0, 2.9)] {
            let expected = (-d.length_squared() * k).exp() * norm;
            assert!((f.weight(d) - expected).abs() < 1e-6 * expected.max(1.0));
        }
        assert_eq!(f.weight(Vec2::new(3.01, 0.0)), 0.0);
        assert_eq!(f.half_extents(), Vec2::splat(r));
    }

    #[test]
    fn footprints_integrate_to_one() {
        for f in [
            Footprint::fixed(3.0),
            Footprint::of_cell(3.0, Vec2::new(9.0, 1.0), Vec2::new(-2.0, 4.0)),
            Footprint::of_cell(3.0, Vec2::new(500.0, 0.0), Vec2::new(0.0, 2.0)),
        ] {
            let h = f.half_extents();
            let step = 0.05;
            let (nx, ny) = ((h.x / step) as i32 + 1, (h.y / step) as i32 + 1);
            let mut sum = 0.0f64;
            for j in -ny..=ny {
                for i in -nx..=nx {
                    sum += f.weight(Vec2::new(i as f32, j as f32) * step) as f64;
                }
            }
            let integral = sum * (step * step) as f64;
            assert!((integral - 1.0).abs() < 0.01, "{f:?}: {integral}");
        }
    }

    #[test]
    fn a_stretched_lattice_of_footprints_sums_to_nearly_flat() {
        // Photons under a glass sphere: cells stretched radially 12 texels by 3, sheared.
        let (ex, ey) = (Vec2::new(12.0, 2.0), Vec2::new(-1.0, 3.0));
        let cell = Footprint::of_cell(3.0, ex, ey);
        let flat = ripple(ex, ey, &cell);
        assert!(flat < 1.03, "footprints ripple by {flat}");
        // The light is one photon per cell area.
        let level = lattice_sum(ex, ey, Vec2::ZERO, &cell) * ex.perp_dot(ey).abs();
        assert!((level - 1.0).abs() < 0.03, "level {level}");
        // The fixed quad, narrower than the cell, draws the lattice's rows: the rings.
        let fixed = ripple(ex, ey, &Footprint::fixed(3.0));
        assert!(fixed > 10.0, "fixed quads ripple by only {fixed}");
    }

    #[test]
    fn a_cell_across_a_fold_is_capped() {
        let f = Footprint::of_cell(3.0, Vec2::new(900.0, 0.0), Vec2::new(0.0, 2.0));
        let h = f.half_extents();
        assert!((h.max_element() - MAX_FOOTPRINT).abs() < 1e-3, "{h}");
    }

    #[test]
    fn signed_axis_picks_the_dominant_component() {
        assert_eq!(signed_axis(Vec3::new(0.9, 0.1, -0.2)), 0);
        assert_eq!(signed_axis(Vec3::new(-0.9, 0.1, -0.2)), 1);
        assert_eq!(signed_axis(Vec3::new(0.0, 1.0, 0.0)), 2);
        assert_eq!(signed_axis(Vec3::new(0.1, -1.0, 0.3)), 3);
        assert_eq!(signed_axis(Vec3::new(0.1, 0.2, 0.5)), 4);
        assert_eq!(signed_axis(Vec3::new(0.1, 0.2, -0.5)), 5);
    }

    #[test]
    fn every_diffuse_triangle_lands_inside_its_own_chart() {
        for name in ["cornell-sphere", "cornell-box", "refraction-bunny"] {
            let (scene, atlas) = atlas(name);
            assert!(!atlas.charts.is_empty(), "{name}: no charts");
            for (object, o) in scene.objects.iter().enumerate() {
                let diffuse = matches!(o.material, Material::Diffuse { .. });
                for axis in 0..6 {
                    assert!(
                        diffuse || atlas.chart(object, axis).is_none(),
                        "{name}: chart for a specular object"
                    );
                }
                if !diffuse {
                    continue;
                }
                for tri in o.mesh.indices.chunks_exact(3) {
                    let p = [0, 1, 2].map(|k| o.mesh.positions[tri[k] as usize]);
                    let ng = (p[1] - p[0]).cross(p[2] - p[0]);
                    let shading: Vec3 = tri.iter().map(|&i| o.mesh.normals[i as usize]).sum();
                    let facing = if ng.dot(shading) < 0.0 { -ng } else { ng };
                    let chart = atlas.chart(object, signed_axis(facing)).expect("chart");
                    let [u0, v0, u1, v1] = chart.rect;
                    for q in p {
                        // Unclamped position: inside the rectangle without the clamp's help.
                        let (a, b) = chart.plane_axes();
                        let side = chart.extent.max_element();
                        let s = (Vec2::new(q[a], q[b]) - chart.min) / side;
                        assert!(
                            s.x >= -1e-5 && s.y >= -1e-5 && s.x <= 1.0 + 1e-5 && s.y <= 1.0 + 1e-5
                        );
                        let uv = chart.uv(q);
                        assert!(uv.x >= u0 && uv.x <= u1 && uv.y >= v0 && uv.y <= v1);
                    }
                }
            }
        }
    }

    #[test]
    fn chart_rectangles_are_disjoint_and_keep_a_gutter() {
        for name in ["cornell-sphere", "cornell-box", "city"] {
            let (_, atlas) = atlas(name);
            let texel = 1.0 / atlas.size as f32;
            for (i, a) in atlas.charts.iter().enumerate() {
                let [a0, b0, a1, b1] = a.rect;
                assert!(a0 >= texel * 0.999 && b0 >= texel * 0.999 && a1 <= 1.0 && b1 <= 1.0);
                assert!(a1 > a0 && b1 > b0, "{name}: empty chart {a:?}");
                for b in &atlas.charts[i + 1..] {
                    let [c0, d0, c1, d1] = b.rect;
                    // Separated by at least the two gutters (2 texels) on one axis.
                    let apart = c0 >= a1 + 1.99 * texel
                        || a0 >= c1 + 1.99 * texel
                        || d0 >= b1 + 1.99 * texel
                        || b0 >= d1 + 1.99 * texel;
                    assert!(apart, "{name}: charts overlap: {a:?} {b:?}");
                }
            }
        }
    }

    #[test]
    fn an_atlas_of_one_receiver_gives_it_the_whole_atlas() {
        let scene = crate::load("chess").unwrap();
        let board = scene
            .objects
            .iter()
            .position(|o| o.name == "board")
            .unwrap();
        let atlas = ChartAtlas::of_objects(&scene, 512, |o| o == board);
        // The board is one upward quad: one chart, filling the atlas but its gutter.
        assert_eq!(atlas.charts.len(), 1);
        assert_eq!(atlas.chart(board, 2).map(|c| c.object), Some(board));
        let [u0, v0, u1, v1] = atlas.charts[0].rect;
        let texel = 1.0 / 512.0;
        assert!((u0 - texel).abs() < 1e-6 && (v0 - texel).abs() < 1e-6);
        assert!((u1 - (1.0 - texel)).abs() < 1e-6 && (v1 - (1.0 - texel)).abs() < 1e-6);
        assert!(atlas.chart_of.iter().filter(|&&c| c != NO_CHART).count() == 1);
    }

    #[test]
    fn a_chart_keeps_its_aspect_ratio() {
        let (_, atlas) = atlas("cornell-box");
        for c in &atlas.charts {
            let [u0, v0, u1, v1] = c.rect;
            let texel_a = c.extent.x / (u1 - u0);
            let texel_b = c.extent.y / (v1 - v0);
            if c.extent.min_element() > 1e-3 {
                assert!((texel_a / texel_b - 1.0).abs() < 1e-3, "{c:?}");
            }
        }
    }
}
