//! The committed Stanford bunny asset (`scene/assets/bunny.glb`): its converter (ignored,
//! run by hand, see `scene/assets/README.md`) and checks that the committed file is what the
//! converter promises.

use glam::{Mat4, Vec2, Vec3};
use scene::{Camera, CameraPath, Material, Mesh, Object, Scene};
use std::path::{Path, PathBuf};

fn asset_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/bunny.glb")
}

/// Converts the npm package `bunny` (1.0.1) into `scene/assets/bunny.glb`:
///
/// ```text
/// cd /tmp && npm pack bunny@1.0.1 && tar xzf bunny-1.0.1.tgz
/// BUNNY_JS=/tmp/package/index.js cargo test -p rtapprox-scene --test gltf_bunny -- --ignored
/// ```
///
/// Positions are translated so that the bounding box is centred on x = z = 0 with its
/// lowest point at y = 0, then scaled uniformly so that the height is exactly 1 (the
/// package's bunny is 9.657897 units tall, +Y up, so the factor is 1 / 9.657897); the
/// arithmetic is done in f64 and rounded to f32 once. Normals are area-weighted vertex
/// normals: the sum of the (unnormalised) cross products of the faces around a vertex,
/// normalised. Texture coordinates are zeros. The triangles keep the package's winding
/// (counter-clockwise seen from outside: the signed volume is positive).
#[test]
#[ignore = "needs the npm package `bunny` unpacked; set BUNNY_JS to its index.js"]
fn convert_bunny_from_npm() {
    let js_path = std::env::var("BUNNY_JS").expect("set BUNNY_JS to the package's index.js");
    let text = std::fs::read_to_string(&js_path).expect("read index.js");
    let array = |key: &str| -> Vec<Vec<f64>> {
        let prefix = format!("exports.{key}=");
        let line = text
            .lines()
            .find_map(|l| l.strip_prefix(&prefix))
            .expect("exports line");
        serde_json::from_str(line.trim().trim_end_matches(';')).expect("JSON array")
    };
    let positions = array("positions");
    let cells = array("cells");
    assert!(positions.iter().all(|p| p.len() == 3) && cells.iter().all(|c| c.len() == 3));

    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in &positions {
        for a in 0..3 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    let height = hi[1] - lo[1];
    let origin = [(lo[0] + hi[0]) * 0.5, lo[1], (lo[2] + hi[2]) * 0.5];
    let scaled: Vec<[f64; 3]> = positions
        .iter()
        .map(|p| [0, 1, 2].map(|a| (p[a] - origin[a]) / height))
        .collect();

    let indices: Vec<u32> = cells.iter().flatten().map(|&i| i as u32).collect();
    let mut normals = vec![[0.0f64; 3]; scaled.len()];
    for t in indices.chunks(3) {
        let [a, b, c] = [0, 1, 2].map(|k| scaled[t[k] as usize]);
        let (u, v) = (
            [b[0] - a[0], b[1] - a[1], b[2] - a[2]],
            [c[0] - a[0], c[1] - a[1], c[2] - a[2]],
        );
        let n = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        for &i in t {
            for a in 0..3 {
                normals[i as usize][a] += n[a];
            }
        }
    }
    let mesh = Mesh {
        positions: scaled
            .iter()
            .map(|p| Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32))
            .collect(),
        normals: normals
            .iter()
            .map(|n| {
                let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
                Vec3::new((n[0] / l) as f32, (n[1] / l) as f32, (n[2] / l) as f32)
            })
            .collect(),
        uvs: vec![Vec2::ZERO; scaled.len()],
        indices,
    };
    let scene = Scene {
        name: "bunny".into(),
        objects: vec![Object::new(
            "bunny",
            mesh,
            Material::diffuse(0.8, 0.8, 0.8),
            Mat4::IDENTITY,
        )],
        textures: vec![],
        lights: vec![],
        camera: Camera {
            eye: Vec3::new(0.0, 0.6, 2.2),
            target: Vec3::new(0.0, 0.45, 0.0),
            up: Vec3::Y,
            fov_y_deg: 40.0,
            orthographic: None,
        },
        camera_path: CameraPath::default(),
        volumes: vec![],
        medium: None,
        background: Vec3::ZERO,
    };
    scene::gltf_io::export_glb(&scene, &asset_path()).expect("write bunny.glb");
    println!(
        "bunny: {} vertices, {} triangles, height {height} units -> 1, {} bytes",
        scene.objects[0].mesh.positions.len(),
        scene.objects[0].mesh.triangle_count(),
        std::fs::metadata(asset_path()).unwrap().len()
    );
}

/// The committed asset: one closed mesh of 3674 triangles, height 1, base at y = 0, centred
/// on x = z = 0, unit normals pointing outwards, small enough to embed.
#[test]
fn committed_bunny_is_normalised() {
    let bytes = std::fs::read(asset_path()).expect("scene/assets/bunny.glb is committed");
    assert!(bytes.len() < 1 << 20, "bunny.glb is {} bytes", bytes.len());
    let scene = scene::gltf_io::import(&asset_path()).expect("bunny.glb imports");
    assert_eq!(scene.objects.len(), 1);
    let mesh = &scene.objects[0].mesh;
    assert_eq!(mesh.triangle_count(), 3674);
    assert_eq!(mesh.positions.len(), 1839);
    let (lo, hi) = mesh.bounds();
    assert!(
        lo.y.abs() < 1e-6 && (hi.y - 1.0).abs() < 1e-6,
        "height: {lo} .. {hi}"
    );
    assert!(
        (lo.x + hi.x).abs() < 1e-6 && (lo.z + hi.z).abs() < 1e-6,
        "not centred: {lo} .. {hi}"
    );
    assert!(mesh.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-5));
    // Outward: the signed volume is positive and the normals agree with the winding.
    let mut volume = 0.0f64;
    for t in mesh.indices.chunks(3) {
        let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[t[k] as usize]);
        volume += a.dot(b.cross(c)) as f64 / 6.0;
        let n =
            mesh.normals[t[0] as usize] + mesh.normals[t[1] as usize] + mesh.normals[t[2] as usize];
        assert!(
            (b - a).cross(c - a).dot(n) > -1e-9,
            "triangle {t:?} winds against its normals"
        );
    }
    assert!(volume > 0.05, "signed volume {volume}");
}
