//! The parameters of a variant, each declared once.

use super::*;

/// The parameters of a variant, each declared once ([`scene::Settings`]); which a variant
/// has follows its drawing method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// The variant's method (what decides which parameters it has): `VolumeTechnique::new`
    /// copies its variant's, and nothing changes it after.
    pub(crate) method: Method,
    /// Billboard half size in units of the volume radius (billboards and ray-traced).
    pub billboard_scale: f32,
    /// Ray-traced: size each billboard to the sphere's silhouette, and draw a screen-filling
    /// quad when the eye is inside or next to the sphere (a departure from the thesis, which
    /// accepts the cut-off, 6.3.3).
    pub fit_silhouette: bool,
    /// Ray-traced: read the raster pass's depth buffer instead of rendering the thesis's
    /// distance texture (the depth "already exists for other reasons").
    pub free_depth: bool,
    /// Billboards and slices: render the distance texture anyway (the thesis's measurement of
    /// what the depth texture costs, 6.4.3).
    pub depth_prepass: bool,
    /// Depth fade: the gap (units of the volume radius) over which a billboard fades in
    /// front of the scene (parameter `fade_distance`).
    pub fade_distance: f32,
}

impl Settings {
    pub(super) fn raytraced(&self) -> bool {
        matches!(self.method, Method::Raytraced(_))
    }
    pub(super) fn scaled(&self) -> bool {
        matches!(
            self.method,
            Method::Raytraced(_) | Method::DepthFade | Method::Billboard
        )
    }
}

impl scene::Settings for Settings {
    const DECLARED: &'static [Declared<Self>] = &[
        Declared::new(
            "billboard_scale",
            (1.0, 8.0),
            "billboard half size in units of the volume radius (the sphere is cut where its \
             silhouette leaves the billboard)",
            |s| setting_if(s.scaled(), &mut s.billboard_scale),
        ),
        Declared::new(
            "fit_silhouette",
            (0.0, 1.0),
            "1: size each billboard to cover the sphere's silhouette and fill the screen \
             when the eye is inside or next to the volume (not in the thesis); \
             0: billboard_scale times the radius, as the thesis",
            |s| setting_if(s.raytraced(), &mut s.fit_silhouette),
        ),
        Declared::new(
            "free_depth",
            (0.0, 1.0),
            "1: read the raster pass's depth buffer (the depth texture exists for other \
             reasons, its cost not charged); 0: render the thesis's R16Float distance texture",
            |s| setting_if(s.raytraced(), &mut s.free_depth),
        ),
        Declared::new(
            "fade_distance",
            (0.0, 10.0),
            "scene-to-billboard gap over which a particle fades in, in units of its \
             radius (0: a hard depth test)",
            |s| setting_if(s.method == Method::DepthFade, &mut s.fade_distance),
        ),
        Declared::new(
            "depth_prepass",
            (0.0, 1.0),
            "1: also render the (unused) scene distance texture, as the thesis did to \
             measure its cost (6.4.3)",
            |s| {
                let unused = matches!(s.method, Method::Billboard | Method::Slices { .. });
                setting_if(unused, &mut s.depth_prepass)
            },
        ),
    ];
}
