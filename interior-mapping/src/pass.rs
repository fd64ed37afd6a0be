//! Interior mapping as one pass of a renderer's own frame: buildings whose windows show rooms
//! found by a per-pixel ray cast against the room planes (van Dongen 2008, chapter 5), drawn
//! over the renderer's colour and depth targets in their formats.
//!
//! What the renderer provides (and nothing else: no `scene::Scene`, no `GpuScene`, no timer):
//!
//! - its wgpu device and queue, wrapped once with `gpu::Context::from_parts`;
//! - the buildings ([`Building`]): each one's hull, a box in the building's frame, its room
//!   size, the colour of its facade, its index among the renderer's objects and where it
//!   stands (`set_position_of` moves it, its rooms with it); the renderer does not draw them;
//! - the point lights that light the facades and, through the windows, the rooms
//!   ([`PointLight`]): the pass shadows the rooms by the hull's walls and windows and the
//!   facades by the buildings themselves; the renderer's other objects cast no shadow on them;
//! - for the variants whose window glass reflects (`Variant::Exterior`,
//!   `Variant::ReflectionOnly`), its world on request, [`gpu::DrawScene`]: every object, from
//!   the eye, into the six faces of a reflection map (`Rgba16Float`, radiance in rgb and the
//!   distance from the eye in alpha; depth `Depth32Float`), each frame;
//! - its colour and depth targets (any renderable colour format, any depth format), holding
//!   its frame already (the pass writes rgb and depth; the renderer's alpha is kept), and its
//!   camera ([`gpu::EyeView`]).
//!
//! The pass is the technique's own code: `InteriorMapping::draw_over` runs the hull passes
//! the harness's `interior-mapping/<variant>` runs in its frame (`write_settings`,
//! `draw_interiors`), with `scene::GpuScene` as the host there.

use crate::technique::{InteriorMapping, Variant};
use glam::{Mat4, Vec3};
use gpu::TargetFormats;
use scene::hosted::HostedPass;
use scene::{Material, Object, Roles, Scene, TechniqueResult};

/// One of the renderer's buildings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Building {
    /// The hull's corner of least coordinates, in the building's frame (y up).
    pub min: Vec3,
    /// The hull's corner of greatest coordinates.
    pub max: Vec3,
    /// The size of a room (metres): the room planes repeat at this spacing from `min`.
    pub room_size: Vec3,
    /// The facade's diffuse albedo (linear).
    pub facade: Vec3,
    /// Its index among the renderer's objects (named in errors; the reflection map asks the
    /// renderer for all its objects).
    pub host_index: usize,
    /// Where it stands: the offset from where `min` and `max` put it.
    pub position: Vec3,
}

/// A point light of the renderer's, lighting the buildings and their rooms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLight {
    /// Where it is (world).
    pub position: Vec3,
    /// Its intensity per RGB channel (radiance times area: irradiance at 1 m is
    /// `intensity / 1 m^2` facing it).
    pub intensity: Vec3,
}

/// The interior-mapping pass of some buildings, made for a renderer's formats: a
/// [`HostedPass`] (its `set_position_of` and `draw`) of the [`InteriorMapping`] technique.
pub struct InteriorPass(HostedPass<InteriorMapping>);

impl InteriorPass {
    /// The pass of `buildings` lit by `lights`, their rooms shown as `variant` shows them
    /// (the room textures `texture_resolution` texels a side), for targets of `formats`.
    pub fn new(
        ctx: &gpu::Context,
        buildings: &[Building],
        lights: &[PointLight],
        variant: Variant,
        formats: TargetFormats,
        texture_resolution: u32,
    ) -> TechniqueResult<Self> {
        let mut technique = InteriorMapping::new(variant, false).for_targets(formats);
        scene::Technique::set_param(
            &mut technique,
            "texture_resolution",
            texture_resolution as f64,
        )?;
        let scene = buildings_scene(buildings, lights)?;
        let indices = buildings.iter().map(|b| b.host_index).collect();
        HostedPass::of_scene(ctx, formats, (scene, indices), technique).map(Self)
    }
}

/// The scene of the renderer's buildings: each a box hull with the building role and its
/// rooms, lit by `lights`.
fn buildings_scene(buildings: &[Building], lights: &[PointLight]) -> TechniqueResult<Scene> {
    let mut scene = Scene {
        name: "hosted buildings".into(),
        lights: lights
            .iter()
            .enumerate()
            .map(|(i, l)| scene::Light {
                name: format!("renderer's light {i}"),
                position: l.position,
                intensity: l.intensity,
                kind: scene::LightKind::Point,
            })
            .collect(),
        ..scene::hosted::empty_scene()
    };
    for (i, b) in buildings.iter().enumerate() {
        let (size, rooms) = (b.max - b.min, b.room_size);
        if !(size.cmpgt(Vec3::ZERO).all() && rooms.cmpgt(Vec3::ZERO).all()) {
            return Err(scene::TechniqueError::Unsupported(format!(
                "building {} (the renderer's object {}) needs a hull and rooms of positive size; \
                 it has {size} and {rooms}",
                i, b.host_index
            )));
        }
        let facade = Material::Diffuse {
            albedo: b.facade,
            texture: None,
            cutout: None,
        };
        let hull = scene::mesh::cuboid(b.min, b.max);
        let mut object = Object::new(
            &format!("building {i}"),
            hull,
            facade,
            Mat4::from_translation(b.position),
        )
        .with_roles(Roles::BUILDING);
        object.building = Some(scene::Building {
            room_size: b.room_size,
        });
        scene.objects.push(object);
    }
    Ok(scene)
}

scene::hosted_pass_deref!(InteriorPass, InteriorMapping);
