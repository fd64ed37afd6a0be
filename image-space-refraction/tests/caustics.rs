//! The caustic passes on the GPU (section 3): the photon buffer, the caustic textures and
//! their energy against the photons'.

use image_space_refraction::Refraction;
use testkit::{Shot, context, render};

fn caustics_variant() -> Refraction {
    image_space_refraction::technique::variant("caustics").expect("the caustics variant")
}

#[test]
fn photons_reach_the_floor_and_the_caustic_keeps_their_power() {
    let _lock = testkit::gpu_lock();
    let scene = scene::load("hu-qin").unwrap();
    let mut t = caustics_variant();
    render(&mut t, &scene, Shot::along_path(&scene, 0.0, 96));
    let c = t.caustics().expect("prepared");
    let [hits, power] = c.read_photons(context()).unwrap();
    let landed = hits.iter().filter(|h| h[2] > 0.5).count();
    let total: f32 = power.iter().map(|p| p[0] + p[1] + p[2]).sum();
    println!("{landed} photons of {} landed, power {total}", hits.len());
    let caustic = c.read_caustic(context()).unwrap();
    let max = caustic.iter().map(|e| e[0]).fold(0.0f32, f32::max);
    println!("largest caustic irradiance {max}");
    assert!(landed > 100, "{landed} photons landed");
    assert!(max > 0.0);
    // Power in the caustic textures (irradiance x texel area) against the photons': equal but
    // for what the filter spreads past the textures' borders.
    let rects = t.rectangles().expect("prepared");
    let res = c.settings.resolution as usize;
    let mut in_textures = 0.0f64;
    for (layer, rect) in rects.refractors[0].placed.iter().enumerate() {
        let area = 4.0 * rect.half_u * rect.half_v / (res * res) as f32;
        let texels = &caustic[layer * res * res..(layer + 1) * res * res];
        in_textures += texels
            .iter()
            .map(|e| f64::from((e[0] + e[1] + e[2]) * area))
            .sum::<f64>();
    }
    println!("power in the caustic textures {in_textures}, in the photons {total}");
    let ratio = in_textures / f64::from(total);
    assert!(
        (0.98..=1.001).contains(&ratio),
        "caustic / photon power {ratio}"
    );
}
