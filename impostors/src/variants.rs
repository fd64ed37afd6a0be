//! The variants of the crate: the searches of Hit() (classic, initial guess, secant and
//! false position at 1 to 8 iterations, split distances), double refraction and the engine's
//! box projection, and the caustics.

use crate::caustics::{CausticPath, CausticSettings};
use crate::technique::{Impostor, Lookup, Mode, Probe, Settings};
use gpu::distance_map::Method;
use scene::Technique;

/// Every variant of this crate, with the ids the harness lists.
pub fn variants() -> Vec<Box<dyn Technique>> {
    let s = Settings::default();
    let mut v = searches(&s);
    v.extend(refraction_and_probes(&s));
    v.extend(caustics(&s));
    v
}

/// The searches of Hit() on one interface: the classic lookup, the initial guess, secant and
/// false position at 1 to 8 iterations, and split distances.
fn searches(s: &Settings) -> Vec<Box<dyn Technique>> {
    let mut v: Vec<Box<dyn Technique>> = Vec::new();
    v.push(Box::new(Impostor::new(
        "impostors/classic",
        "classic environment map (direction-only lookup) on the impostor's own maps and regeneration",
        Settings { mode: Mode::Classic, iterations: 0, ..s.clone() },
    )));
    v.push(Box::new(Impostor::new(
        "impostors/initial-guess",
        "distance impostor, perpendicular + planar guesses only (eqs. 2, 4), no iteration",
        Settings {
            iterations: 0,
            ..s.clone()
        },
    )));
    for n in 1..=8 {
        v.push(Box::new(Impostor::new(
            &format!("impostors/secant-{n}"),
            &format!("distance impostor, {n} secant iterations (eq. 6, previous approximation as partner)"),
            Settings { method: Method::Secant, iterations: n, ..s.clone() },
        )));
    }
    for n in 1..=8 {
        v.push(Box::new(Impostor::new(
            &format!("impostors/false-position-{n}"),
            &format!("distance impostor, {n} false-position iterations (the paper's Hit listing)"),
            Settings {
                method: Method::FalsePosition,
                iterations: n,
                ..s.clone()
            },
        )));
    }
    v.push(Box::new(Impostor::new(
        "impostors/false-position-4-split",
        "false position, 4 iterations, distances in a separate R16Float cube (paper section 6)",
        Settings {
            iterations: 4,
            split: true,
            ..s.clone()
        },
    )));
    v
}

/// Double refraction through the refractor map, and the engine's box-projected probes.
fn refraction_and_probes(s: &Settings) -> Vec<Box<dyn Technique>> {
    let mut v: Vec<Box<dyn Technique>> = Vec::new();
    v.push(Box::new(Impostor::new(
        "impostors/double-refraction",
        "glass: Hit() in a refractor map (normal + distance), refraction out, then Hit() in the \
         environment impostor (section 4); false position, 4 iterations",
        Settings {
            mode: Mode::DoubleRefraction,
            iterations: 4,
            ..s.clone()
        },
    )));
    v.push(Box::new(Impostor::new(
        "impostors/box-projected",
        "engine baseline as shipped: a reflection probe among the specular objects, captured \
         once, looked up by parallax correction against the room's bounds (Lagarde and \
         Zanuttini 2012); one interface like the localized variants",
        Settings {
            lookup: Lookup::BoxProjected,
            probe: Probe::RoomCentre,
            iterations: 0,
            ..s.clone()
        },
    )));
    v.push(Box::new(Impostor::new(
        "impostors/box-projected-object",
        "box projection on the impostor's own map (captured at the object's centre every \
         frame): false-position-4 with the lookup alone replaced",
        Settings {
            lookup: Lookup::BoxProjected,
            iterations: 0,
            ..s.clone()
        },
    )));
    v.push(Box::new(Impostor::new(
        "impostors/box-projected-double",
        "double refraction through the refractor map as impostors/double-refraction, the exit \
         ray looked up by box projection instead of Hit()",
        Settings {
            mode: Mode::DoubleRefraction,
            lookup: Lookup::BoxProjected,
            iterations: 0,
            ..s.clone()
        },
    )));
    v
}

/// Double refraction plus caustics: the paper's light maps and the compute scatter.
fn caustics(s: &Settings) -> Vec<Box<dyn Technique>> {
    let mut v: Vec<Box<dyn Technique>> = Vec::new();
    v.push(Box::new(Impostor::new(
        "impostors/caustics",
        "double-refraction plus caustics as in the paper: photons from the lights through the \
         object, landing points by Hit(), light-map address from a uv/chart cube, Gaussian \
         quads blended into the receivers' light maps (section 5)",
        Settings {
            mode: Mode::DoubleRefraction,
            iterations: 4,
            caustics: Some(CausticSettings::new(CausticPath::LightMap)),
            ..s.clone()
        },
    )));
    v.push(Box::new(Impostor::new(
        "impostors/caustics-compute",
        "double-refraction plus caustics, modern scatter: the same photons added by a compute \
         pass with atomics into a grid indexed by direction from the reference point",
        Settings {
            mode: Mode::DoubleRefraction,
            iterations: 4,
            caustics: Some(CausticSettings::new(CausticPath::Grid)),
            ..s.clone()
        },
    )));
    v
}
