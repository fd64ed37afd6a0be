//! What a variant is: which volumes it draws, how (method) and with which opacity function;
//! the thesis's, the particle systems' and the engine's lists.

use super::*;

/// Colour buffer the scene and the volumes are composited in (the "floating point buffer").
pub const FLOAT_BUFFER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Colour buffer of the 8-bit slice variants.
pub const BYTE_BUFFER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
/// The depth pre-pass's distance texture: "a 16 bit floating point texture" (6.3.3).
pub const DISTANCE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R16Float;

/// Which volumes of a scene a variant draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum VolumeSet {
    /// The large volumes (`particle == false`): the thesis's "simple, large particle" that its
    /// 17 tests analyse.
    Single,
    /// Every volume (the particle-system versions).
    All,
}

impl VolumeSet {
    /// Whether a variant drawing this set draws volume `v`.
    pub fn includes(self, v: &Volume) -> bool {
        match self {
            VolumeSet::Single => !v.particle,
            VolumeSet::All => true,
        }
    }
}

/// Optical depth of a volume's chord through its centre, without its noise texture:
/// `density R integral_{-1}^{1} (1 - x^2)^k dx` (midpoint rule, 256 steps: exact to 1e-5 for
/// the profiles in use).
pub fn centre_optical_depth(v: &Volume) -> f32 {
    let n = 256;
    let smooth = scene::DensityProfile {
        noise: 0.0,
        ..v.profile
    };
    let shape: f32 = (0..n)
        .map(|i| {
            let x = -1.0 + (i as f32 + 0.5) * 2.0 / n as f32;
            smooth.shape(Vec3::new(x, 0.0, 0.0)) * 2.0 / n as f32
        })
        .sum();
    v.density * v.radius * shape
}

/// The opacity reached over one metre (the scale of the thesis's opacity functions) that
/// makes `opacity` give a volume's true centre opacity `1 - exp(-tau_c)` over its diameter,
/// tau_c = [`centre_optical_depth`]. This is how a variant reads the scene's density field
/// (an artist matching the smoke's look at its centre); away from the centre each opacity
/// function departs from Beer-Lambert in its own way, which is part of its error.
pub fn opacity_scale(v: &Volume, opacity: OpacityFn) -> f32 {
    let alpha = 1.0 - (-centre_optical_depth(v)).exp();
    opacity.scale_for(alpha, 2.0 * v.radius)
}

/// How a variant renders a volume.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    /// 6.3.1: one textured billboard, no volume.
    Billboard,
    /// 6.3.2: `count` parallel slices; `float_buffer` blends them in Rgba16Float instead of
    /// Rgba8Unorm.
    Slices {
        /// Number of slices (the thesis tests 5, 9, 19, 39 and 79).
        count: u32,
        /// Blend the slices in `FLOAT_BUFFER_FORMAT` (true) or `BYTE_BUFFER_FORMAT` (false).
        float_buffer: bool,
    },
    /// 6.3.3: a billboard that ray-traces a volume primitive against the scene distance.
    Raytraced(Primitive),
    /// Engine baseline: the depth-fade soft particle every engine ships: the textured
    /// billboard of `Billboard` without depth test, its opacity multiplied by
    /// `path_length::depth_fade` of the scene depth (the raster pass's depth buffer) behind it.
    DepthFade,
}

/// One technique variant: method, opacity function and which volumes it draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Variant {
    /// How each volume is drawn (billboard, slices, ray-traced primitive).
    pub method: Method,
    /// How the visible path length becomes opacity (thesis figure 6.21).
    pub opacity: OpacityFn,
    /// Which of the scene's volumes are drawn.
    pub set: VolumeSet,
}

impl Variant {
    /// `volumes/<name>`, `volumes/particles-<name>` for the particle-system versions.
    pub fn id(&self) -> String {
        let name = match self.method {
            Method::Billboard => "billboard".to_string(),
            Method::DepthFade => "depth-fade".to_string(),
            Method::Slices {
                count,
                float_buffer,
            } => {
                format!("slices-{count}{}", if float_buffer { "-float" } else { "" })
            }
            Method::Raytraced(Primitive::Constant) => "raytraced-constant".into(),
            Method::Raytraced(Primitive::Linear) => "raytraced-linear".into(),
            Method::Raytraced(Primitive::Texture) => "raytraced-thickness".into(),
            Method::Raytraced(Primitive::Sphere) => {
                format!("raytraced-sphere-{}", self.opacity.name())
            }
        };
        let suffix = match (self.method, self.opacity) {
            (Method::Raytraced(Primitive::Sphere), _) | (_, OpacityFn::Log) => String::new(),
            (_, f) => format!("-{}", f.name()),
        };
        let prefix = if self.set == VolumeSet::All {
            "particles-"
        } else {
            ""
        };
        format!("volumes/{prefix}{name}{suffix}")
    }

    /// The test number of the thesis's figure 6.23 this variant reproduces.
    pub fn thesis_test(&self) -> Option<u32> {
        if self.set != VolumeSet::Single {
            return None;
        }
        let slice_rank = |n: u32| {
            [5, 9, 19, 39, 79]
                .iter()
                .position(|&m| m == n)
                .map(|p| p as u32)
        };
        match (self.method, self.opacity) {
            (Method::Billboard, OpacityFn::Log) => Some(1),
            (
                Method::Slices {
                    count,
                    float_buffer,
                },
                OpacityFn::Log,
            ) => slice_rank(count).map(|r| if float_buffer { 7 + r } else { 2 + r }),
            (Method::Raytraced(Primitive::Constant), OpacityFn::Log) => Some(12),
            (Method::Raytraced(Primitive::Linear), OpacityFn::Log) => Some(13),
            (Method::Raytraced(Primitive::Sphere), OpacityFn::Log) => Some(14),
            (Method::Raytraced(Primitive::Sphere), OpacityFn::Linear) => Some(15),
            (Method::Raytraced(Primitive::Sphere), OpacityFn::Sqrt) => Some(16),
            (Method::Raytraced(Primitive::Texture), OpacityFn::Log) => Some(17),
            _ => None,
        }
    }

    pub(super) fn description(&self) -> String {
        let what = match self.method {
            Method::Billboard => "simple billboard, no volume (6.3.1)".to_string(),
            Method::DepthFade => "engine baseline: depth-fade soft particle, the textured \
                                  billboard faded by (scene depth - billboard depth) / fade"
                .to_string(),
            Method::Slices {
                count,
                float_buffer,
            } => format!(
                "{count} camera-facing slices forming a sphere, perspective-corrected texture \
                 coordinates, {} colour buffer (6.3.2)",
                if float_buffer {
                    "16-bit float"
                } else {
                    "8-bit"
                }
            ),
            Method::Raytraced(p) => format!(
                "ray-traced {} against the scene depth (6.3.3)",
                match p {
                    Primitive::Constant => "constant-thickness volume",
                    Primitive::Linear => "linearly decreasing thickness volume",
                    Primitive::Sphere => "sphere",
                    Primitive::Texture => "thickness-texture volume",
                }
            ),
        };
        let set = match self.set {
            VolumeSet::Single => "the scene's large volumes",
            VolumeSet::All => "every volume as a particle system",
        };
        let test = self
            .thesis_test()
            .map(|t| format!(", thesis fig. 6.23 test {t}"))
            .unwrap_or_default();
        format!(
            "{what}; {} path-length-to-opacity; {set}{test}",
            self.opacity.name()
        )
    }
}

/// The 17 variants of the thesis's figure 6.23, in its order.
pub fn thesis_variants() -> Vec<Variant> {
    let single = |method, opacity| Variant {
        method,
        opacity,
        set: VolumeSet::Single,
    };
    let mut out = vec![single(Method::Billboard, OpacityFn::Log)];
    for float_buffer in [false, true] {
        for count in [5, 9, 19, 39, 79] {
            out.push(single(
                Method::Slices {
                    count,
                    float_buffer,
                },
                OpacityFn::Log,
            ));
        }
    }
    out.push(single(
        Method::Raytraced(Primitive::Constant),
        OpacityFn::Log,
    ));
    out.push(single(Method::Raytraced(Primitive::Linear), OpacityFn::Log));
    for f in [OpacityFn::Log, OpacityFn::Linear, OpacityFn::Sqrt] {
        out.push(single(Method::Raytraced(Primitive::Sphere), f));
    }
    out.push(single(
        Method::Raytraced(Primitive::Texture),
        OpacityFn::Log,
    ));
    out
}

/// The particle-system versions: every volume of the scene, sorted back to front.
pub fn particle_variants() -> Vec<Variant> {
    let all = |method| Variant {
        method,
        opacity: OpacityFn::Log,
        set: VolumeSet::All,
    };
    vec![
        all(Method::Billboard),
        all(Method::Slices {
            count: 9,
            float_buffer: false,
        }),
        all(Method::Slices {
            count: 9,
            float_buffer: true,
        }),
        all(Method::Raytraced(Primitive::Sphere)),
        all(Method::Raytraced(Primitive::Texture)),
    ]
}

/// The engine baseline: depth-fade soft particles on the large volumes and on every volume.
pub fn engine_variants() -> Vec<Variant> {
    [VolumeSet::Single, VolumeSet::All]
        .into_iter()
        .map(|set| Variant {
            method: Method::DepthFade,
            opacity: OpacityFn::Log,
            set,
        })
        .collect()
}

/// Every variant this crate registers.
pub fn all_variants() -> Vec<Variant> {
    let mut v = thesis_variants();
    v.extend(particle_variants());
    v.extend(engine_variants());
    v
}
