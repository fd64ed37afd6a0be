//! The built-in named scenes: the equal ground every technique is compared on.
//!
//! A scene is named by a spec `name` or `name:key=value,key=value`, for example
//! `cornell-sphere:material=mirror` or `city:buildings=64`. Each scene declares its
//! parameters (name, default, meaning) so `harness list --params` and `harness sweep` can
//! read them.
//!
//! # Layout: one file per scene (family)
//!
//! | file | scenes |
//! | --- | --- |
//! | [`cornell`] | `cornell-sphere`, `cornell-box` (one room, two variants) |
//! | [`bunny`] | `refraction-bunny` |
//! | [`chess`] | `chess` (and the piece meshes the refractor-map techniques build maps of) |
//! | [`city`] | `city` (and the interior generators the `interior-mapping` crate reuses) |
//! | [`smoke`] | `smoke` |
//! | [`pool`] | `pool`, `murky-pool` (a swimming pool with a glass height-field water surface; the murky one's water scatters) |
//! | [`hu_qin`] | `hu-qin` (one glass refractor, possibly deforming, before nearby meshes: Hu and Qin 2006) |
//! | [`textures`] | texture helpers any scene may use (`checker_texture`, `from_texels`) |
//! | [`assets`] | meshes of the embedded assets any scene may use (`bunny_mesh`) |
//! | this file | the registry ([`builtin_scenes`], [`build`]) and spec parsing |
//!
//! A scene file builds its scene from typed arguments and imports only from [`textures`],
//! [`assets`], [`crate::mesh`] and the scene model, never from another scene file or from this
//! registry.
//! **Adding a scene is one new file plus one registry entry**: write `chess.rs` with a
//! `pub fn chess(..) -> Result<Scene, SceneError>`, add `pub mod chess;` below and one
//! `Builtin` to `registry()` (its [`SceneInfo`] with the declared parameters, and the
//! function that reads them from [`SceneArgs`] and calls the scene file). Everything else
//! (`scene::load`, `harness list`, `harness compare`'s default scene list, the registry tests)
//! picks the new entry up from there.

pub mod assets;
pub mod bunny;
pub mod chess;
pub mod city;
pub mod cornell;
pub mod hu_qin;
pub mod pool;
pub mod smoke;
pub mod textures;

use crate::{Scene, SceneError};
use std::collections::BTreeMap;

/// A declared scene parameter.
#[derive(Clone, Debug)]
pub struct SceneParam {
    pub name: &'static str,
    pub default: &'static str,
    pub help: &'static str,
    /// The accepted values of a numeric parameter, inclusive; `None` for a word (`material`),
    /// which its scene checks against its own list.
    pub range: Option<(f64, f64)>,
    /// Only whole numbers are accepted.
    pub integer: bool,
}

impl SceneParam {
    /// The declared range as `harness list --params` shows it (`[2, 4096] integer`).
    pub fn range_text(&self) -> String {
        match self.range {
            Some((lo, hi)) if self.integer => format!("[{lo}, {hi}] integer"),
            Some((lo, hi)) => format!("[{lo}, {hi}]"),
            None => "word".into(),
        }
    }
}

/// A built-in scene and what can be changed about it.
#[derive(Clone, Debug)]
pub struct SceneInfo {
    pub name: &'static str,
    pub description: &'static str,
    pub params: Vec<SceneParam>,
}

/// One registry entry: what the scene declares and how it is built from its parameters.
struct Builtin {
    info: SceneInfo,
    build: fn(&SceneArgs) -> Result<Scene, SceneError>,
}

/// A scene's parameters as given in its spec, with the declared defaults for the rest.
pub struct SceneArgs<'a> {
    info: &'a SceneInfo,
    params: &'a BTreeMap<String, String>,
}

impl SceneArgs<'_> {
    /// The value of `key`: the spec's, else the declared default (empty if undeclared).
    pub fn get(&self, key: &str) -> String {
        self.params.get(key).cloned().unwrap_or_else(|| {
            self.info
                .params
                .iter()
                .find(|p| p.name == key)
                .map(|p| p.default.to_string())
                .unwrap_or_default()
        })
    }

    /// The value of `key` as a finite number within the parameter's declared range (and
    /// whole, for an integer parameter).
    pub fn num(&self, key: &str) -> Result<f32, SceneError> {
        let text = self.get(key);
        let value = num(&text, key)?;
        let Some(declared) = self.info.params.iter().find(|p| p.name == key) else {
            return Ok(value);
        };
        if let Some((lo, hi)) = declared.range
            && !(lo..=hi).contains(&(value as f64))
        {
            return Err(SceneError::BadParam(format!(
                "{key}={text} is outside its range [{lo}, {hi}]"
            )));
        }
        if declared.integer && value.fract() != 0.0 {
            return Err(SceneError::BadParam(format!(
                "{key}={text} is not a whole number"
            )));
        }
        Ok(value)
    }
}

/// A parameter that is a word (checked by its scene).
fn word(name: &'static str, default: &'static str, help: &'static str) -> SceneParam {
    SceneParam {
        name,
        default,
        help,
        range: None,
        integer: false,
    }
}

/// A real parameter accepted in `[min, max]`.
fn real(
    name: &'static str,
    default: &'static str,
    (min, max): (f64, f64),
    help: &'static str,
) -> SceneParam {
    SceneParam {
        range: Some((min, max)),
        ..word(name, default, help)
    }
}

/// A whole-number parameter accepted in `[min, max]`.
fn integer(
    name: &'static str,
    default: &'static str,
    (min, max): (f64, f64),
    help: &'static str,
) -> SceneParam {
    SceneParam {
        integer: true,
        ..real(name, default, (min, max), help)
    }
}

/// Most buildings in `city`: a 64 x 64 grid, 2 km across.
pub const MAX_BUILDINGS: usize = 4096;
/// Most particles in `smoke`'s cloud (each one is a volume every renderer visits).
pub const MAX_PARTICLES: usize = 1024;

/// A refractor's index of refraction checked against [`crate::Material::IOR_RANGE`].
fn check_ior(ior: f32) -> Result<(), SceneError> {
    let r = crate::Material::IOR_RANGE;
    if r.contains(&ior) {
        return Ok(());
    }
    Err(SceneError::BadParam(format!(
        "ior={ior} is outside [{}, {}]",
        r.start(),
        r.end()
    )))
}

/// The registry: every built-in scene, in the order `harness list` shows them.
fn registry() -> Vec<Builtin> {
    let mut all = room_and_object_scenes();
    all.extend(outdoor_and_water_scenes());
    all
}

/// `cornell-sphere` and `cornell-box`, with the parameters they share.
fn cornell_rooms() -> Vec<Builtin> {
    let material = |default| word("material", default, cornell::MATERIAL_HELP);
    let sphere_x = || real("sphere_x", "0", (-0.6, 0.6), "sphere centre x (m)");
    let light = || word("light", "point", cornell::LIGHT_HELP);
    let camera = || word("camera", "pinhole", cornell::CAMERA_HELP);
    let screen = || word("screen", "none", cornell::SCREEN_HELP);
    vec![
        Builtin {
            info: SceneInfo {
                name: "cornell-sphere",
                description: "closed Cornell-style room, one point light, one sphere that moves \
                              along x over the camera path",
                params: vec![
                    material("glass-1.5"),
                    sphere_x(),
                    light(),
                    camera(),
                    screen(),
                ],
            },
            build: |a| {
                let scene = cornell::cornell_sphere(&a.get("material"), a.num("sphere_x")?)?;
                screened(viewed(lit(scene, a, "spot", cornell::spot_lit)?, a)?, a)
            },
        },
        Builtin {
            info: SceneInfo {
                name: "cornell-box",
                description: "the same room with a tall box that makes it concave (the distance-\
                              impostor paper's hard case)",
                params: vec![material("mirror"), sphere_x(), light(), camera(), screen()],
            },
            build: |a| {
                let scene = cornell::cornell_box(&a.get("material"), a.num("sphere_x")?)?;
                screened(viewed(lit(scene, a, "spot", cornell::spot_lit)?, a)?, a)
            },
        },
    ]
}

/// The Cornell rooms, the bunny, the chess board and the city (the papers' scenes).
fn room_and_object_scenes() -> Vec<Builtin> {
    let ior = crate::Material::IOR_RANGE;
    let mut all = cornell_rooms();
    all.extend(vec![
        Builtin {
            info: SceneInfo {
                name: "refraction-bunny",
                description: "a glass Stanford bunny in front of a checker wall with nearby boxes",
                params: vec![real(
                    "ior",
                    "1.5",
                    (*ior.start() as f64, *ior.end() as f64),
                    "bunny index of refraction",
                )],
            },
            build: |a| bunny::refraction_bunny(a.num("ior")?),
        },
        Builtin {
            info: SceneInfo {
                name: "chess",
                description: "a chessboard with 32 glass pieces and a glass sphere, one point \
                              light; the white king's pawn moves e2-e4 over the camera path",
                params: vec![
                    word("material", "glass", chess::MATERIAL_HELP),
                    real(
                        "ior",
                        "1.5",
                        (*ior.start() as f64, *ior.end() as f64),
                        "index of refraction of the glass",
                    ),
                    integer(
                        "slices",
                        "24",
                        (3.0, 256.0),
                        "vertices round each cross-section of a piece",
                    ),
                ],
            },
            build: |a| chess::chess(&a.get("material"), a.num("ior")?, a.num("slices")? as u32),
        },
        Builtin {
            info: SceneInfo {
                name: "city",
                description: "a grid of box buildings plus a cylinder and a sphere building; \
                              camera path along a street",
                params: vec![
                    integer(
                        "buildings",
                        "16",
                        (2.0, MAX_BUILDINGS as f64),
                        "number of buildings",
                    ),
                    real(
                        "rooms_per_building",
                        "1000",
                        (1.0, 1e8),
                        "rooms per building; sets the room size of each hull",
                    ),
                    integer(
                        "interiors",
                        "1",
                        (0.0, 1.0),
                        "1: the (at most 3) box buildings beside the start of the street get \
                         real interiors (window holes, room planes) when rooms_per_building <= \
                         100000; 0: none",
                    ),
                ],
            },
            build: |a| {
                city::city(
                    a.num("buildings")? as usize,
                    a.num("rooms_per_building")?,
                    a.num("interiors")?,
                )
            },
        },
    ]);
    all
}

/// The smoke, the pools and Hu and Qin's scene.
fn outdoor_and_water_scenes() -> Vec<Builtin> {
    let ior = crate::Material::IOR_RANGE;
    vec![
        Builtin {
            info: SceneInfo {
                name: "smoke",
                description: "ground plane and posts/logs crossing a large soft volume, plus a \
                              particle cloud",
                params: vec![integer(
                    "particles",
                    "24",
                    (0.0, MAX_PARTICLES as f64),
                    "particles in the cloud",
                )],
            },
            build: |a| Ok(smoke::smoke(a.num("particles")? as usize)),
        },
        Builtin {
            info: SceneInfo {
                name: "pool",
                description: "a tiled swimming pool under the sun: glass height-field water (drifting \
                              waves), a ladder and a ball in the water; seen by a swimmer \
                              under the surface",
                params: pool_params("0"),
            },
            build: build_pool,
        },
        Builtin {
            info: SceneInfo {
                name: "murky-pool",
                description: "the pool with scattering water (a homogeneous medium below the \
                              waves): light shafts under the surface",
                params: pool_params("0.2"),
            },
            build: build_pool,
        },
        Builtin {
            info: SceneInfo {
                name: "hu-qin",
                description: "one glass refractor (sphere, teapot, bunny or a deforming sphere) \
                              before nearby coloured meshes, casting a caustic on the floor \
                              (Hu and Qin 2006)",
                params: vec![
                    word("refractor", "sphere", hu_qin::REFRACTOR_HELP),
                    real(
                        "ior",
                        "1.15",
                        (*ior.start() as f64, *ior.end() as f64),
                        "index of refraction of the refractor",
                    ),
                    integer(
                        "gold_sphere",
                        "0",
                        (0.0, 1.0),
                        "1: the small sphere beside the refractor is gold (recursive \
                         reflections and refractions)",
                    ),
                    word(
                        "environment",
                        "near",
                        "near: nearby meshes, a floor and a wall; distant: the refractor alone \
                         in a checkered hall 60 m across (section 2.1's distant environment)",
                    ),
                    integer(
                        "lights",
                        "1",
                        (1.0, 2.0),
                        "2: a second light on the right (figure 27)",
                    ),
                    integer(
                        "metal",
                        "0",
                        (0.0, 1.0),
                        "1: the refractor is polished gold (reflective caustics, figure 26)",
                    ),
                ],
            },
            build: |a| {
                let distant = match a.get("environment").as_str() {
                    "near" => false,
                    "distant" => true,
                    other => {
                        return Err(SceneError::BadParam(format!(
                            "environment={other} is not near or distant"
                        )));
                    }
                };
                hu_qin::hu_qin(&hu_qin::HuQin {
                    refractor: a.get("refractor"),
                    ior: a.num("ior")?,
                    gold_sphere: a.num("gold_sphere")? != 0.0,
                    distant,
                    lights: a.num("lights")? as u32,
                    metal: a.num("metal")? != 0.0,
                })
            },
        },
    ]
}

/// The parameters of `pool` and `murky-pool` (which differ in the default extinction).
fn pool_params(extinction: &'static str) -> Vec<SceneParam> {
    let anisotropy = crate::medium::MAX_ANISOTROPY as f64;
    vec![
        word(
            "view",
            "below",
            "below: under the surface (caustics seen directly); above: from the pool's end (the \
             reference has no caustics seen through the surface)",
        ),
        real(
            "extinction",
            extinction,
            (0.0, 10.0),
            "extinction of the water per metre (0: clear water, no medium)",
        ),
        real(
            "albedo",
            "0.9",
            (0.0, 1.0),
            "single-scattering albedo of the water (scattering / extinction)",
        ),
        real(
            "anisotropy",
            "0.2",
            (-anisotropy, anisotropy),
            "Henyey-Greenstein asymmetry g of the water's scattering",
        ),
        word("light", "point", pool::LIGHT_HELP),
    ]
}

/// A scene under its `light` parameter: `point` (its own light) or `other`, the lighting
/// `relight` gives it.
fn lit(
    scene: Scene,
    a: &SceneArgs,
    other: &str,
    relight: fn(Scene) -> Scene,
) -> Result<Scene, SceneError> {
    match a.get("light").as_str() {
        "point" => Ok(scene),
        w if w == other => Ok(relight(scene)),
        w => Err(SceneError::BadParam(format!(
            "light={w}: expected point or {other}"
        ))),
    }
}

/// A Cornell room under its `camera` parameter: `pinhole` (its own view) or `orthographic`.
fn viewed(scene: Scene, a: &SceneArgs) -> Result<Scene, SceneError> {
    match a.get("camera").as_str() {
        "pinhole" => Ok(scene),
        "orthographic" => Ok(cornell::orthographic_view(scene)),
        w => Err(SceneError::BadParam(format!(
            "camera={w}: expected pinhole or orthographic"
        ))),
    }
}

/// A Cornell room under its `screen` parameter: `none`, or `perforated` (an alpha cut-out).
fn screened(scene: Scene, a: &SceneArgs) -> Result<Scene, SceneError> {
    match a.get("screen").as_str() {
        "none" => Ok(scene),
        "perforated" => Ok(cornell::perforated_screen(scene)),
        w => Err(SceneError::BadParam(format!(
            "screen={w}: expected none or perforated"
        ))),
    }
}

/// `pool` or `murky-pool` from its parameters.
fn build_pool(a: &SceneArgs) -> Result<Scene, SceneError> {
    let scene = pool::pool(&a.get("view"), pool_murk(a)?)?;
    lit(scene, a, "sun", pool::sun_lit)
}

/// The water's scattering from a pool spec.
fn pool_murk(a: &SceneArgs) -> Result<Option<pool::Murk>, SceneError> {
    Ok(Some(pool::Murk {
        extinction: a.num("extinction")?,
        albedo: a.num("albedo")?,
        anisotropy: a.num("anisotropy")?,
    }))
}

/// The built-in scenes under lights other than point lights: the tests that hold every
/// renderer to every built-in scene hold them to these too (the pool from above as well, where
/// the sun lights surfaces directly; below the water only its caustics do).
pub const LIGHT_VARIANTS: [&str; 5] = [
    "cornell-sphere:light=spot",
    "cornell-box:light=spot",
    "pool:light=sun",
    "pool:view=above,light=sun",
    "murky-pool:light=sun",
];

/// The built-in scenes seen by an orthographic camera, which the reference, the ray tracer and
/// the raster baseline render and every other technique refuses with the reason.
pub const CAMERA_VARIANTS: [&str; 2] = [
    "cornell-sphere:camera=orthographic",
    "cornell-box:camera=orthographic,light=spot",
];

/// The built-in scenes with an alpha cut-out (`Material::Diffuse`'s `cutout`), which every
/// renderer draws with its holes.
pub const CUTOUT_VARIANTS: [&str; 1] = ["cornell-box:screen=perforated"];

/// Every built-in scene.
pub fn builtin_scenes() -> Vec<SceneInfo> {
    registry().into_iter().map(|b| b.info).collect()
}

/// Parses `name` or `name:key=value,...` into the name and its parameters.
pub fn parse_spec(spec: &str) -> Result<(String, BTreeMap<String, String>), SceneError> {
    let (name, rest) = spec.split_once(':').unwrap_or((spec, ""));
    let mut params = BTreeMap::new();
    for pair in rest.split(',').filter(|s| !s.is_empty()) {
        let (k, v) = pair
            .split_once('=')
            .ok_or_else(|| SceneError::BadParam(format!("\"{pair}\" is not key=value")))?;
        params.insert(k.trim().to_string(), v.trim().to_string());
    }
    Ok((name.to_string(), params))
}

/// Builds a built-in scene by name with the given parameters (unknown parameters are errors).
pub fn build(name: &str, params: &BTreeMap<String, String>) -> Result<Scene, SceneError> {
    let entry = registry()
        .into_iter()
        .find(|s| s.info.name == name)
        .ok_or_else(|| SceneError::UnknownScene(name.to_string(), scene_names()))?;
    let info = &entry.info;
    for key in params.keys() {
        if !info.params.iter().any(|p| p.name == key) {
            let known: Vec<_> = info.params.iter().map(|p| p.name).collect();
            return Err(SceneError::BadParam(format!(
                "scene {name} has no parameter \"{key}\" (it has: {})",
                known.join(", ")
            )));
        }
    }
    let mut scene = (entry.build)(&SceneArgs { info, params })?;
    scene.name = spec_string(name, params);
    scene.validate()?;
    Ok(scene)
}

fn spec_string(name: &str, params: &BTreeMap<String, String>) -> String {
    if params.is_empty() {
        return name.to_string();
    }
    let kv: Vec<String> = params.iter().map(|(k, v)| format!("{k}={v}")).collect();
    format!("{name}:{}", kv.join(","))
}

fn scene_names() -> String {
    builtin_scenes()
        .iter()
        .map(|s| s.name)
        .collect::<Vec<_>>()
        .join(", ")
}

fn num(value: &str, key: &str) -> Result<f32, SceneError> {
    value
        .parse::<f32>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| SceneError::BadParam(format!("{key}={value} is not a finite number")))
}
