//! The one small trait every technique implements, and what the harness hands it.
//!
//! Like a wgpu example, a technique declares what it needs (features) and which scenes it
//! can render; like a Falcor render pass, it declares its parameters by name with defaults
//! and ranges (what `harness list --params` and `harness sweep` read). `prepare` builds its
//! maps once per scene; `render` records one frame into the harness's encoder.

use crate::{Camera, GpuScene, Scene};
use gpu::{GpuError, Target};

/// A declared, sweepable parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct Param {
    pub name: &'static str,
    pub default: f64,
    pub min: f64,
    pub max: f64,
    /// Whether only integer values make sense (iteration counts, resolutions).
    pub integer: bool,
    pub help: &'static str,
}

impl Param {
    /// A parameter `name` with its `default`, accepted in `[min, max]` (whole numbers only when
    /// `integer`), and one line of `help`.
    pub const fn new(
        name: &'static str,
        default: f64,
        (min, max): (f64, f64),
        integer: bool,
        help: &'static str,
    ) -> Self {
        Self {
            name,
            default,
            min,
            max,
            integer,
            help,
        }
    }
}

/// A setting a parameter reads and writes, as the `f64` of [`Technique::set_param`]: whole
/// counts (`u32`), reals (`f32`) and switches (`bool`, 0 or 1).
pub trait ParamValue {
    /// The setting as the parameter's value.
    fn read(&self) -> f64;
    /// Sets it from a value already checked against the parameter's range.
    fn write(&mut self, value: f64);
    /// Whether only whole numbers make sense.
    fn integer(&self) -> bool;
}

impl ParamValue for u32 {
    fn read(&self) -> f64 {
        *self as f64
    }
    fn write(&mut self, value: f64) {
        *self = value as u32;
    }
    fn integer(&self) -> bool {
        true
    }
}

impl ParamValue for u64 {
    fn read(&self) -> f64 {
        *self as f64
    }
    fn write(&mut self, value: f64) {
        *self = value as u64;
    }
    fn integer(&self) -> bool {
        true
    }
}

impl ParamValue for f32 {
    fn read(&self) -> f64 {
        *self as f64
    }
    fn write(&mut self, value: f64) {
        *self = value as f32;
    }
    fn integer(&self) -> bool {
        false
    }
}

impl ParamValue for bool {
    fn read(&self) -> f64 {
        f64::from(u8::from(*self))
    }
    fn write(&mut self, value: f64) {
        *self = value != 0.0;
    }
    fn integer(&self) -> bool {
        true
    }
}

/// `setting` where `condition` holds (a parameter of some variants only), else `None`.
pub fn setting_if(condition: bool, setting: &mut impl ParamValue) -> Option<&mut dyn ParamValue> {
    if condition { Some(setting) } else { None }
}

/// One parameter of a settings type `S`, declared once: its name, range and help, and the
/// setting it reads and writes. `setting` answers `None` where these settings lack it (a
/// parameter of another variant: caustics' on a variant without caustics), and the
/// parameter is then not declared.
pub struct Declared<S> {
    pub name: &'static str,
    pub range: (f64, f64),
    pub help: &'static str,
    pub setting: fn(&mut S) -> Option<&mut dyn ParamValue>,
}

impl<S> Declared<S> {
    /// Parameter `name` in `[min, max]` with one line of `help`, reading and writing the
    /// setting `setting` finds.
    pub const fn new(
        name: &'static str,
        (min, max): (f64, f64),
        help: &'static str,
        setting: fn(&mut S) -> Option<&mut dyn ParamValue>,
    ) -> Self {
        Self {
            name,
            range: (min, max),
            help,
            setting,
        }
    }
}

/// A family's settings with their parameters declared once ([`Settings::DECLARED`]): the
/// parameter list (with each setting's current value as its default) and `set` follow from
/// it, so a parameter cannot be listed without being settable, or settable without being
/// listed.
pub trait Settings: Clone + 'static {
    /// Every parameter these settings may have, in the order [`Settings::params`] lists them.
    const DECLARED: &'static [Declared<Self>];

    /// The parameters these settings have, each with its current value as its default.
    /// Settings that hold settings of a shared layer (a search's maps, the section-5
    /// impostors') override it to list those too.
    fn params(&self) -> Vec<Param> {
        declared_params(self)
    }

    /// Sets parameter `name` (already checked against its range by [`check_param`]) and says
    /// whether these settings have it.
    fn set(&mut self, name: &str, value: f64) -> bool {
        declared_set(self, name, value)
    }
}

/// The parameters of [`Settings::DECLARED`] that `settings` has, each with its current value.
pub fn declared_params<S: Settings>(settings: &S) -> Vec<Param> {
    let mut probe = settings.clone();
    S::DECLARED
        .iter()
        .filter_map(|d| {
            let value = (d.setting)(&mut probe)?;
            let (read, integer) = (value.read(), value.integer());
            Some(Param::new(d.name, read, d.range, integer, d.help))
        })
        .collect()
}

/// Sets parameter `name` of [`Settings::DECLARED`] if `settings` has it.
pub fn declared_set<S: Settings>(settings: &mut S, name: &str, value: f64) -> bool {
    // A name may be declared more than once, with the help of each kind of variant: the
    // first entry these settings have is the one.
    let mut probe = settings.clone();
    let applies = |d: &&Declared<S>| d.name == name && (d.setting)(&mut probe).is_some();
    match S::DECLARED.iter().find(applies) {
        Some(declared) => {
            let setting = (declared.setting)(settings).expect("the probe has it");
            setting.write(value);
            true
        }
        None => false,
    }
}

/// The `id`, `description` and `representative` of a [`Technique`] impl whose type keeps
/// them in fields of those names (`id: String`, `description: String`, `representative:
/// bool`): what each variant type configured by its constructor writes alike.
#[macro_export]
macro_rules! named_variant {
    () => {
        fn id(&self) -> String {
            self.id.clone()
        }
        fn description(&self) -> String {
            self.description.clone()
        }
        fn representative(&self) -> bool {
            self.representative
        }
    };
}

/// The `params` and `set_param` of a [`Technique`] impl whose parameters are its field
/// `$settings` (a [`Settings`]): a parameter set drops the prepared `$state` (an `Option`),
/// which the next `prepare` or frame makes again with it.
#[macro_export]
macro_rules! declared_params {
    ($settings:ident, $state:ident) => {
        fn params(&self) -> Vec<$crate::Param> {
            $crate::Settings::params(&self.$settings)
        }
        fn set_param(&mut self, name: &str, value: f64) -> $crate::TechniqueResult<()> {
            let id = $crate::Technique::id(self);
            $crate::technique::set_checked(&id, &mut self.$settings, name, value)?;
            self.$state = None;
            Ok(())
        }
    };
}

/// Checks `value` against the declared parameters of `settings` and sets it: what a
/// technique's [`Technique::set_param`] does with settings of its own.
pub fn set_checked(
    id: &str,
    settings: &mut impl Settings,
    name: &str,
    value: f64,
) -> TechniqueResult<()> {
    check_param(id, &settings.params(), name, value)?;
    // A listed parameter the settings cannot set is a bug in the family's declaration, not
    // an input error.
    assert!(
        settings.set(name, value),
        "{id}: parameter {name} is listed by params() but not settable"
    );
    Ok(())
}

/// What is being rendered this frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    pub camera: Camera,
    /// Seconds along the scene's camera path / object motion.
    pub time: f32,
    pub width: u32,
    pub height: u32,
}

/// The per-frame GPU recording context (it lives in `gpu`, which needs it too).
pub use gpu::Frame;

/// Errors a technique reports; each is one sentence for the user.
#[derive(Debug, thiserror::Error)]
pub enum TechniqueError {
    #[error(transparent)]
    Gpu(#[from] GpuError),
    #[error(transparent)]
    Scene(#[from] crate::SceneError),
    #[error("technique {0} has no parameter \"{1}\" (it has: {2})")]
    UnknownParam(String, String, String),
    #[error("parameter {0}={1} is outside its range [{2}, {3}]")]
    ParamOutOfRange(String, f64, f64, f64),
    #[error("{0}")]
    Unsupported(String),
    #[error("technique {0} rendered before prepare(): call prepare() once per scene first")]
    NotPrepared(String),
    #[error("{0}")]
    OverBudget(String),
}

/// GPU memory the per-object maps of one technique (environment cube maps, distance
/// impostors, refractor maps) may take together.
pub const MAP_BUDGET_BYTES: u64 = 1 << 30;

/// Fails, naming the limit, when `objects` per-object maps of `bytes_each` bytes exceed
/// [`MAP_BUDGET_BYTES`]: the documented strategy of every technique that keeps a map per
/// object is this clear refusal (the reference and the raster pass have no such limit), with
/// the largest object count that fits and the parameter that trades resolution for it.
pub fn check_map_budget(
    technique: &str,
    objects: usize,
    bytes_each: u64,
    resolution_param: &str,
) -> TechniqueResult<()> {
    let total = objects as u64 * bytes_each;
    if total <= MAP_BUDGET_BYTES {
        return Ok(());
    }
    Err(TechniqueError::OverBudget(format!(
        "{technique} keeps {:.1} MB of maps per specular object; the scene's {objects} need \
         {:.2} GB, over its {} MB budget (at most {} objects fit; lower `{resolution_param}` to fit more)",
        bytes_each as f64 / 1e6,
        total as f64 / 1e9,
        MAP_BUDGET_BYTES >> 20,
        MAP_BUDGET_BYTES / bytes_each.max(1)
    )))
}

pub type TechniqueResult<T> = Result<T, TechniqueError>;

/// Refuses, with the reason, a scene lit by a spot or directional light for a technique whose
/// paper emits its photons from a point light (a raster of the casters from the light's
/// position, one photon per texel, each carrying the same share of the light's intensity):
/// `what` says what of the technique needs it. The reference and the ray tracer, and every
/// technique's shading of diffuse surfaces, take all three kinds.
pub fn point_lights_only(technique: &str, what: &str, scene: &crate::Scene) -> TechniqueResult<()> {
    match scene
        .lights
        .iter()
        .find(|l| l.kind != crate::LightKind::Point)
    {
        None => Ok(()),
        Some(l) => Err(TechniqueError::Unsupported(format!(
            "{technique} needs point lights ({what}); the scene's light \"{}\" is a {} light",
            l.name,
            l.kind_name()
        ))),
    }
}

/// Refuses, with the reason, a scene seen by an orthographic camera for a technique that does
/// not render one ([`Technique::orthographic_camera`]).
pub fn orthographic_refusal(
    technique: &dyn Technique,
    scene: &crate::Scene,
) -> TechniqueResult<()> {
    if technique.orthographic_camera() || !scene.camera.is_orthographic() {
        return Ok(());
    }
    Err(TechniqueError::Unsupported(format!(
        "{} {PINHOLE_ONLY} (its shaders derive view rays from the eye point); the scene's \
         camera is orthographic, which the reference, the ray tracer and raster render",
        technique.id()
    )))
}

/// The words of [`orthographic_refusal`]'s reason after the technique's id.
pub const PINHOLE_ONLY: &str = "needs a pinhole camera";

/// Where a technique's frame time comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Timing {
    /// Recorded GPU work, timed by the harness with timestamp queries.
    Gpu,
    /// CPU work (the reference): wall-clock time of `render`.
    Cpu,
}

pub trait Technique {
    /// Stable identifier, `family/variant`, e.g. "impostors/false-position-4".
    fn id(&self) -> String;
    /// One line for `harness list`.
    fn description(&self) -> String;
    /// Declared parameters with defaults and ranges.
    fn params(&self) -> Vec<Param> {
        Vec::new()
    }
    /// Sets a declared parameter (validated by [`check_param`]).
    fn set_param(&mut self, name: &str, value: f64) -> TechniqueResult<()> {
        check_param(&self.id(), &self.params(), name, value)
    }
    /// Whether the default `harness compare` runs this variant. A family's exhaustive rest
    /// (every iteration count, every slice count: what `harness sweep` covers) says `false`;
    /// `harness compare --all-variants`, or naming the variant in `--techniques`, runs it.
    fn representative(&self) -> bool {
        true
    }
    /// Device features without which the technique cannot run (the harness skips it, with
    /// the reason, on an adapter that lacks them).
    fn required_features(&self) -> gpu::wgpu::Features {
        gpu::wgpu::Features::empty()
    }
    /// Whether the technique can render this scene (for example: it has a refractor).
    fn supports(&self, scene: &Scene) -> bool;
    /// Whether the technique renders an orthographic camera's view
    /// ([`crate::Camera::orthographic`]). The techniques' shaders derive their view rays, and
    /// the views of their maps, from the eye point of a pinhole, so only the exact renderers
    /// and the `raster` baseline (whose diffuse model needs no view ray) say yes;
    /// [`orthographic_refusal`] gives the harness the reason for the others.
    fn orthographic_camera(&self) -> bool {
        false
    }
    fn timing(&self) -> Timing {
        Timing::Gpu
    }
    /// Frames of one unchanged view (camera and time) the technique renders before its image
    /// is complete: 1 for a technique that draws its image in one frame (all but one). A
    /// progressive technique, which adds to its image frame after frame while the view stays
    /// (the exact tracer's caustics: new photons every frame, the image their running mean),
    /// says how many; the harness renders that many frames at an error frame's view, each one
    /// timed as a frame, and measures the last.
    fn frames_to_converge(&self) -> u32 {
        1
    }
    /// Variants whose whole frame is a part of this technique's frame (the exact tracer's
    /// caustics contain its Whitted eye pass): a run that measures both measures the contained
    /// one from this one's frames (its image through [`Technique::render_contained`], its
    /// time the sum of the named spans) instead of rendering it again.
    fn contains(&self) -> Vec<Contained> {
        Vec::new()
    }
    /// Draws contained variant `id`'s image of the frame just rendered into `target` (a pass
    /// over what the frame made, recorded into `frame`).
    fn render_contained(
        &mut self,
        _frame: &mut Frame,
        id: &str,
        _target: &Target,
    ) -> TechniqueResult<()> {
        Err(TechniqueError::Unsupported(format!(
            "{} contains no variant {id}",
            self.id()
        )))
    }
    /// The exact image this technique approximates, when that is not the scene's reference
    /// alone; computed on the CPU from `reference` (the scene's reference image of `view`).
    /// `None` (every technique in the workspace today) means the reference. A technique must
    /// not return its own model here: the reference already renders everything the scene
    /// defines, volumes included (participating media, `truth::media`), and the harness's
    /// primary error is against it.
    fn ground_truth(
        &self,
        _scene: &Scene,
        _view: &View,
        _reference: &gpu::HdrImage,
    ) -> Option<gpu::HdrImage> {
        None
    }
    /// Builds per-scene resources; GPU work recorded into `frame` is timed as "prepare".
    fn prepare(&mut self, frame: &mut Frame, scene: &GpuScene) -> TechniqueResult<()>;
    /// Records one frame of `view` into `target` (colour = linear radiance).
    fn render(
        &mut self,
        frame: &mut Frame,
        scene: &GpuScene,
        view: &View,
        target: &Target,
    ) -> TechniqueResult<()>;
}

/// A variant inside another's frame (see [`Technique::contains`]): its id (with its default
/// parameters) and the timer spans of the containing frame that are its own frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Contained {
    pub id: String,
    pub spans: Vec<&'static str>,
}

/// Validates `name=value` against declared parameters: the default `set_param` check, and
/// what an implementation calls before storing the value.
pub fn check_param(id: &str, params: &[Param], name: &str, value: f64) -> TechniqueResult<()> {
    let Some(p) = params.iter().find(|p| p.name == name) else {
        let names: Vec<_> = params.iter().map(|p| p.name).collect();
        return Err(TechniqueError::UnknownParam(
            id.into(),
            name.into(),
            names.join(", "),
        ));
    };
    if !(value >= p.min && value <= p.max) || (p.integer && value.fract() != 0.0) {
        return Err(TechniqueError::ParamOutOfRange(
            name.into(),
            value,
            p.min,
            p.max,
        ));
    }
    Ok(())
}

/// The error of a technique asked to render before [`Technique::prepare`] built its
/// resources: what every technique returns instead of panicking.
pub fn not_prepared(technique: &(impl Technique + ?Sized)) -> TechniqueError {
    TechniqueError::NotPrepared(technique.id())
}

/// A family of techniques, one crate: its variants and the image checks it declares. Each
/// crate exports one as `FAMILY`, and the harness lists every family once
/// (`harness::families()`): its registry and its image checks are both read from that list.
#[derive(Clone, Copy, Debug)]
pub struct Family {
    /// The crate's name; every variant's id but the foundation's starts with it.
    pub name: &'static str,
    /// Fresh instances of every variant.
    pub techniques: fn() -> Vec<Box<dyn Technique>>,
    /// The image checks the family declares (run by the tests crate against the reference).
    pub image_checks: fn() -> Vec<ImageCheck>,
}

/// An image check a technique crate declares, like a wgpu example's image test: `technique`
/// rendered on `scene` at `size` x `size`, at the start, middle and end of the scene's camera
/// path, must stay within `max_flip_mean` and `max_rmse` of the reference (no NaN pixel, ever).
/// The tests crate runs every declared check (`harness::image_checks`); a crate declares one
/// per claim its README makes about its error.
#[derive(Clone, Debug, PartialEq)]
pub struct ImageCheck {
    /// Technique id, `crate/variant`.
    pub technique: &'static str,
    /// Scene spec (`cornell-box`, `cornell-sphere:material=gold`).
    pub scene: &'static str,
    pub size: u32,
    /// Bound on the mean FLIP of every checked frame.
    pub max_flip_mean: f32,
    /// Bound on the RMSE (linear radiance) of every checked frame.
    pub max_rmse: f32,
    /// Why the bounds are what they are: the measured values they were set from, and what a
    /// loose bound tolerates (a failure case the README names, noise of the reference...).
    pub reason: &'static str,
    /// Parameters set on the technique for the check (none: its defaults).
    pub params: &'static [(&'static str, f64)],
    /// Per checked frame (in [`check_times`] order), a tighter RMSE bound than `max_rmse`
    /// where one frame alone needs the loose one (empty: `max_rmse` for every frame). A bound
    /// loose enough for the worst frame can be loose enough for a broken feature too.
    pub rmse_per_frame: &'static [f32],
}

impl ImageCheck {
    /// The default image size of a check: small enough for the software rasterizer of CI.
    pub const SIZE: u32 = 64;

    /// A check at [`ImageCheck::SIZE`] x [`ImageCheck::SIZE`].
    pub const fn new(
        technique: &'static str,
        scene: &'static str,
        max_flip_mean: f32,
        max_rmse: f32,
        reason: &'static str,
    ) -> Self {
        Self {
            technique,
            scene,
            size: Self::SIZE,
            max_flip_mean,
            max_rmse,
            reason,
            params: &[],
            rmse_per_frame: &[],
        }
    }

    /// The check with `params` set on the technique.
    pub const fn with_params(self, params: &'static [(&'static str, f64)]) -> Self {
        Self { params, ..self }
    }

    /// The check with an RMSE bound per checked frame, each at most `max_rmse`.
    pub const fn with_rmse_per_frame(self, rmse_per_frame: &'static [f32]) -> Self {
        Self {
            rmse_per_frame,
            ..self
        }
    }

    /// The RMSE bound of the `frame`-th checked frame.
    pub fn rmse_bound(&self, frame: usize) -> f32 {
        self.rmse_per_frame
            .get(frame)
            .copied()
            .unwrap_or(self.max_rmse)
            .min(self.max_rmse)
    }
}

/// The times an image check renders: start, middle and end of a camera path of `duration`
/// seconds (a still scene: time 0 only).
pub fn check_times(duration: f32) -> Vec<f32> {
    if duration > 0.0 {
        vec![0.0, 0.5 * duration, duration]
    } else {
        vec![0.0]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_frame_without_its_own_rmse_bound_takes_max_rmse() {
        let check = ImageCheck::new("a/b", "cornell-box", 0.1, 0.5, "test");
        assert_eq!(check.rmse_bound(0), 0.5);
        let check = check.with_rmse_per_frame(&[0.1, 0.5, 0.2]);
        assert_eq!(
            [0, 1, 2, 3].map(|f| check.rmse_bound(f)),
            [0.1, 0.5, 0.2, 0.5]
        );
    }
}
