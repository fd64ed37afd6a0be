//! The variants of the crate: the paper's, the baselines, the engine's.

use super::*;

/// The variants of this crate.
pub fn variants() -> Vec<Box<dyn Technique>> {
    configured()
        .into_iter()
        .map(|r| Box::new(r) as Box<dyn Technique>)
        .collect()
}

/// One variant by its name (`hu-qin`, `caustics`, ...), as its concrete type.
pub fn variant(name: &str) -> Option<Refraction> {
    let id = format!("image-space-refraction/{name}");
    configured().into_iter().find(|r| r.id == id)
}

pub(super) fn configured() -> Vec<Refraction> {
    let with = |variant, back_first| Settings {
        variant,
        back_first,
        ..Settings::default()
    };
    let id = |v: &str| format!("image-space-refraction/{v}");
    let nearby = |corrected, recursive| Settings {
        nearby: Some(Nearby {
            corrected,
            recursive,
            ..Nearby::default()
        }),
        ..Settings::default()
    };
    vec![
        (Refraction::new(
            &id("one-interface"),
            "refraction at the visible surface only, the environment map looked up with T1",
            with(Variant::OneInterface, false),
        )),
        (Refraction::new(
            &id("two-interface-baseline"),
            "Wyman 2005: exit point from the view-ray and precomputed normal thickness, \
             back-facing normal (the method Hu and Qin improve)",
            with(Variant::TwoInterfaceBaseline, false),
        )),
        (Refraction::new(
            &id("hu-qin"),
            "Hu and Qin 2006: front/back buffers every frame, silhouette search and angle \
             test, iterative d_T, environment map",
            with(Variant::HuQin, false),
        )),
        (Refraction::new(
            &id("hu-qin-back-first"),
            "hu-qin with section 4's acceleration: back side first, front side when P2 \
             leaves the silhouette",
            with(Variant::HuQin, true),
        ))
        .exhaustive(),
        (Refraction::new(
            &id("nearby-uncorrected"),
            "hu-qin with nearby objects as rectangle impostors (section 2.2), the texel where \
             the ray meets the rectangle",
            nearby(false, false),
        )),
        (Refraction::new(
            &id("baseline-nearby"),
            "two-interface-baseline with the rectangle impostors and depth correction: the \
             paper's figure 11 (Wyman's exit point against Hu and Qin's, nearby geometry)",
            Settings {
                variant: Variant::TwoInterfaceBaseline,
                ..nearby(true, false)
            },
        ))
        .exhaustive(),
        (Refraction::new(
            &id("nearby-corrected"),
            "hu-qin with rectangle impostors and the iterative depth correction from the \
             paper's seed (figures 16-17)",
            nearby(true, false),
        )),
        (Refraction::new(
            &id("recursive"),
            "nearby-corrected with reflective and refractive nearby objects drawn into their \
             textures with their own shading (recursive reflections and refractions)",
            nearby(true, true),
        )),
        (Refraction::new(
            &id("caustics"),
            "nearby-corrected with caustics: photon buffers from the lights through the \
             refractor, caustic textures on the rectangles filtered on the GPU, caustic \
             mapping onto the receivers (section 3)",
            Settings {
                caustics: Some(CausticSettings::default()),
                ..nearby(true, false)
            },
        )),
        (Refraction::new(
            &id("thickness-proxy"),
            "engine baseline: screen-space refraction with a thickness proxy (HDRP's sphere \
             model: one bend, a sphere's chord, the scene colour buffer)",
            with(Variant::ThicknessProxy, false),
        )),
        (Refraction::new(
            &id("thickness-proxy-probe"),
            "engine baseline as shipped: thickness-proxy with the room's reflection probe (one \
             box-projected probe captured once, no per-object maps): any number of glass \
             objects",
            Settings {
                room_probe: true,
                ..with(Variant::ThicknessProxy, false)
            },
        )),
    ]
}
