//! Caustics (section 7) on the GPU: the light maps hold the flux that the exact photon paths
//! carry to the chessboard, where they carry it; separating the static pieces' light map
//! changes nothing but the cost; caustics only ever add light, and only on the receiver.

use glam::{Vec2, Vec3};
use refractor_maps::caustics::{Landing, PhotonSum, caustic_receiver, exact_photons};
use refractor_maps::{CausticSettings, RefractorMaps, Settings};
use scene::lightmap::ChartAtlas;
use scene::{Scene, Technique};
use testkit::{Shot, gpu_lock, render_shots};

const PHOTONS: u32 = 48;
const LIGHT_MAP: u32 = 256;

fn caustics(separated: bool) -> RefractorMaps {
    let mut t = RefractorMaps::new(
        "refractor-maps/test",
        "test",
        true,
        Settings {
            caustics: Some(CausticSettings {
                photons: PHOTONS,
                lightmap_resolution: LIGHT_MAP,
                separated,
                ..CausticSettings::default()
            }),
            ..Settings::default()
        },
    );
    for (name, value) in [("resolution", 128.0), ("env_resolution", 16.0)] {
        t.set_param(name, value).unwrap();
    }
    t
}

/// A light map's texels (rgb power per texel).
fn read_light_map(texture: &gpu::wgpu::Texture) -> Vec<Vec3> {
    gpu::read_texture_f32x4(testkit::context(), texture, 0)
        .unwrap()
        .iter()
        .map(|t| Vec3::new(t[0], t[1], t[2]))
        .collect()
}

/// A light map's total power and power-weighted mean uv (texel centres).
fn light_map_sum(texels: &[Vec3]) -> PhotonSum {
    let side = (texels.len() as f32).sqrt() as u32;
    let landings: Vec<Landing> = texels
        .iter()
        .enumerate()
        .filter(|(_, p)| p.element_sum() > 0.0)
        .map(|(i, &power)| Landing {
            uv: (Vec2::new((i as u32 % side) as f32, (i as u32 / side) as f32) + 0.5) / side as f32,
            power,
        })
        .collect();
    PhotonSum::of(&landings)
}

/// The exact photons of `pieces` (scene objects) at `time` from every light.
fn exact(scene: &Scene, pieces: &[usize], time: f32) -> Vec<Landing> {
    let above = pieces
        .iter()
        .map(|&o| scene.objects[o].center_at(time))
        .sum::<Vec3>()
        / pieces.len() as f32;
    let receiver = caustic_receiver(scene, above).unwrap();
    let atlas = ChartAtlas::of_objects(scene, LIGHT_MAP, |o| o == receiver.object);
    let chart = atlas.chart(receiver.object, 2).unwrap();
    let bvh = scene::bvh::SceneBvh::build(scene, time);
    let mut landings = Vec::new();
    for light in &scene.lights {
        for &piece in pieces {
            landings.extend(exact_photons(
                scene, &bvh, piece, &receiver, chart, light, PHOTONS, time,
            ));
        }
    }
    landings
}

/// The exact photons splatted with the light map's Gaussian (unclipped), as texels.
fn splat_on_cpu(landings: &[Landing], radius: f32) -> Vec<Vec3> {
    let side = LIGHT_MAP as i32;
    let footprint = scene::lightmap::Footprint::fixed(radius);
    let mut texels = vec![Vec3::ZERO; (side * side) as usize];
    for l in landings {
        let centre = l.uv * side as f32;
        let r = radius.ceil() as i32;
        let (ci, cj) = (centre.x.floor() as i32, centre.y.floor() as i32);
        for j in cj - r..=cj + r {
            for i in ci - r..=ci + r {
                let d = Vec2::new(i as f32 + 0.5, j as f32 + 0.5) - centre;
                if (0..side).contains(&i) && (0..side).contains(&j) {
                    texels[(j * side + i) as usize] += l.power * footprint.weight(d);
                }
            }
        }
    }
    texels
}

/// The GPU light map beside the exact photons splatted on the CPU, one exposure (the GPU
/// map's 99.5th percentile maps to white): `target/refractor-maps-caustics/light-maps.png`.
fn save_side_by_side(gpu: &[Vec3], exact: &[Vec3]) {
    let side = LIGHT_MAP;
    let mut lum: Vec<f32> = gpu
        .iter()
        .map(|p| p.element_sum())
        .filter(|&l| l > 0.0)
        .collect();
    lum.sort_by(f32::total_cmp);
    let white = lum.get(lum.len() * 995 / 1000).copied().unwrap_or(1.0) / 3.0;
    let mut image = gpu::HdrImage {
        width: 2 * side + 4,
        height: side,
        pixels: vec![[1.0, 1.0, 1.0, 1.0]; ((2 * side + 4) * side) as usize],
    };
    for j in 0..side {
        for i in 0..side {
            let t = (j * side + i) as usize;
            for (offset, map) in [(0, gpu), (side + 4, exact)] {
                let p = map[t] / white;
                image.pixels[(j * image.width + offset + i) as usize] = [p.x, p.y, p.z, 1.0];
            }
        }
    }
    testkit::save_png(
        &image,
        &testkit::out_dir("refractor-maps-caustics").join("light-maps.png"),
    );
}

fn assert_close(label: &str, gpu: &[Vec3], exact: &[Landing]) {
    let (gpu, exact) = (light_map_sum(gpu), PhotonSum::of(exact));
    let ratio = gpu.power.element_sum() / exact.power.element_sum();
    let shift = (gpu.uv_centroid - exact.uv_centroid).length() * LIGHT_MAP as f32;
    println!(
        "{label}: light map {:.5} W, exact paths {:.5} W ({} photons), ratio {ratio:.4}, \
         centroids {shift:.2} texels apart",
        gpu.power.element_sum(),
        exact.power.element_sum(),
        exact.count
    );
    assert!(exact.count > 100, "{label}: too few exact photons landed");
    // Measured on lavapipe: 0.988 (static pieces), 1.041 (the pawn on e4). A missing
    // cos^3, pixel area or Fresnel factor moves the ratio by 10% or more.
    assert!((ratio - 1.0).abs() < 0.07, "{label}: power ratio {ratio}");
    assert!(shift < 2.0, "{label}: centroids {shift} texels apart");
}

#[test]
fn the_light_maps_hold_the_flux_of_the_exact_photon_paths() {
    let _lock = gpu_lock();
    let scene = scene::load("chess").unwrap();
    let (movers, statics): (Vec<usize>, Vec<usize>) = scene
        .specular_objects()
        .into_iter()
        .partition(|&o| !scene.objects[o].motion.is_static());
    assert_eq!(movers.len(), 1);
    // The pawn's light map is made at the frame's time: the last shot's, t = 2 (on e4).
    let mut t = caustics(true);
    let shots: Vec<_> = [0.0, 2.0].map(|t| Shot::along_path(&scene, t, 16)).into();
    render_shots(&mut t, &scene, &shots);
    let (static_map, moving_map) = t.light_maps().unwrap();
    let (static_map, moving_map) = (read_light_map(static_map), read_light_map(moving_map));
    let (static_exact, moving_exact) = (exact(&scene, &statics, 0.0), exact(&scene, &movers, 2.0));
    assert_close("static pieces", &static_map, &static_exact);
    assert_close("moving pawn (t = 2)", &moving_map, &moving_exact);
    let both: Vec<Vec3> = static_map
        .iter()
        .zip(&moving_map)
        .map(|(a, b)| *a + *b)
        .collect();
    let all_exact = [static_exact, moving_exact].concat();
    let radius = CausticSettings::default().splat_radius;
    save_side_by_side(&both, &splat_on_cpu(&all_exact, radius));
}

#[test]
fn separating_the_static_light_map_changes_only_the_cost() {
    let _lock = gpu_lock();
    let scene = scene::load("chess").unwrap();
    let shots: Vec<_> = [0.0, 1.0].map(|t| Shot::along_path(&scene, t, 32)).into();
    let separated = render_shots(&mut caustics(true), &scene, &shots);
    let full = render_shots(&mut caustics(false), &scene, &shots);
    let diff = separated
        .pixels
        .iter()
        .zip(&full.pixels)
        .flat_map(|(p, q)| (0..3).map(move |c| (p[c] - q[c]).abs() / q[c].abs().max(1.0)))
        .fold(0.0, f32::max);
    // The same photons splatted into other maps: only the order of the blended f32 sums
    // differs, and a texel sums up to thousands of overlapping splats (rounding grows with
    // their count: measured 4e-5 with fixed quads, 1.5e-4 with footprints). A piece missing
    // from either map would differ by the caustic itself.
    assert!(
        diff < 1e-3,
        "separated and full update differ by {diff} (relative to the pixel, at least 1)"
    );
}

#[test]
fn caustics_only_add_light_and_only_on_the_board() {
    let _lock = gpu_lock();
    let scene = scene::load("chess").unwrap();
    let shots = [Shot::along_path(&scene, 1.0, 48)];
    let with = render_shots(&mut caustics(true), &scene, &shots);
    let mut plain = caustics(true);
    plain.settings.caustics = None;
    let without = render_shots(&mut plain, &scene, &shots);
    let reference = testkit::reference("chess", &scene, shots[0], 0);
    let board = scene
        .objects
        .iter()
        .position(|o| o.name == "board")
        .unwrap();
    let mut brighter = 0;
    for (i, (p, q)) in with.pixels.iter().zip(&without.pixels).enumerate() {
        let added = (0..3).map(|c| p[c] - q[c]).fold(f32::INFINITY, f32::min);
        let most = (0..3).map(|c| p[c] - q[c]).fold(0.0, f32::max);
        assert!(added > -1e-5, "pixel {i}: caustics darken it by {added}");
        if most > 1e-5 {
            brighter += 1;
            assert_eq!(
                reference.object_ids[i], board as i32,
                "pixel {i}: caustic light off the board"
            );
        }
    }
    assert!(brighter > 10, "caustics lit only {brighter} pixels");
}
