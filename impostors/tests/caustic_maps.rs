//! The paper's light-map caustics (section 5) step by step: every photon of the caustic map
//! is splatted into the light map with its whole power (the Gaussian quads are normalised),
//! and the light map's picture is written for inspection.

mod common;

use impostors::{Impostor, caustics::CausticPath};

fn caustic_variant(path: CausticPath) -> Impostor {
    let id = match path {
        CausticPath::LightMap => "impostors/caustics",
        CausticPath::Grid => "impostors/caustics-compute",
    };
    let mut t = Impostor::new(id, "test", impostors::Settings::default());
    t.settings.mode = impostors::Mode::DoubleRefraction;
    t.settings.caustics = Some(impostors::caustics::CausticSettings::new(path));
    t
}

/// Sum of the photon power in a caustic map (texels with a photon only).
fn photon_power(
    ctx: &gpu::Context,
    address: &gpu::wgpu::Texture,
    power: &gpu::wgpu::Texture,
) -> f64 {
    let address = gpu::read_texture_f32x4(ctx, address, 0).unwrap();
    let power = gpu::read_texture_f32x4(ctx, power, 0).unwrap();
    address
        .iter()
        .zip(&power)
        .filter(|(a, _)| a[3] > 0.5)
        .map(|(_, p)| (p[0] + p[1] + p[2]) as f64)
        .sum()
}

#[test]
fn splatting_keeps_the_photon_power() {
    let ctx = common::ctx();
    for spec in [
        "cornell-sphere:material=glass-1.5",
        "cornell-sphere:material=gold",
    ] {
        let scene = scene::load(spec).unwrap();
        let mut t = caustic_variant(CausticPath::LightMap);
        {
            let _g = common::gpu_lock();
            common::render(&mut t, &scene, 0.0, 32);
        }
        let (caustics, maps) = t.caustics().expect("prepared");
        let (address, power) = maps[0].caustic_map();
        let photons = photon_power(ctx, address, power);
        let light_map = gpu::read_texture_f32x4(ctx, caustics.light_map(), 0).unwrap();
        let splatted: f64 = light_map.iter().map(|p| (p[0] + p[1] + p[2]) as f64).sum();
        println!(
            "{spec}: photon power {photons:.6} W, light map {splatted:.6} W, ratio {:.4}",
            splatted / photons
        );
        // The quads are cut at their chart's rectangle, so power near a chart's border is
        // lost, never gained.
        assert!(photons > 0.0, "{spec}: no photons");
        assert!(
            splatted <= photons * 1.01 && splatted >= photons * 0.8,
            "{spec}: light map holds {splatted} W of {photons} W"
        );
        // Picture of the atlas (log scale) for the README.
        let size = caustics.light_map().width();
        let max = light_map
            .iter()
            .map(|p| p[0] + p[1] + p[2])
            .fold(0.0f32, f32::max)
            .max(1e-20);
        let mut img = gpu::HdrImage::new(size, size);
        for (i, p) in light_map.iter().enumerate() {
            let v = ((p[0] + p[1] + p[2]) / max * 1e3 + 1.0).ln() / (1e3f32 + 1.0).ln();
            img.pixels[i] = [v, v, v, 1.0];
        }
        common::save_png(
            &img,
            &format!("light-map-{}.png", spec.replace([':', '='], "_")),
        );
    }
}
