//! The variants of the family and the settings every parameter sets.

use super::*;

/// How photon rays find their first surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum March {
    /// The paper's: lines rasterized into rows, the tolerance test, the first hit per row.
    Lines,
    /// One compute invocation per photon marching pixel by pixel with a thickness per layer.
    Dda,
    /// The paper's single-shader alternative (section 2.1: "photon tracing can also be
    /// implemented as a single pixel shader being executed for each photon"): one compute
    /// invocation per photon walking the same samples with the lines' tolerance test and
    /// keeping the same sample, stopping there.
    Shader,
}

/// How receiver points spread their flux.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Splat {
    /// Section 3.1: ray casting the receiver's tangent plane per covered pixel.
    Oriented,
    /// Screen-aligned point sprites (the naive variant of the paper's figure 6).
    Sprite,
}

/// How the view rays through specular surfaces are traced (section 4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Refraction {
    /// The paper's monotone layers inside refractors and the tolerance test outside.
    Monotone,
    /// The DDA with thickness, over every layer.
    Dda,
}

/// How light shafts in a scattering medium are made (section 3.2 and the engine's way).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shafts {
    /// The paper's: photon beams drawn as lines (bands), blurred, blended.
    GodRays,
    /// The engine baseline: froxel volumetric fog lit by shadow maps in which transparent
    /// surfaces cast no shadow, sampled with temporal jitter and reprojected history
    /// (Wronski 2014, Hillaire 2015). No photon reaches it.
    Froxels,
    /// A hybrid of ours, not an engine's: the froxels lit by the scene's shadow maps and by a
    /// caustic map of where this technique's photons end.
    FroxelsWithPhotons,
}

impl Shafts {
    /// Whether the froxel grid draws the shafts.
    pub fn froxels(self) -> bool {
        matches!(self, Shafts::Froxels | Shafts::FroxelsWithPhotons)
    }

    /// Whether the shafts are drawn from the photons' beams (the march keeps them).
    pub fn from_photons(self) -> bool {
        matches!(self, Shafts::GodRays | Shafts::FroxelsWithPhotons)
    }
}

/// The parameters of a variant (all declared, all sweepable).
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Side of the photon grid: `photons`^2 photons per light.
    pub photons: u32,
    /// LDI layers peeled (the paper: "usually sufficient to only consider up to eight").
    pub layers: u32,
    /// Count the view's depth complexity first and peel only that many layers (section 2.2:
    /// a count pass and a reduce-max; `scene::layer_count`). Where the adapter cannot draw
    /// the layers indirectly (no `INDIRECT_FIRST_INSTANCE`) every layer is peeled, which gives
    /// the same LDI.
    pub count_layers: bool,
    /// The paper's world-space tolerance of the line test (m).
    pub tolerance: f32,
    /// The DDA's thickness of every surface (m).
    pub thickness: f32,
    /// Splat radius in photon spacings at the casters (the grid's pixel at their distance).
    pub splat_radius: f32,
    /// Specular events a photon may have after the transfer map (section 2.3).
    pub bounces: u32,
    /// Rows of the line buffer: photons per batch of the line marcher.
    pub rows: u32,
    /// Standard deviation of the god rays' Gaussian blur, as a fraction of the image height.
    pub shaft_blur: f32,
    /// Side of a froxel tile in pixels.
    pub froxel_size: u32,
    /// Depth slices of the froxel grid.
    pub slices: u32,
    /// Side of the hybrid froxels' caustic map (texels).
    pub caustic_map: u32,
    /// Froxels: weight of this frame's jittered sample against the reprojected history
    /// (Hillaire's exponential moving average); 1 keeps no history and does not jitter.
    pub temporal_blend: f32,
    /// Each photon leaves from a random point of its transfer-map pixel instead of the pixel
    /// centre (stratified jittered emission, `jittered_emission` in scene.wgsl).
    pub jitter: bool,
    /// Oriented splats: each photon's cone stretched over the footprint of its lattice cell on
    /// the receiver (`footprint_matrix` in splat_weight.wgsl).
    pub footprint: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            photons: 256,
            layers: 8,
            count_layers: true,
            tolerance: 0.03,
            thickness: 0.1,
            splat_radius: 3.0,
            bounces: 2,
            rows: 4096,
            shaft_blur: 0.01,
            froxel_size: 8,
            slices: 64,
            caustic_map: 128,
            temporal_blend: 0.1,
            jitter: false,
            footprint: true,
        }
    }
}

impl scene::Settings for Settings {
    const DECLARED: &'static [Declared<Self>] = &[
        Declared::new(
            "photons",
            (8.0, 1024.0),
            "side of the photon grid (photons x photons per light; the paper: 128 x 64 to \
                 1024 x 1024)",
            |s| Some(&mut s.photons),
        ),
        Declared::new(
            "layers",
            (1.0, 16.0),
            "LDI layers peeled from the eye (depth complexity cap)",
            |s| Some(&mut s.layers),
        ),
        Declared::new(
            "count_layers",
            (0.0, 1.0),
            "1: count the depth complexity and peel only that many layers (section 2.2); \
                 0: peel every layer",
            |s| Some(&mut s.count_layers),
        ),
        Declared::new(
            "tolerance",
            (1e-4, 1.0),
            "world-space tolerance of the line test (m)",
            |s| Some(&mut s.tolerance),
        ),
        Declared::new(
            "thickness",
            (1e-4, 2.0),
            "thickness of every LDI surface for the DDA test (m)",
            |s| Some(&mut s.thickness),
        ),
        Declared::new(
            "splat_radius",
            (0.25, 32.0),
            "splat radius in photon spacings at the casters",
            |s| Some(&mut s.splat_radius),
        ),
        Declared::new(
            "bounces",
            (0.0, 6.0),
            "specular events a photon may have after the transfer map",
            |s| Some(&mut s.bounces),
        ),
        Declared::new(
            "rows",
            (64.0, 8192.0),
            "rows of the line buffer (photons per line batch)",
            |s| Some(&mut s.rows),
        ),
        Declared::new(
            "shaft_blur",
            (0.0, 0.1),
            "god rays: standard deviation of the blur, a fraction of the image height",
            |s| Some(&mut s.shaft_blur),
        ),
        Declared::new(
            "froxel_size",
            (1.0, 64.0),
            "froxel fog: side of a froxel tile (pixels)",
            |s| Some(&mut s.froxel_size),
        ),
        Declared::new(
            "slices",
            (1.0, 256.0),
            "froxel fog: exponential depth slices",
            |s| Some(&mut s.slices),
        ),
        Declared::new(
            "caustic_map",
            (8.0, 2048.0),
            "froxel-fog-photons: side of the caustic map (texels)",
            |s| Some(&mut s.caustic_map),
        ),
        Declared::new(
            "temporal_blend",
            (0.01, 1.0),
            "froxel fog: weight of the frame's jittered sample against the reprojected \
                 history (1: no history, no jitter)",
            |s| Some(&mut s.temporal_blend),
        ),
        footprint_declared(|s| Some(&mut s.footprint)),
        jitter_declared(|s| Some(&mut s.jitter)),
    ];
}

/// A variant: caustics (marcher and splats) or none, the refraction tracing, and the
/// shadows (the shared pass's shadow maps, or screen-space shadow rays).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Variant {
    pub name: &'static str,
    pub caustics: Option<(March, Splat)>,
    pub refraction: Refraction,
    pub screen_space_shadows: bool,
    /// Light shafts (only in a scene with a scattering medium).
    pub shafts: Option<Shafts>,
}

/// The variants: `lines`, `dda`, `sprites`, `shader` (caustics; the specular surfaces traced by
/// the DDA), `refraction` and `refraction-dda` (refraction tracing alone), `shadows` (screen-space
/// shadow rays instead of shadow maps, no caustics), `god-rays` and `froxel-fog` (the `dda`
/// caustics plus light shafts, the paper's and the engines'), `froxel-fog-photons` (the
/// froxels fed the photons too: a hybrid of ours, not representative).
pub fn variants() -> Vec<Variant> {
    use March::*;
    // The caustic variants trace the specular surfaces with the DDA: the paper's tolerance
    // test misses grazing surfaces (README, "Failure cases"), and its misses would bury the
    // caustics' error under the surface's; `refraction` measures the paper's tracing alone.
    let caustics = |name, march, splat| Variant {
        name,
        caustics: Some((march, splat)),
        refraction: Refraction::Dda,
        screen_space_shadows: false,
        shafts: None,
    };
    let shafts = |name, shafts| Variant {
        shafts: Some(shafts),
        ..caustics(name, Dda, Splat::Oriented)
    };
    vec![
        caustics("lines", Lines, Splat::Oriented),
        caustics("dda", Dda, Splat::Oriented),
        caustics("sprites", Lines, Splat::Sprite),
        caustics("shader", Shader, Splat::Oriented),
        Variant {
            name: "refraction",
            caustics: None,
            refraction: Refraction::Monotone,
            screen_space_shadows: false,
            shafts: None,
        },
        Variant {
            name: "refraction-dda",
            caustics: None,
            refraction: Refraction::Dda,
            screen_space_shadows: false,
            shafts: None,
        },
        Variant {
            name: "shadows",
            caustics: None,
            refraction: Refraction::Dda,
            screen_space_shadows: true,
            shafts: None,
        },
        shafts("god-rays", Shafts::GodRays),
        shafts("froxel-fog", Shafts::Froxels),
        shafts("froxel-fog-photons", Shafts::FroxelsWithPhotons),
    ]
}
