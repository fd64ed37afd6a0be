//! Which of the paper's versions a variant renders, and its parameters, each declared once.

use super::*;

/// Which of the paper's versions a technique renders.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variant {
    /// Ceilings, floors and walls with lighting, flat colours (figure 5.13 top left).
    Basic,
    /// Four textures: floor, ceiling, two wall orientations (figure 5.13 bottom left).
    Textured,
    /// Textured, with the window glass reflecting an environment cube map (5.2.3).
    Exterior,
    /// Textured plus an alpha-tested, animated furniture plane (5.2.4).
    Furniture,
    /// Per-room lights, texture atlas variation and displaced walls (5.4).
    Varied,
    /// Baseline of 5.3.2: only the ceilings textured, walls and floors flat colours, lit
    /// (figure 5.13 top right).
    CeilingOnly,
    /// Baseline of 5.3.2: all four surfaces read from one texture (a 2 x 2 atlas), the tile
    /// chosen per hit from the plane family.
    SingleTexture,
    /// Baseline of 5.3 and 5.3.2: no interior at all, the windows fully reflect the
    /// environment cube map (the traditional building material the paper's ~5x is measured
    /// against).
    ReflectionOnly,
    /// Engine baseline: cube-map interiors (Unreal's `InteriorCubemap`): one pre-rendered room
    /// cube map looked up toward the exit of the room box (`rooms::cubemap_room`).
    Cubemap,
    /// Cube-map interiors with the per-window variation engines use: one of
    /// [`textures::VARIANTS`] room cube maps and a mirroring of each horizontal axis per room.
    CubemapVaried,
}

impl Variant {
    /// Every variant, in the order of `interior_mapping::techniques()` (without pre-pass).
    pub const ALL: [Variant; 10] = [
        Variant::Basic,
        Variant::Textured,
        Variant::Exterior,
        Variant::Furniture,
        Variant::Varied,
        Variant::CeilingOnly,
        Variant::SingleTexture,
        Variant::ReflectionOnly,
        Variant::Cubemap,
        Variant::CubemapVaried,
    ];
    pub(super) fn name(self) -> &'static str {
        match self {
            Variant::Basic => "basic",
            Variant::Textured => "textured",
            Variant::Exterior => "exterior",
            Variant::Furniture => "furniture",
            Variant::Varied => "varied",
            Variant::CeilingOnly => "ceiling-only",
            Variant::SingleTexture => "single-texture",
            Variant::ReflectionOnly => "reflection-only",
            Variant::Cubemap => "cubemap",
            Variant::CubemapVaried => "cubemap-varied",
        }
    }
    /// The variant number the shader branches on (`Settings.a.x` in technique.wgsl).
    pub(super) fn code(self) -> f32 {
        self as u32 as f32
    }
    /// Whether the windows reflect the environment cube map (rendered every frame).
    pub(super) fn uses_env_map(self) -> bool {
        matches!(self, Variant::Exterior | Variant::ReflectionOnly)
    }
    /// Whether the rooms come from room cube maps (the engine baseline).
    pub fn uses_room_cubes(self) -> bool {
        matches!(self, Variant::Cubemap | Variant::CubemapVaried)
    }
    /// Room cube maps in the atlas: [`textures::VARIANTS`] for the varied cube maps, else 1.
    pub fn room_cube_count(self) -> u32 {
        match self {
            Variant::CubemapVaried => VARIANTS,
            Variant::Cubemap => 1,
            _ => 0,
        }
    }
}

/// The parameters of an [`InteriorMapping`] variant, each declared once
/// ([`scene::Settings`]); which a variant has follows its `variant`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// The variant (what decides which parameters it has): `InteriorMapping::new` copies
    /// its own, and nothing changes it after.
    pub(crate) variant: Variant,
    /// Multiplies each building's room size (parameter `room_scale`).
    pub room_scale: f32,
    /// Interior texture size, texels per side (parameter `texture_resolution`).
    pub texture_resolution: u32,
    /// `varied`: probability that a room's light is on (parameter `light_probability`).
    pub light_probability: f32,
    /// Unshadowed room light, radiance = albedo x value (parameter `interior_light`; 0 matches
    /// the reference).
    pub interior_light: f32,
    /// `furniture`: depth of the furniture plane behind the facade, in rooms (parameter
    /// `furniture_depth`).
    pub furniture_depth: f32,
    /// `varied`: largest wall displacement, in rooms (parameter `displacement`).
    pub displacement: f32,
    /// Room surfaces of box hulls lit only through the windows (exact); false: the scene's
    /// shadow maps, as the polygon baseline.
    pub room_shadows: bool,
}

impl Settings {
    /// Whether rooms are cast (all but `reflection-only`, whose only parameter is the window
    /// grid's `room_scale`).
    pub(super) fn casts_rooms(&self) -> bool {
        self.variant != Variant::ReflectionOnly
    }
}

impl scene::Settings for Settings {
    const DECLARED: &'static [Declared<Self>] = &[
        Declared::new(
            "room_scale",
            (0.05, 20.0),
            "multiplies each building's room size",
            |s| Some(&mut s.room_scale),
        ),
        Declared::new(
            "texture_resolution",
            (16.0, 256.0),
            "room cube map face size (texels per side; one face spans a room face as one \
             interior texture does)",
            |s| {
                let cubes = s.casts_rooms() && s.variant.uses_room_cubes();
                setting_if(cubes, &mut s.texture_resolution)
            },
        ),
        Declared::new(
            "texture_resolution",
            (16.0, 256.0),
            "interior texture size (texels per side)",
            |s| {
                let textures = s.casts_rooms() && !s.variant.uses_room_cubes();
                setting_if(textures, &mut s.texture_resolution)
            },
        ),
        Declared::new(
            "room_shadows",
            (0.0, 1.0),
            "1: rooms of box hulls lit only through their windows (exact); 0: the scene's \
             shadow maps, like interior-mapping/polygons",
            |s| setting_if(s.casts_rooms(), &mut s.room_shadows),
        ),
        Declared::new(
            "interior_light",
            (0.0, 100.0),
            "unshadowed room light: radiance = albedo * value (0 matches the reference)",
            |s| setting_if(s.casts_rooms(), &mut s.interior_light),
        ),
        Declared::new(
            "light_probability",
            (0.0, 1.0),
            "probability that a room's light is on (c in 5.4.1)",
            |s| setting_if(s.variant == Variant::Varied, &mut s.light_probability),
        ),
        Declared::new(
            "displacement",
            (0.0, crate::rooms::MAX_DISPLACEMENT as f64),
            "largest wall displacement (rooms)",
            |s| setting_if(s.variant == Variant::Varied, &mut s.displacement),
        ),
        Declared::new(
            "furniture_depth",
            (0.0, 1.0),
            "furniture plane depth behind the facade (rooms)",
            |s| setting_if(s.variant == Variant::Furniture, &mut s.furniture_depth),
        ),
    ];
}
