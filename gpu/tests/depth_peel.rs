//! Depth peeling of UV-sphere meshes against the analytic spheres.
//!
//! Tolerances: a UV sphere with `SLICES` x `STACKS` quads lies inside the true sphere by at most
//! its sagitta `1 - cos(half the quad diagonal angle)` (about 2.4e-3 for a unit sphere here),
//! so a distance along a view ray may differ by `sagitta / cos(incidence)`; pixels whose ray
//! passes within 0.1 of the silhouette are skipped (the mesh silhouette is inside the
//! sphere's). Where the ray meets a mesh vertex (the image centre here) the distance is exact
//! up to rounding: 1e-4. Normals are the interpolated vertex normals of a unit sphere, which
//! equal the direction of the interpolated surface point: 1e-3 in the dot product.

use std::sync::OnceLock;

use glam::{Mat4, Vec2, Vec3, Vec4};
use gpu::wgpu::util::DeviceExt;
use gpu::{Context, DepthPeeler, GpuError, Vertex, wgpu};

const SLICES: u32 = 64;
const STACKS: u32 = 32;
/// Odd, so that the centre pixel's ray is the camera axis.
const SIZE: u32 = 65;
const FOV_Y_DEGREES: f32 = 50.0;

fn ctx() -> &'static Context {
    static CTX: OnceLock<Context> = OnceLock::new();
    CTX.get_or_init(|| {
        Context::new().unwrap_or_else(|e| panic!("the depth peeling test needs a GPU adapter: {e}"))
    })
}

/// UV sphere with poles on +-Y and outward normals; the vertex at stack STACKS/2, slice 0 is
/// `center + (0, 0, radius)` and slice SLICES/2 is `center - (0, 0, radius)`.
fn uv_sphere(center: Vec3, radius: f32, vertices: &mut Vec<Vertex>, indices: &mut Vec<u32>) {
    let base = vertices.len() as u32;
    for stack in 0..=STACKS {
        let theta = std::f32::consts::PI * stack as f32 / STACKS as f32;
        for slice in 0..=SLICES {
            let phi = std::f32::consts::TAU * slice as f32 / SLICES as f32;
            let n = Vec3::new(
                theta.sin() * phi.sin(),
                theta.cos(),
                theta.sin() * phi.cos(),
            );
            vertices.push(Vertex {
                position: (center + radius * n).to_array(),
                normal: n.to_array(),
                uv: [slice as f32 / SLICES as f32, stack as f32 / STACKS as f32],
            });
        }
    }
    let row = SLICES + 1;
    for stack in 0..STACKS {
        for slice in 0..SLICES {
            let a = base + stack * row + slice;
            let (b, c, d) = (a + 1, a + row, a + row + 1);
            indices.extend_from_slice(&[a, c, b, b, c, d]);
        }
    }
}

/// Largest distance of the mesh inside the sphere, for a unit radius.
fn sagitta() -> f32 {
    let (dt, dp) = (
        std::f32::consts::PI / STACKS as f32,
        std::f32::consts::TAU / SLICES as f32,
    );
    1.0 - (0.5 * (dt * dt + dp * dp).sqrt()).cos()
}

struct Camera {
    eye: Vec3,
    view_proj: Mat4,
}

impl Camera {
    fn on_z_axis(z: f32) -> Self {
        let eye = Vec3::new(0.0, 0.0, z);
        let proj = glam::camera::rh::proj::directx::perspective(
            FOV_Y_DEGREES.to_radians(),
            1.0,
            0.1,
            20.0,
        );
        let view = glam::camera::rh::view::look_at_mat4(eye, Vec3::ZERO, Vec3::Y);
        Self {
            eye,
            view_proj: proj * view,
        }
    }

    /// Unit direction of the ray through the centre of pixel (i, j), row 0 at the top.
    fn ray(&self, i: u32, j: u32) -> Vec3 {
        let ndc = Vec2::new(
            (i as f32 + 0.5) / SIZE as f32 * 2.0 - 1.0,
            1.0 - (j as f32 + 0.5) / SIZE as f32 * 2.0,
        );
        let inv = self.view_proj.inverse();
        let far = inv * Vec4::new(ndc.x, ndc.y, 1.0, 1.0);
        (far.truncate() / far.w - self.eye).normalize()
    }
}

struct Peeled {
    layers: Vec<Vec<[f32; 4]>>,
    depths: Vec<Vec<f32>>,
}

fn peel(spheres: &[(Vec3, f32)], camera: &Camera, layers: u32) -> Peeled {
    let ctx = ctx();
    let (mut vertices, mut indices) = (Vec::new(), Vec::new());
    for &(center, radius) in spheres {
        uv_sphere(center, radius, &mut vertices, &mut indices);
    }
    let vertex_buffer = ctx
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("sphere vertices"),
            contents: bytemuck::cast_slice(&vertices),
            usage: wgpu::BufferUsages::VERTEX,
        });
    let index_buffer = ctx
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("sphere indices"),
            contents: bytemuck::cast_slice(&indices),
            usage: wgpu::BufferUsages::INDEX,
        });
    let peeler = DepthPeeler::new(ctx, SIZE, SIZE, layers).expect("peeler");
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    ctx.validated(|| {
        peeler.peel(
            ctx,
            &mut encoder,
            &vertex_buffer,
            &index_buffer,
            indices.len() as u32,
            camera.view_proj,
            camera.eye,
        )
    })
    .expect("no validation error")
    .expect("peel");
    ctx.queue.submit([encoder.finish()]);
    Peeled {
        layers: (0..layers)
            .map(|l| peeler.read_layer(ctx, l).expect("read layer"))
            .collect(),
        depths: (0..layers)
            .map(|l| peeler.read_depth(ctx, l).expect("read depth"))
            .collect(),
    }
}

fn at(image: &[[f32; 4]], i: u32, j: u32) -> Vec4 {
    Vec4::from_array(image[(j * SIZE + i) as usize])
}

/// Camera on +Z at distance 3 from a unit sphere: layer 0 is the front surface, layer 1 the
/// back surface, layer 2 empty, with outward normals, at every pixel away from the silhouette.
#[test]
fn unit_sphere_peels_into_front_back_and_empty() {
    let camera = Camera::on_z_axis(3.0);
    let peeled = peel(&[(Vec3::ZERO, 1.0)], &camera, 3);
    let (front, back, empty) = (&peeled.layers[0], &peeled.layers[1], &peeled.layers[2]);

    // The centre pixel looks down the axis through mesh vertices at z = +1 and z = -1.
    let c = SIZE / 2;
    let (f, b) = (at(front, c, c), at(back, c, c));
    assert!(
        (f.w - 2.0).abs() < 1e-4,
        "front distance at the centre {} (want 2)",
        f.w
    );
    assert!(
        (b.w - 4.0).abs() < 1e-4,
        "back distance at the centre {} (want 4)",
        b.w
    );
    assert!(
        (f.truncate() - Vec3::Z).length() < 1e-3,
        "front normal {}",
        f.truncate()
    );
    assert!(
        (b.truncate() - Vec3::NEG_Z).length() < 1e-3,
        "back normal {}",
        b.truncate()
    );
    assert_eq!(at(empty, c, c), Vec4::ZERO, "layer 2 at the centre");

    let sag = sagitta();
    let (mut hits, mut misses) = (0, 0);
    for j in 0..SIZE {
        for i in 0..SIZE {
            let d = camera.ray(i, j);
            let t = gpu::prelude::ray_sphere(camera.eye, d, Vec3::ZERO, 1.0);
            let pixel = (j * SIZE + i) as usize;
            assert_eq!(
                at(empty, i, j),
                Vec4::ZERO,
                "layer 2 must be empty at ({i}, {j})"
            );
            assert_eq!(peeled.depths[2][pixel], 1.0, "layer 2 depth at ({i}, {j})");
            // Distance of the ray from the sphere centre, compared with the radius.
            let miss_distance = camera.eye.cross(d).length() - 1.0;
            if miss_distance > 0.0 {
                for layer in [front, back] {
                    assert_eq!(at(layer, i, j), Vec4::ZERO, "({i}, {j}) misses the sphere");
                }
                misses += 1;
                continue;
            }
            if miss_distance > -0.1 {
                continue; // near the silhouette
            }
            hits += 1;
            for (layer, t_exact, outward, name) in
                [(front, t.x, -1.0, "front"), (back, t.y, 1.0, "back")]
            {
                let texel = at(layer, i, j);
                let p_exact = camera.eye + t_exact * d;
                let cos_incidence = p_exact.dot(d).abs();
                let tol = 1.2 * sag / cos_incidence + 1e-4;
                assert!(
                    (texel.w - t_exact).abs() <= tol,
                    "{name} distance at ({i}, {j}): {} vs analytic {t_exact} (tol {tol})",
                    texel.w
                );
                let n = texel.truncate();
                let p = camera.eye + texel.w * d;
                assert!(
                    (n.length() - 1.0).abs() < 1e-4,
                    "{name} normal at ({i}, {j}) not unit: {n}"
                );
                assert!(
                    n.dot(p.normalize()) > 1.0 - 1e-3,
                    "{name} normal at ({i}, {j}) {n} is not radial at {p}"
                );
                assert!(
                    outward * n.dot(d) > 0.0,
                    "{name} normal at ({i}, {j}) {n} does not point outward"
                );
            }
            let (zf, zb) = (peeled.depths[0][pixel], peeled.depths[1][pixel]);
            assert!(
                0.0 < zf && zf < zb && zb < 1.0,
                "depths at ({i}, {j}): front {zf}, back {zb}"
            );
        }
    }
    assert!(
        hits > 1000 && misses > 100,
        "the image should show the sphere and its surroundings ({hits} hits, {misses} misses)"
    );
}

/// Two spheres on the axis (radius 1 at the origin, 0.5 at z = -3) give four surfaces in
/// order at the centre pixel, then an empty layer.
#[test]
fn two_spheres_peel_in_order() {
    let camera = Camera::on_z_axis(3.0);
    let peeled = peel(
        &[(Vec3::ZERO, 1.0), (Vec3::new(0.0, 0.0, -3.0), 0.5)],
        &camera,
        5,
    );
    let c = SIZE / 2;
    let want = [
        (2.0, Vec3::Z),
        (4.0, Vec3::NEG_Z),
        (5.5, Vec3::Z),
        (6.5, Vec3::NEG_Z),
    ];
    for (layer, (distance, normal)) in want.into_iter().enumerate() {
        let texel = at(&peeled.layers[layer], c, c);
        assert!(
            (texel.w - distance).abs() < 1e-4,
            "layer {layer}: distance {} (want {distance})",
            texel.w
        );
        assert!(
            (texel.truncate() - normal).length() < 1e-3,
            "layer {layer}: normal {}",
            texel.truncate()
        );
    }
    assert_eq!(at(&peeled.layers[4], c, c), Vec4::ZERO);
    assert_eq!(peeled.depths[4][(c * SIZE + c) as usize], 1.0);
}

/// Bad input gives an error naming the problem, not a panic.
#[test]
fn bad_input_is_an_error() {
    let ctx = ctx();
    assert!(matches!(
        DepthPeeler::new(ctx, 64, 64, 0),
        Err(GpuError::InvalidInput(_))
    ));
    assert!(matches!(
        DepthPeeler::new(ctx, 0, 64, 2),
        Err(GpuError::SizeOverLimit { .. })
    ));
    let max = ctx.device.limits().max_texture_dimension_2d;
    assert!(matches!(
        DepthPeeler::new(ctx, max + 1, 16, 2),
        Err(GpuError::SizeOverLimit { .. })
    ));

    let peeler = DepthPeeler::new(ctx, 16, 16, 2).expect("peeler");
    let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("tiny"),
        size: 64,
        usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::INDEX,
        mapped_at_creation: false,
    });
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    let camera = Camera::on_z_axis(3.0);
    let mut nan = camera.view_proj;
    nan.x_axis.x = f32::NAN;
    let err = peeler
        .peel(ctx, &mut encoder, &buffer, &buffer, 3, nan, camera.eye)
        .unwrap_err();
    assert!(err.to_string().contains("finite"), "{err}");
    let err = peeler
        .peel(
            ctx,
            &mut encoder,
            &buffer,
            &buffer,
            30,
            camera.view_proj,
            camera.eye,
        )
        .unwrap_err();
    assert!(err.to_string().contains("index buffer"), "{err}");
    assert!(matches!(
        peeler.read_layer(ctx, 2),
        Err(GpuError::InvalidInput(_))
    ));

    // An empty mesh gives empty layers.
    peeler
        .peel(
            ctx,
            &mut encoder,
            &buffer,
            &buffer,
            0,
            camera.view_proj,
            camera.eye,
        )
        .expect("empty peel");
    ctx.queue.submit([encoder.finish()]);
    assert!(
        peeler
            .read_layer(ctx, 1)
            .expect("read")
            .iter()
            .all(|t| *t == [0.0; 4])
    );
    assert!(
        peeler
            .read_depth(ctx, 0)
            .expect("read")
            .iter()
            .all(|z| *z == 1.0)
    );
}
