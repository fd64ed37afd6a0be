//! How a variant finds the second interface, and the parameters of a variant, each declared
//! once.

use super::*;

/// How a variant finds the second interface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variant {
    /// The refracted ray `T1` looks the environment up at once (one interface).
    OneInterface,
    /// Wyman 2005: `P2 = P1 + d T1`, `d` interpolated between the view-ray thickness and the
    /// precomputed thickness along the normal; back-facing `N2` (the method the paper improves).
    TwoInterfaceBaseline,
    /// Hu and Qin 2006, section 2.1: side by angle test (or back first), iterative `d_T`.
    HuQin,
    /// The engine approach (HDRP's sphere model): one bend, a thickness, the scene colour.
    ThicknessProxy,
}

impl Variant {
    pub(super) fn wgsl_id(self) -> u32 {
        match self {
            Variant::OneInterface => 0,
            Variant::TwoInterfaceBaseline => 1,
            Variant::HuQin => 2,
            Variant::ThicknessProxy => 3,
        }
    }
    pub(super) fn needs_buffers(self) -> bool {
        matches!(self, Variant::TwoInterfaceBaseline | Variant::HuQin)
    }
}

/// Parameters of a [`Refraction`] (settable by name through [`Technique::set_param`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// The second-interface method.
    pub variant: Variant,
    /// Face size of the environment cube maps (`resolution`).
    pub env_resolution: u32,
    /// `d_T` iteration: stop when a correction is at most this (metres, `tolerance`).
    pub tolerance: f32,
    /// `d_T` iteration: most corrections (`iterations`).
    pub max_iterations: u32,
    /// `d_T` iteration: the first `d_T` as a fraction of the refractor's bounding radius
    /// (`initial_step`).
    pub initial_step: f32,
    /// Section 4's acceleration: back side first, front side when `P2` leaves the silhouette
    /// (`back_first` 1), instead of the silhouette search and angle test (0).
    pub back_first: bool,
    /// Thickness proxy: the sphere's diameter (or the slab's thickness) as a fraction of the
    /// object's bounding diameter (`thickness`).
    pub thickness: f32,
    /// Thickness proxy: HDRP's box model (a slab: one bend, leaving along the view ray,
    /// `proxy` 1) instead of its sphere model (into and out of a tangent sphere, `proxy` 0).
    pub box_proxy: bool,
    /// Nearby geometry as rectangle impostors (section 2.2), or the environment map alone.
    pub nearby: Option<Nearby>,
    /// Caustics (section 3; needs `nearby`: photons land on the rectangles).
    pub caustics: Option<CausticSettings>,
    /// The engine's environment (`probe` 1): one reflection probe for every object, captured
    /// once in the first frame where an artist would place it (`scene::probe_centre`) without
    /// the specular objects, looked up box-projected against the scene's diffuse bounds
    /// (Lagarde and Zanuttini 2012, `gpu::prelude::box_project`), instead of the paper's map
    /// from each object's centre every frame. One map whatever the number of objects: a scene of many glass
    /// objects (`chess`) renders. Without `nearby` only.
    pub room_probe: bool,
}

impl scene::Settings for Settings {
    /// Which parameters a variant has follows its second-interface method, its nearby
    /// geometry and its caustics.
    const DECLARED: &'static [Declared<Self>] = &[
        Declared::new(
            "resolution",
            (4.0, 4096.0),
            "environment cube map face size (texels)",
            |s| Some(&mut s.env_resolution),
        ),
        Declared::new(
            "tolerance",
            (1e-6, 1.0),
            "d_T iteration stops when a correction is at most this (m of view depth)",
            |s| setting_if(s.variant == Variant::HuQin, &mut s.tolerance),
        ),
        Declared::new(
            "iterations",
            (1.0, 64.0),
            "d_T iteration: most corrections",
            |s| setting_if(s.variant == Variant::HuQin, &mut s.max_iterations),
        ),
        Declared::new(
            "initial_step",
            (1e-4, 2.0),
            "d_T iteration: first d_T as a fraction of the refractor's bounding radius",
            |s| setting_if(s.variant == Variant::HuQin, &mut s.initial_step),
        ),
        Declared::new(
            "back_first",
            (0.0, 1.0),
            "1: section 4's acceleration (back side first); 0: silhouette search and angle \
             test",
            |s| setting_if(s.variant == Variant::HuQin, &mut s.back_first),
        ),
        Declared::new(
            "thickness",
            (0.0, 4.0),
            "the proxy sphere's diameter (slab's thickness) as a fraction of the object's \
             bounding diameter",
            |s| setting_if(s.variant == Variant::ThicknessProxy, &mut s.thickness),
        ),
        Declared::new(
            "proxy",
            (0.0, 1.0),
            "0: HDRP's sphere model (in and out of a tangent sphere); 1: its box model (a \
             slab, leaving along the view ray)",
            |s| setting_if(s.variant == Variant::ThicknessProxy, &mut s.box_proxy),
        ),
        Declared::new(
            "probe",
            (0.0, 1.0),
            "1: one room probe for every object, captured once, box-projected (the engine's); \
             0: the paper's map from each object's centre every frame",
            |s| setting_if(s.nearby.is_none(), &mut s.room_probe),
        ),
        Declared::new(
            "photon_buffer",
            (8.0, 2048.0),
            "side of each light's photon buffer (photons per light: its square)",
            |s| Some(&mut s.caustics.as_mut()?.photon_size),
        ),
        Declared::new(
            "caustic_resolution",
            (8.0, 2048.0),
            "side of each rectangle's caustic texture (texels)",
            |s| Some(&mut s.caustics.as_mut()?.resolution),
        ),
        Declared::new(
            "filter_k",
            (0.0, 8.0),
            "the caustic filter's half size k (section 3.2; the paper's default 2)",
            |s| Some(&mut s.caustics.as_mut()?.k),
        ),
        jitter_declared(|s| Some(&mut s.caustics.as_mut()?.jitter)),
        Declared::new(
            "filter_s",
            (0.0, 100.0),
            "the caustic filter's scale s (1: the photons' power; the filter is normalized by \
             its weights)",
            |s| Some(&mut s.caustics.as_mut()?.scale),
        ),
        Declared::new(
            "impostor_resolution",
            (8.0, 4096.0),
            "side of each rectangle impostor's texture (texels)",
            |s| Some(&mut s.nearby.as_mut()?.resolution),
        ),
        Declared::new(
            "seeds",
            (1.0, 64.0),
            "points on the ray tried as the correction's start (figure 17)",
            |s| corrected(s).map(|n| &mut n.seeds as &mut dyn ParamValue),
        ),
        Declared::new(
            "corrections",
            (1.0, 64.0),
            "most depth corrections of a rectangle lookup (figure 16)",
            |s| corrected(s).map(|n| &mut n.iterations as &mut dyn ParamValue),
        ),
        Declared::new(
            "depth_tolerance",
            (1e-6, 1.0),
            "a correction stops within this depth difference (m)",
            |s| corrected(s).map(|n| &mut n.tolerance as &mut dyn ParamValue),
        ),
    ];
}

/// The rectangle impostors' settings where their lookup is depth-corrected.
pub(super) fn corrected(s: &mut Settings) -> Option<&mut Nearby> {
    s.nearby.as_mut().filter(|n| n.corrected)
}

/// Parameters of the rectangle impostors of nearby geometry (section 2.2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Nearby {
    /// Figure 16's iterative depth correction from figure 17's seed (`corrected`), or the
    /// texel where the ray meets the rectangle (figure 13).
    pub corrected: bool,
    /// Seeds on the ray for the first point of the correction (`seeds`).
    pub seeds: u32,
    /// Most corrections (`corrections`).
    pub iterations: u32,
    /// Depth tolerance of a correction, metres (`depth_tolerance`).
    pub tolerance: f32,
    /// Side of each impostor texture (`impostor_resolution`).
    pub resolution: u32,
    /// Reflective and refractive nearby objects drawn into their textures with their own
    /// (one-interface) shading: recursive reflections and refractions (section 2.2.1).
    pub recursive: bool,
}

impl Default for Nearby {
    fn default() -> Self {
        Self {
            corrected: true,
            seeds: 8,
            iterations: 4,
            tolerance: 1e-3,
            resolution: 256,
            recursive: false,
        }
    }
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            variant: Variant::HuQin,
            env_resolution: 256,
            tolerance: 1e-3,
            max_iterations: 8,
            initial_step: 0.1,
            back_first: false,
            thickness: 1.0,
            box_proxy: false,
            nearby: None,
            caustics: None,
            room_probe: false,
        }
    }
}
