//! The scene as the tracer's shaders read it: one table of vec4s (lights, volumes, emitters,
//! objects, the texture table, the sRGB table) and every texture's texels.

use glam::Vec3;
use scene::Scene;
use scene::emission::Emitter;

/// Lights, volumes, emitters, objects, the texture table and the sRGB table in one buffer of
/// vec4s (the layout `tracer.wgsl`'s accessors read), and every texture's texels.
pub(crate) struct Tables {
    pub(crate) data: Vec<[f32; 4]>,
    pub(crate) counts: [u32; 4],
    pub(crate) offsets: [u32; 4],
    pub(crate) texture_table: u32,
    pub(crate) srgb_table: u32,
}

impl Tables {
    pub(crate) fn new(scene: &Scene, time: f32, emitters: &[Emitter]) -> Self {
        let mut data: Vec<[f32; 4]> = Vec::new();
        let lights = data.len() as u32;
        for l in &scene.lights {
            // As tracer.wgsl's `light` reads them: the kind in position.w, the direction, a
            // spot's cone cosines.
            let (kind, direction, cone) = l.shader_fields();
            data.push(l.position.extend(kind).to_array());
            data.push(l.intensity.extend(0.0).to_array());
            data.push(direction.extend(0.0).to_array());
            data.push(cone);
        }
        let volumes = data.len() as u32;
        let placed: Vec<_> = scene
            .volumes
            .iter()
            .filter(|v| v.validate().is_ok() && v.density > 0.0)
            .collect(); // as `marched_volumes` counts them
        for v in &placed {
            let c = v.center + v.motion.offset(time);
            data.push(c.extend(v.radius).to_array());
            data.push(v.color.extend(v.density).to_array());
            let p = v.profile;
            data.push([p.falloff, p.noise, p.noise_frequency, 0.0]);
        }
        let emitter_offset = data.len() as u32;
        let mut first = 0u32;
        for e in emitters {
            data.push(e.axis.extend(e.one_minus_cos).to_array());
            data.push([
                f32::from_bits(e.light as u32),
                e.measure,
                f32::from_bits(e.photons as u32),
                f32::from_bits(first),
            ]);
            data.push(e.origin.extend(e.radius).to_array());
            first += e.photons as u32;
        }
        let objects = data.len() as u32;
        for o in &scene.objects {
            let (albedo, texture, kind, ior, n, k) = match o.material {
                scene::Material::Diffuse {
                    albedo, texture, ..
                } => (
                    albedo,
                    texture
                        .filter(|t| *t < scene.textures.len())
                        .map_or(-1, |t| t as i32),
                    0.0,
                    1.0,
                    Vec3::ZERO,
                    Vec3::ZERO,
                ),
                scene::Material::Metal { n, k } => (Vec3::ZERO, -1, 1.0, 1.0, n, k),
                scene::Material::Glass { ior } => {
                    (Vec3::ZERO, -1, 2.0, ior, Vec3::ZERO, Vec3::ZERO)
                }
            };
            data.push(albedo.extend(f32::from_bits(texture as u32)).to_array());
            data.push([kind, ior, 0.0, 0.0]);
            data.push(n.extend(0.0).to_array());
            data.push(k.extend(0.0).to_array());
            data.push(o.emission.extend(0.0).to_array());
        }
        let texture_table = data.len() as u32;
        // Texels follow the cut-out table in the same buffer (`texture_data`).
        let mut texel_offset = crate::bvh::cutout_table(scene).len() as u32;
        for t in &scene.textures {
            data.push([
                f32::from_bits(texel_offset),
                f32::from_bits(t.width),
                f32::from_bits(t.height),
                0.0,
            ]);
            texel_offset += t.width * t.height;
        }
        let srgb_table = data.len() as u32;
        for chunk in (0..=255u8).collect::<Vec<_>>().chunks(4) {
            let mut v = [0.0; 4];
            for (slot, &c) in v.iter_mut().zip(chunk) {
                *slot = scene::srgb_to_linear(c);
            }
            data.push(v);
        }
        Tables {
            data,
            counts: [
                scene.lights.len() as u32,
                placed.len() as u32,
                emitters.len() as u32,
                scene.objects.len() as u32,
            ],
            offsets: [lights, volumes, emitter_offset, objects],
            texture_table,
            srgb_table,
        }
    }
}

/// The objects' alpha cut-outs ([`crate::bvh::cutout_table`]), then every texture's RGBA8
/// texels as one u32 each (red in the low byte), in scene order: `texture_data` in
/// `shaders/triangles.wgsl`. One buffer for both keeps the tracer within the eight storage
/// buffers a shader stage may bind on every adapter.
pub(crate) fn texture_data(scene: &Scene) -> Vec<u32> {
    let mut out = crate::bvh::cutout_table(scene);
    out.extend(scene.textures.iter().flat_map(|t| {
        t.rgba8
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
    }));
    out
}
