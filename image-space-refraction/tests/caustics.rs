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

/// The caustic alone against the reference's (README, "Caustics"): the caustic variant's
/// image minus `nearby-corrected`'s (the same frame without caustics) against the reference
/// minus the reference without caustic photons, on `hu-qin` at 128 x 128, t = 0, for photon
/// buffers of 64^2 and 128^2 and filter sizes k = 1, 2, 3, with caustic textures of 256^2
/// (2.3 cm texels on the 6 m floor), 512^2 and 1024^2. Figures: the RMSE of the caustic
/// over the image and over the pixels where the reference's caustic exceeds 0.05, and the
/// caustic's power (sum of radiance) over the reference's. Run with `--nocapture` for the
/// table.
#[test]
fn caustic_error_against_the_reference_caustic() {
    let _lock = testkit::gpu_lock();
    let spec = "hu-qin";
    let scene = scene::load(spec).unwrap();
    let shot = Shot::along_path(&scene, 0.0, 128);
    // 8 million photons: 490 per pixel, eight times the harness's density, so that the
    // reference's own noise stays below the differences measured.
    let with = testkit::reference(spec, &scene, shot, 8_000_000).image;
    let without = testkit::reference(spec, &scene, shot, 0).image;
    let truth: Vec<f32> = with
        .pixels
        .iter()
        .zip(&without.pixels)
        .flat_map(|(a, b)| (0..3).map(move |c| a[c] - b[c]))
        .collect();
    let mut base = image_space_refraction::technique::variant("nearby-corrected").unwrap();
    let base = render(&mut base, &scene, shot);
    println!(
        "| caustic texture | photon buffer | k | RMSE | RMSE in the caustic | power / reference |"
    );
    println!("| --- | --- | --- | --- | --- | --- |");
    for (resolution, photons, k) in [256.0, 512.0, 1024.0]
        .into_iter()
        .flat_map(|r| [64.0, 128.0].map(|p| (r, p)))
        .flat_map(|(r, p)| [1.0, 2.0, 3.0].map(|k| (r, p, k)))
    {
        {
            let mut t = caustics_variant();
            scene::Technique::set_param(&mut t, "caustic_resolution", resolution).unwrap();
            scene::Technique::set_param(&mut t, "photon_buffer", photons).unwrap();
            scene::Technique::set_param(&mut t, "filter_k", k).unwrap();
            let image = render(&mut t, &scene, shot);
            let ours: Vec<f32> = image
                .pixels
                .iter()
                .zip(&base.pixels)
                .flat_map(|(a, b)| (0..3).map(move |c| a[c] - b[c]))
                .collect();
            let (mut all, mut inside, mut n_inside) = (0.0f64, 0.0f64, 0usize);
            for (o, r) in ours.chunks(3).zip(truth.chunks(3)) {
                let d: f64 = o.iter().zip(r).map(|(a, b)| f64::from(a - b).powi(2)).sum();
                all += d;
                if r.iter().sum::<f32>() / 3.0 > 0.05 {
                    inside += d;
                    n_inside += 1;
                }
            }
            let rmse = (all / truth.len() as f64).sqrt();
            let rmse_inside = (inside / (3 * n_inside.max(1)) as f64).sqrt();
            let power = ours.iter().sum::<f32>() / truth.iter().sum::<f32>();
            println!(
                "| {resolution}^2 | {photons}^2 | {k} | {rmse:.4} | {rmse_inside:.4} | {power:.3} |"
            );
            assert!(
                rmse.is_finite() && (0.5..2.0).contains(&power),
                "power ratio {power}"
            );
        }
    }
}
