//! Import of glTF written by hand (as another tool would write it), and of bad input.
//!
//! The fixture is written below as JSON: a node hierarchy with a parent transform, a glass
//! box (`KHR_materials_transmission` + `KHR_materials_ior`), a mirror (metallic 1,
//! roughness 0) given as a triangle strip without normals, a textured floor with normalized
//! `u8` texture coordinates and a line primitive (skipped), a `KHR_lights_punctual` point
//! light and a perspective camera. Its buffer and PNG image are base64 `data:` URIs, or
//! external files beside the `.gltf` for the path import.

use glam::{Mat4, Quat, Vec2, Vec3};
use scene::builtin::textures::checker_texture;
use scene::gltf_io::{import, import_slice, to_glb_bytes};
use scene::{Material, Roles, SceneError};
use serde_json::{Value, json};
use std::path::PathBuf;
use testkit::gltf::base64;

const TEXELS: [u8; 16] = [
    255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 128,
];

fn png_2x2() -> Vec<u8> {
    use image::ImageEncoder;
    let mut out = Vec::new();
    image::codecs::png::PngEncoder::new(&mut out)
        .write_image(&TEXELS, 2, 2, image::ExtendedColorType::Rgba8)
        .unwrap();
    out
}

/// The fixture's binary data and where each part starts.
#[derive(Clone)]
struct Fixture {
    json: Value,
    bin: Vec<u8>,
    box_indices_at: usize,
    box_positions_at: usize,
}

fn fixture() -> Fixture {
    let mut bin = Vec::new();
    let mut push = |bytes: &[u8]| {
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        let at = bin.len();
        bin.extend_from_slice(bytes);
        (at, bytes.len())
    };
    let cube = scene::mesh::cuboid(Vec3::splat(-0.5), Vec3::splat(0.5));
    let f32s = |v: &[Vec3]| {
        v.iter()
            .flat_map(|p| p.to_array())
            .flat_map(f32::to_le_bytes)
            .collect::<Vec<u8>>()
    };
    let (box_pos, box_pos_len) = push(&f32s(&cube.positions));
    let (box_nor, box_nor_len) = push(&f32s(&cube.normals));
    let box_idx_bytes: Vec<u8> = cube
        .indices
        .iter()
        .flat_map(|&i| (i as u16).to_le_bytes())
        .collect();
    let (box_idx, box_idx_len) = push(&box_idx_bytes);
    // Mirror: a strip of two triangles in the z = 0 plane, facing +z, no normals, no indices.
    let strip = [
        Vec3::new(-1.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(-1.0, 2.0, 0.0),
        Vec3::new(1.0, 2.0, 0.0),
    ];
    let (mir_pos, mir_pos_len) = push(&f32s(&strip));
    // Floor: a quad facing +y; uvs are normalized u8 in a view with a 4-byte stride.
    let floor = [
        Vec3::new(-2.0, 0.0, 2.0),
        Vec3::new(2.0, 0.0, 2.0),
        Vec3::new(2.0, 0.0, -2.0),
        Vec3::new(-2.0, 0.0, -2.0),
    ];
    let (fl_pos, fl_pos_len) = push(&f32s(&floor));
    let (fl_nor, fl_nor_len) = push(&f32s(&[Vec3::Y; 4]));
    let (fl_uv, fl_uv_len) = push(&[0, 0, 0, 0, 255, 0, 0, 0, 255, 255, 0, 0, 0, 255, 0, 0]);
    let (fl_idx, fl_idx_len) = push(&[0, 1, 2, 0, 2, 3]);
    let view = |at: usize, len: usize| json!({ "buffer": 0, "byteOffset": at, "byteLength": len });
    let mut uv_view = view(fl_uv, fl_uv_len);
    uv_view["byteStride"] = json!(4);
    let json = json!({
        "asset": { "version": "2.0", "generator": "hand-written test fixture" },
        "extensionsUsed": ["KHR_materials_transmission", "KHR_materials_ior", "KHR_lights_punctual"],
        "scene": 0,
        "scenes": [{ "name": "fixture", "nodes": [0, 4, 5] }],
        "nodes": [
            { "name": "group", "translation": [1.0, 0.0, 0.0], "scale": [2.0, 2.0, 2.0], "children": [1, 2, 3] },
            { "name": "glass box", "mesh": 0, "translation": [0.0, 0.5, 0.0] },
            { "name": "lamp", "translation": [0.0, 2.0, 0.0], "extensions": { "KHR_lights_punctual": { "light": 0 } } },
            // Rotation of 90 degrees about +y, then translation (0, 0, -1); column-major.
            { "name": "mirror", "mesh": 1, "matrix": [0.0, 0.0, -1.0, 0.0,  0.0, 1.0, 0.0, 0.0,  1.0, 0.0, 0.0, 0.0,  0.0, 0.0, -1.0, 1.0] },
            { "name": "floor", "mesh": 2 },
            { "name": "camera", "camera": 0, "translation": [0.0, 1.0, 5.0] }
        ],
        "meshes": [
            { "name": "box", "primitives": [{ "attributes": { "POSITION": 0, "NORMAL": 1 }, "indices": 2, "material": 0 }] },
            { "name": "mirror", "primitives": [{ "attributes": { "POSITION": 3 }, "material": 1, "mode": 5 }] },
            { "name": "floor", "primitives": [
                { "attributes": { "POSITION": 4, "NORMAL": 5, "TEXCOORD_0": 6 }, "indices": 7, "material": 2 },
                { "attributes": { "POSITION": 4 }, "mode": 1 }
            ] }
        ],
        "materials": [
            { "name": "glass", "pbrMetallicRoughness": { "metallicFactor": 0.0, "roughnessFactor": 0.0 },
              "extensions": { "KHR_materials_transmission": { "transmissionFactor": 1.0 }, "KHR_materials_ior": { "ior": 1.45 } } },
            { "name": "mirror", "pbrMetallicRoughness": { "baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 1.0, "roughnessFactor": 0.0 } },
            { "name": "floor", "pbrMetallicRoughness": { "baseColorFactor": [0.5, 0.5, 0.5, 1.0], "baseColorTexture": { "index": 0 }, "metallicFactor": 0.0 } }
        ],
        "textures": [{ "source": 0 }],
        "images": [{ "name": "tiles", "uri": format!("data:image/png;base64,{}", base64(&png_2x2())) }],
        "extensions": { "KHR_lights_punctual": { "lights": [{ "name": "lamp", "type": "point", "color": [1.0, 0.5, 0.25], "intensity": 683.0 }] } },
        "cameras": [{ "type": "perspective", "perspective": { "yfov": 0.6, "znear": 0.05 } }],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": 24, "type": "VEC3", "min": [-0.5, -0.5, -0.5], "max": [0.5, 0.5, 0.5] },
            { "bufferView": 1, "componentType": 5126, "count": 24, "type": "VEC3" },
            { "bufferView": 2, "componentType": 5123, "count": 36, "type": "SCALAR" },
            { "bufferView": 3, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1.0, 0.0, 0.0], "max": [1.0, 2.0, 0.0] },
            { "bufferView": 4, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-2.0, 0.0, -2.0], "max": [2.0, 0.0, 2.0] },
            { "bufferView": 5, "componentType": 5126, "count": 4, "type": "VEC3" },
            { "bufferView": 6, "componentType": 5121, "normalized": true, "count": 4, "type": "VEC2" },
            { "bufferView": 7, "componentType": 5121, "count": 6, "type": "SCALAR" }
        ],
        "bufferViews": [
            view(box_pos, box_pos_len), view(box_nor, box_nor_len), view(box_idx, box_idx_len),
            view(mir_pos, mir_pos_len), view(fl_pos, fl_pos_len), view(fl_nor, fl_nor_len),
            uv_view, view(fl_idx, fl_idx_len)
        ],
        "buffers": [{ "byteLength": 0 }]
    });
    let mut f = Fixture {
        json,
        bin,
        box_indices_at: box_idx,
        box_positions_at: box_pos,
    };
    f.json["buffers"][0]["byteLength"] = json!(f.bin.len());
    f
}

impl Fixture {
    /// The fixture as one self-contained `.gltf` (the buffer as a data URI).
    fn gltf_bytes(&self) -> Vec<u8> {
        let mut j = self.json.clone();
        let uri = json!(format!(
            "data:application/octet-stream;base64,{}",
            base64(&self.bin)
        ));
        // (Fuzzed documents may have no buffer object to put it in.)
        if let Some(buffer) = j
            .get_mut("buffers")
            .and_then(|b| b.get_mut(0))
            .and_then(Value::as_object_mut)
        {
            buffer.insert("uri".into(), uri);
        }
        serde_json::to_vec_pretty(&j).unwrap()
    }
}

fn load(f: &Fixture) -> Result<scene::Scene, SceneError> {
    import_slice(&f.gltf_bytes(), "fixture.gltf")
}

fn check_fixture(s: &scene::Scene) {
    assert_eq!(s.name, "fixture");
    let names: Vec<&str> = s.objects.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(
        names,
        ["glass box", "mirror", "floor"],
        "the line primitive is skipped"
    );

    // Glass box: world = T(1,0,0) * S(2) * T(0,0.5,0); mesh kept in object space.
    let glass = &s.objects[0];
    assert_eq!(glass.material, Material::Glass { ior: 1.45 });
    assert_eq!(glass.roles, Roles::REFRACTOR | Roles::CAUSTIC_CASTER);
    let expect = Mat4::from_translation(Vec3::X)
        * Mat4::from_scale(Vec3::splat(2.0))
        * Mat4::from_translation(Vec3::Y * 0.5);
    assert!(
        glass.transform.abs_diff_eq(expect, 1e-6),
        "{}",
        glass.transform
    );
    assert_eq!(
        glass.transform.transform_point3(Vec3::splat(0.5)),
        Vec3::new(2.0, 2.0, 1.0)
    );
    assert_eq!(
        glass.mesh,
        scene::mesh::cuboid(Vec3::splat(-0.5), Vec3::splat(0.5)).tap_uvs_zero()
    );

    // Mirror: metallic 1, roughness 0, white -> a perfect mirror (F = 1 at every angle).
    let mirror = &s.objects[1];
    let Material::Metal { n, k } = mirror.material else {
        panic!("mirror is {:?}", mirror.material)
    };
    for cos in [1.0, 0.5, 0.0] {
        assert!(
            (gpu::prelude::fresnel_nk(cos, n, k) - Vec3::ONE)
                .abs()
                .max_element()
                < 1e-6
        );
    }
    assert_eq!(mirror.roles, Roles::REFLECTOR | Roles::CAUSTIC_CASTER);
    let m = Mat4::from_rotation_translation(
        Quat::from_rotation_y(std::f32::consts::FRAC_PI_2),
        Vec3::new(0.0, 0.0, -1.0),
    );
    let expect = Mat4::from_translation(Vec3::X) * Mat4::from_scale(Vec3::splat(2.0)) * m;
    assert!(
        mirror.transform.abs_diff_eq(expect, 1e-6),
        "{}",
        mirror.transform
    );
    // The strip became two triangles with flat normals (+z in object space, unwelded).
    assert_eq!(mirror.mesh.triangle_count(), 2);
    assert_eq!(mirror.mesh.positions.len(), 6);
    assert!(mirror.mesh.normals.iter().all(|n| *n == Vec3::Z));
    // World normal: +z rotated 90 degrees about y is +x.
    let wn = (mirror.normal_matrix_at(0.0) * Vec3::Z).normalize();
    assert!(wn.abs_diff_eq(Vec3::X, 1e-6), "{wn}");

    // Floor: textured diffuse; normalized u8 uvs.
    let floor = &s.objects[2];
    assert_eq!(
        floor.material,
        Material::Diffuse {
            albedo: Vec3::splat(0.5),
            texture: Some(0),
            cutout: None
        }
    );
    assert_eq!(floor.roles, Roles::NONE);
    assert_eq!(floor.mesh.uvs, [Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y]);
    assert_eq!(floor.mesh.indices, [0, 1, 2, 0, 2, 3]);
    assert_eq!(s.textures.len(), 1);
    assert_eq!(
        (
            s.textures[0].name.as_str(),
            s.textures[0].width,
            s.textures[0].height
        ),
        ("tiles", 2, 2)
    );
    assert_eq!(s.textures[0].rgba8, TEXELS);

    // Light: under the group, so at (1,0,0) + 2 * (0,2,0); 683 cd of colour (1, .5, .25)
    // is (1, .5, .25) W/sr.
    assert_eq!(s.lights.len(), 1);
    assert_eq!(s.lights[0].name, "lamp");
    assert_eq!(s.lights[0].position, Vec3::new(1.0, 4.0, 0.0));
    assert!(
        s.lights[0]
            .intensity
            .abs_diff_eq(Vec3::new(1.0, 0.5, 0.25), 1e-6)
    );

    // Camera: at (0,1,5) looking down -z with +y up, 0.6 rad.
    let c = s.camera;
    assert_eq!(c.eye, Vec3::new(0.0, 1.0, 5.0));
    assert!(
        (c.target - c.eye)
            .normalize()
            .abs_diff_eq(Vec3::NEG_Z, 1e-6)
    );
    assert!(c.up.abs_diff_eq(Vec3::Y, 1e-6));
    assert!((c.fov_y_deg - 0.6f32.to_degrees()).abs() < 1e-4);
    assert!(s.camera_path.keys.is_empty() && s.volumes.is_empty() && s.background == Vec3::ZERO);
}

trait UvsZero {
    fn tap_uvs_zero(self) -> Self;
}
impl UvsZero for scene::Mesh {
    fn tap_uvs_zero(mut self) -> Self {
        self.uvs = vec![Vec2::ZERO; self.positions.len()];
        self
    }
}

#[test]
fn hand_written_gltf_with_data_uris() {
    let s = load(&fixture()).unwrap();
    check_fixture(&s);
    // And what we make of it survives our own export.
    let back = import_slice(&to_glb_bytes(&s).unwrap(), "again.glb").unwrap();
    assert!(back == s);
}

fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("scene-gltf-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn hand_written_gltf_with_external_files() {
    let f = fixture();
    let dir = temp_dir("external");
    std::fs::write(dir.join("fixture data.bin"), &f.bin).unwrap();
    std::fs::write(dir.join("tiles.png"), png_2x2()).unwrap();
    let mut j = f.json.clone();
    j["buffers"][0]["uri"] = json!("fixture%20data.bin");
    j["images"][0]["uri"] = json!("tiles.png");
    let path = dir.join("fixture.gltf");
    std::fs::write(&path, serde_json::to_vec_pretty(&j).unwrap()).unwrap();
    check_fixture(&import(&path).unwrap());
    // From memory, the external files cannot be found: a clear error.
    let e = import_slice(&std::fs::read(&path).unwrap(), "fixture.gltf")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("fixture data.bin") && e.contains("from memory"),
        "{e}"
    );
    // A missing external file names the file.
    std::fs::remove_file(dir.join("tiles.png")).unwrap();
    let e = import(&path).unwrap_err().to_string();
    assert!(e.contains("tiles.png"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn without_a_camera_the_scene_is_framed() {
    let mut f = fixture();
    f.json["scenes"][0]["nodes"] = json!([0, 4]);
    let s = load(&f).unwrap();
    // Every object vertex projects inside the image.
    for o in &s.objects {
        for p in &o.mesh.positions {
            let q = s
                .camera
                .project(o.transform.transform_point3(*p), 100, 100)
                .unwrap();
            assert!(
                q.x >= 0.0 && q.x <= 100.0 && q.y >= 0.0 && q.y <= 100.0,
                "{} at {q}",
                o.name
            );
        }
    }
}

// ---------------------------------------------------------------------------------------
// Bad input: an Err with one readable sentence, never a panic.

fn gltf_err(bytes: &[u8]) -> String {
    match import_slice(bytes, "bad.gltf") {
        Ok(_) => panic!("bad input was accepted"),
        Err(e) => {
            let text = e.to_string();
            assert!(
                !text.is_empty() && !text.contains('\n'),
                "message is not one line: {text}"
            );
            text
        }
    }
}

/// A `.glb` with its JSON chunk text edited by `edit` (which must change it).
fn edit_glb_json(glb: &[u8], edit: impl Fn(&str) -> String) -> Vec<u8> {
    let json_len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let text = std::str::from_utf8(&glb[20..20 + json_len]).unwrap();
    let mut json = edit(text.trim_end()).into_bytes();
    assert_ne!(json, text.trim_end().as_bytes(), "the edit changed nothing");
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let rest = &glb[20 + json_len..];
    let mut out = b"glTF".to_vec();
    for w in [
        2u32,
        (20 + json.len() + rest.len()) as u32,
        json.len() as u32,
        0x4E4F534A,
    ] {
        out.extend_from_slice(&w.to_le_bytes());
    }
    out.extend_from_slice(&json);
    out.extend_from_slice(rest);
    out
}

fn err_with(f: &Fixture) -> String {
    gltf_err(&f.gltf_bytes())
}

#[test]
fn missing_file() {
    let e = import(std::path::Path::new("/no/such/dir/scene.glb")).unwrap_err();
    assert!(matches!(e, SceneError::Io(..)), "{e:?}");
    let text = e.to_string();
    assert!(
        text.contains("/no/such/dir/scene.glb") && text.contains("cannot read"),
        "{text}"
    );
    assert!(scene::load("/no/such/dir/scene.gltf").is_err());
}

#[test]
fn malformed_json() {
    let e = gltf_err(b"{ \"asset\": { \"version\": \"2.0\" }, \"nodes\": [ ");
    assert!(e.contains("JSON is malformed"), "{e}");
    let e = gltf_err(b"");
    assert!(e.contains("JSON"), "{e}");
    // NaN is not JSON: a node matrix with a literal NaN is malformed JSON.
    let text = String::from_utf8(fixture().gltf_bytes())
        .unwrap()
        .replace("\"scale\": [\n        2.0", "\"scale\": [\n        NaN");
    assert!(text.contains("NaN"));
    assert!(gltf_err(text.as_bytes()).contains("JSON"));
    // Valid JSON that is not glTF.
    let e = gltf_err(b"{\"hello\": 1}");
    assert!(e.contains("asset") || e.contains("glTF"), "{e}");
}

#[test]
fn truncated_glb() {
    let bytes = to_glb_bytes(&scene::load("cornell-sphere").unwrap()).unwrap();
    for len in [
        4,
        11,
        12,
        19,
        20,
        100,
        bytes.len() / 2,
        bytes.len() - 4,
        bytes.len() - 1,
    ] {
        let e = gltf_err(&bytes[..len]);
        assert!(e.contains("truncated") || e.contains("short"), "{len}: {e}");
    }
    // A header that declares a length shorter than a header.
    let mut bad = bytes.clone();
    bad[8..12].copy_from_slice(&8u32.to_le_bytes());
    gltf_err(&bad);
    // A chunk that runs past the end.
    let mut bad = bytes.clone();
    bad[12..16].copy_from_slice(&u32::MAX.to_le_bytes());
    assert!(gltf_err(&bad).contains("chunk"));
    // Wrong version.
    let mut bad = bytes;
    bad[4] = 1;
    assert!(gltf_err(&bad).contains("version"));
}

#[test]
fn accessor_out_of_range() {
    let mut f = fixture();
    f.json["accessors"][0]["count"] = json!(10_000);
    let e = err_with(&f);
    assert!(
        e.contains("accessor 0") && e.contains("out of range"),
        "{e}"
    );

    let mut f = fixture();
    f.json["accessors"][1]["byteOffset"] = json!(u32::MAX);
    assert!(err_with(&f).contains("out of range"));

    let mut f = fixture();
    f.json["bufferViews"][3]["byteLength"] = json!(1_000_000);
    let e = err_with(&f);
    assert!(e.contains("buffer view 3") && e.contains("outside"), "{e}");

    let mut f = fixture();
    f.json["buffers"][0]["byteLength"] = json!(f.bin.len() + 100);
    assert!(err_with(&f).contains("byteLength"));

    // An accessor index that does not exist is caught by validation.
    let mut f = fixture();
    f.json["meshes"][0]["primitives"][0]["indices"] = json!(99);
    let e = err_with(&f);
    assert!(
        e.contains("does not validate") && e.contains("indices"),
        "{e}"
    );

    // A NORMAL accessor of the wrong type.
    let mut f = fixture();
    f.json["accessors"][1]["type"] = json!("VEC2");
    let e = err_with(&f);
    assert!(e.contains("NORMAL") && e.contains("expected Vec3"), "{e}");
    // A POSITION accessor that does not exist (the gltf crate's own validation would
    // index out of bounds here).
    let mut f = fixture();
    f.json["meshes"][1]["primitives"][0]["attributes"]["POSITION"] = json!(255);
    let e = err_with(&f);
    assert!(e.contains("accessor 255 for POSITION"), "{e}");
}

#[test]
fn index_out_of_range() {
    let mut f = fixture();
    let at = f.box_indices_at + 2 * 5;
    f.bin[at..at + 2].copy_from_slice(&99u16.to_le_bytes());
    let e = err_with(&f);
    assert!(
        e.contains("index 99")
            && e.contains("24 vertices")
            && e.contains("mesh 0 (\"box\") primitive 0"),
        "{e}"
    );
}

#[test]
fn non_finite_node_transform() {
    // 1e39 overflows f32 to infinity; JSON cannot hold NaN itself.
    let cases: Vec<(usize, &str, Value)> = vec![
        (
            3,
            "matrix",
            json!([1e39, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]),
        ),
        (1, "translation", json!([0.0, 1e39, 0.0])),
        (1, "scale", json!([1.0, 1.0, -1e39])),
        (1, "rotation", json!([0.0, 1e39, 0.0, 1.0])),
    ];
    for (node, key, value) in cases {
        let mut f = fixture();
        f.json["nodes"][node][key] = value;
        let e = err_with(&f);
        assert!(
            e.contains("non-finite transform") && e.contains(&format!("node {node}")),
            "{key}: {e}"
        );
    }
    // Finite locally, infinite once multiplied down the hierarchy.
    let mut f = fixture();
    f.json["nodes"][0]["scale"] = json!([1e30, 1e30, 1e30]);
    f.json["nodes"][1]["translation"] = json!([1e10, 0.0, 0.0]);
    assert!(err_with(&f).contains("non-finite world transform"));
    // A zero quaternion is no rotation.
    let mut f = fixture();
    f.json["nodes"][1]["rotation"] = json!([0.0, 0.0, 0.0, 0.0]);
    assert!(err_with(&f).contains("quaternion"));
}

#[test]
fn non_finite_vertex_data() {
    let mut f = fixture();
    let at = f.box_positions_at + 4 * 7;
    f.bin[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    let e = err_with(&f);
    assert!(
        e.contains("non-finite vertices") && e.contains("glass box"),
        "{e}"
    );
}

#[test]
fn other_malformed_content() {
    // A node hierarchy with a cycle.
    let mut f = fixture();
    f.json["nodes"][1]["children"] = json!([0]);
    let e = err_with(&f);
    assert!(
        e.contains("cycle") || e.contains("does not validate"),
        "{e}"
    );
    // An image that is not an image.
    let mut f = fixture();
    f.json["images"][0]["uri"] = json!(format!(
        "data:image/png;base64,{}",
        base64(b"not a png at all")
    ));
    let e = err_with(&f);
    assert!(e.contains("image 0 is neither PNG nor JPEG"), "{e}");
    // An image of another format: named, with the formats the importer takes.
    let mut f = fixture();
    f.json["images"][0]["uri"] = json!(format!(
        "data:image/bmp;base64,{}",
        base64(b"BM\x3a\0\0\0\0\0\0\0\x36\0\0\0")
    ));
    let e = err_with(&f);
    assert!(
        e.contains("image 0 is a Bmp image; textures may be PNG or JPEG"),
        "{e}"
    );
    // Bad base64.
    let mut f = fixture();
    f.json["images"][0]["uri"] = json!("data:image/png;base64,@@@@");
    assert!(err_with(&f).contains("base64"));
    // A URI scheme we do not fetch.
    let mut f = fixture();
    f.json["images"][0]["uri"] = json!("https://example.com/tiles.png");
    assert!(err_with(&f).contains("scheme"));
    // Only lines: nothing to render.
    let mut f = fixture();
    f.json["scenes"][0]["nodes"] = json!([5]);
    assert!(err_with(&f).contains("no triangle"));
    // A required extension we do not support.
    let mut f = fixture();
    f.json["extensionsRequired"] = json!(["KHR_draco_mesh_compression"]);
    assert!(err_with(&f).contains("Unsupported extension"));
    // Triangle count not a multiple of three.
    let mut f = fixture();
    f.json["accessors"][7]["count"] = json!(5);
    assert!(err_with(&f).contains("multiple of 3"));
    // Extras from a newer version of this format.
    let cornell = to_glb_bytes(&scene::load("cornell-sphere").unwrap()).unwrap();
    let newer = edit_glb_json(&cornell, |t| t.replace("\"version\":1,", "\"version\":9,"));
    assert!(gltf_err(&newer).contains("version 9"));
    // Exact data in the extras that overflows f32 (a volume's radius) is checked too.
    let smoke = to_glb_bytes(&scene::load("smoke:particles=1").unwrap()).unwrap();
    let huge = edit_glb_json(&smoke, |t| {
        t.replacen("\"radius\":1.5", "\"radius\":1e39", 1)
    });
    let e = gltf_err(&huge);
    assert!(e.contains("volume \"smoke\" is not finite"), "{e}");
}

/// Every path to a value in a JSON document.
fn value_paths(v: &Value, path: &mut Vec<Value>, out: &mut Vec<Vec<Value>>) {
    out.push(path.clone());
    match v {
        Value::Array(a) => a.iter().enumerate().for_each(|(i, x)| {
            path.push(json!(i));
            value_paths(x, path, out);
            path.pop();
        }),
        Value::Object(m) => m.iter().for_each(|(k, x)| {
            path.push(json!(k));
            value_paths(x, path, out);
            path.pop();
        }),
        _ => {}
    }
}

/// The document with the value at `path` replaced (`Some`) or removed (`None`).
fn mutated(doc: &Value, path: &[Value], value: Option<&Value>) -> Value {
    let mut doc = doc.clone();
    let Some((last, parents)) = path.split_last() else {
        return value.cloned().unwrap_or(Value::Null);
    };
    let parent = parents.iter().fold(&mut doc, |v, k| match k {
        Value::String(s) => &mut v[s.as_str()],
        k => &mut v[k.as_u64().unwrap() as usize],
    });
    match (parent, last, value) {
        (Value::Object(m), Value::String(k), None) => {
            m.remove(k);
        }
        (Value::Array(a), k, None) => {
            a.remove(k.as_u64().unwrap() as usize);
        }
        (Value::Object(m), Value::String(k), Some(v)) => {
            m.insert(k.clone(), v.clone());
        }
        (Value::Array(a), k, Some(v)) => a[k.as_u64().unwrap() as usize] = v.clone(),
        _ => unreachable!(),
    }
    doc
}

/// Structural fuzzing: every value in the fixture's JSON (and in an exported scene's JSON,
/// extras included) removed or replaced, one at a time, by awkward values; and bit flips
/// and truncations over a whole exported `.glb`. Nothing may panic; every rejection is a
/// readable sentence.
#[test]
fn no_panic_on_corrupted_input() {
    let numbers = [
        json!(0),
        json!(1),
        json!(-1),
        json!(3),
        json!(255),
        json!(4294967295u64),
        json!(1e39),
        json!(-0.5),
    ];
    let others = [
        json!(null),
        json!("VEC3"),
        json!([]),
        json!({}),
        json!([1, 2, 3]),
    ];
    let (mut ok, mut err) = (0, 0);
    let mut check = |result: Result<scene::Scene, SceneError>| match result {
        Ok(_) => ok += 1,
        Err(e) => {
            let text = e.to_string();
            assert!(!text.is_empty() && !text.contains('\n'), "{text}");
            err += 1;
        }
    };

    let f = fixture();
    let mut paths = vec![];
    value_paths(&f.json, &mut vec![], &mut paths);
    assert!(paths.len() > 100);
    for path in &paths {
        let mut g = f.clone();
        g.json = mutated(&f.json, path, None);
        check(load(&g));
        for value in numbers.iter().chain(&others) {
            g.json = mutated(&f.json, path, Some(value));
            check(load(&g));
        }
    }

    let mut small = scene::load("cornell-sphere").unwrap();
    small.objects.last_mut().unwrap().mesh = scene::mesh::uv_sphere(0.3, 4, 8);
    small
        .textures
        .push(checker_texture("t", 4, 2, [0, 0, 0], [255, 255, 255]));
    small.objects[0].material = Material::Diffuse {
        albedo: Vec3::ONE,
        texture: Some(0),
        cutout: None,
    };
    let bytes = to_glb_bytes(&small).unwrap();
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let doc: Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    let bin = &bytes[20 + json_len + 8..];
    let glb = |doc: &Value| {
        let mut j = serde_json::to_vec(doc).unwrap();
        while !j.len().is_multiple_of(4) {
            j.push(b' ');
        }
        let mut out = b"glTF".to_vec();
        for w in [
            2u32,
            (28 + j.len() + bin.len()) as u32,
            j.len() as u32,
            0x4E4F534A,
        ] {
            out.extend_from_slice(&w.to_le_bytes());
        }
        out.extend_from_slice(&j);
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(&0x004E4942u32.to_le_bytes());
        out.extend_from_slice(bin);
        out
    };
    assert!(import_slice(&glb(&doc), "rebuilt.glb").unwrap() == small);
    let mut paths = vec![];
    value_paths(&doc, &mut vec![], &mut paths);
    for path in &paths {
        check(import_slice(&glb(&mutated(&doc, path, None)), "fuzz.glb"));
        for value in [
            &numbers[0],
            &numbers[5],
            &numbers[6],
            &others[0],
            &others[1],
        ] {
            check(import_slice(
                &glb(&mutated(&doc, path, Some(value))),
                "fuzz.glb",
            ));
        }
    }

    for k in 0..3000usize {
        let mut b = bytes.clone();
        let pos = (k * 7919 + k * k * 31) % b.len();
        b[pos] ^= 1 << (k % 8);
        if k % 3 == 0 {
            b.truncate((k * 104_729) % bytes.len());
        }
        check(import_slice(&b, "fuzz.glb"));
    }
    assert!(ok > 100 && err > 100, "{ok} accepted, {err} rejected");
}

/// Everything of a file the importer leaves out or approximates is named in a note, one line
/// each, naming the light, camera or material (Blender's exports have all of these): spot and
/// directional lights, cameras not used, emission, alpha blending, rough glass and rough
/// metal (alpha masks: `alpha_without_a_texture_is_exact`). The scene itself is imported as before.
#[test]
fn what_is_left_out_is_named() {
    let mut f = fixture();
    let j = &mut f.json;
    j["nodes"][2]["children"] = json!([6, 7]);
    for node in [
        json!({ "name": "sun", "extensions": { "KHR_lights_punctual": { "light": 1 } } }),
        json!({ "name": "spot", "translation": [0.0, 3.0, 0.0], "extensions": { "KHR_lights_punctual": { "light": 2 } } }),
        json!({ "name": "plan view", "camera": 1, "translation": [0.0, 9.0, 0.0] }),
        json!({ "name": "spare view", "camera": 2, "translation": [3.0, 1.0, 5.0] }),
        json!({ "name": "wide", "extensions": { "KHR_lights_punctual": { "light": 3 } } }),
    ] {
        j["nodes"].as_array_mut().unwrap().push(node);
    }
    // The plan view comes after the fixture's camera: the latter stays the view.
    j["scenes"][0]["nodes"] = json!([0, 4, 5, 8, 9, 10]);
    // What the importer ignores: a skin, an animation, vertex colours, morph targets, two
    // extensions it does not read, a light's range (the floor's lines primitive is the
    // fixture's own).
    j["nodes"][4]["skin"] = json!(0);
    j["skins"] = json!([{ "joints": [5] }]);
    j["accessors"].as_array_mut().unwrap().push(
        json!({ "bufferView": 4, "componentType": 5126, "count": 4, "type": "SCALAR", "min": [-2.0], "max": [2.0] }),
    );
    j["animations"] = json!([{
        "channels": [{ "sampler": 0, "target": { "node": 3, "path": "translation" } }],
        "samplers": [{ "input": 8, "output": 3 }]
    }]);
    j["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = json!(0);
    j["meshes"][0]["primitives"][0]["targets"] = json!([{ "POSITION": 1 }]);
    let used = j["extensionsUsed"].as_array_mut().unwrap();
    used.push(json!("KHR_materials_volume"));
    used.push(json!("KHR_texture_transform"));
    let lights = j["extensions"]["KHR_lights_punctual"]["lights"]
        .as_array_mut()
        .unwrap();
    lights.push(json!({ "name": "Sun", "type": "directional", "intensity": 3.0 }));
    lights.push(json!({ "name": "Spot", "type": "spot", "intensity": 500.0, "range": 10.0, "spot": { "innerConeAngle": 0.2, "outerConeAngle": 0.5 } }));
    // Past glTF's rules: mended, named.
    lights.push(json!({ "name": "Wide", "type": "spot", "spot": { "innerConeAngle": 2.5, "outerConeAngle": 2.0 } }));
    let cameras = j["cameras"].as_array_mut().unwrap();
    cameras.push(json!({ "name": "Plan", "type": "orthographic", "orthographic": { "xmag": 2.0, "ymag": 2.0, "znear": 0.1, "zfar": 20.0 } }));
    cameras.push(json!({ "name": "Spare", "type": "perspective", "perspective": { "yfov": 0.8, "znear": 0.05 } }));
    j["materials"][0]["pbrMetallicRoughness"]["roughnessFactor"] = json!(0.1);
    j["materials"][1]["pbrMetallicRoughness"]["roughnessFactor"] = json!(0.3);
    j["materials"][2]["emissiveFactor"] = json!([1.0, 0.5, 0.0]);
    j["materials"][2]["alphaMode"] = json!("BLEND");
    let (mut s, notes) =
        scene::gltf_io::import_slice_noted(&f.gltf_bytes(), "fixture.gltf").unwrap();
    // The sun and the spot are lights of the scene, pointing down their nodes' -Z; the
    // rest is the fixture.
    let (sun, spot, wide) = (s.lights.remove(1), s.lights.remove(1), s.lights.remove(1));
    let right = std::f32::consts::FRAC_PI_2;
    assert!(matches!(
        wide.kind,
        scene::LightKind::Spot { inner_cone, outer_cone, .. } if inner_cone == right && outer_cone == right
    ));
    // The floor's material emits: its objects carry the radiance, and nothing else emits.
    let emitting: Vec<Vec3> = s.objects.iter().map(|o| o.emission).collect();
    assert!(emitting.contains(&Vec3::new(1.0, 0.5, 0.0)), "{emitting:?}");
    assert!(
        emitting
            .iter()
            .all(|e| *e == Vec3::ZERO || *e == Vec3::new(1.0, 0.5, 0.0))
    );
    for o in &mut s.objects {
        o.emission = Vec3::ZERO;
    }
    check_fixture(&s);
    assert_eq!(
        (sun.name.as_str(), sun.intensity, sun.kind),
        (
            "Sun",
            Vec3::splat(3.0 / 683.0),
            scene::LightKind::Directional {
                direction: Vec3::NEG_Z
            }
        )
    );
    assert_eq!(
        (spot.name.as_str(), spot.position, spot.kind),
        (
            "Spot",
            // Under the lamp (node 2) at (1, 4, 0), in the group scaled by 2.
            Vec3::new(1.0, 10.0, 0.0),
            scene::LightKind::Spot {
                direction: Vec3::NEG_Z,
                inner_cone: 0.2,
                outer_cone: 0.5
            }
        )
    );
    let expected = [
        "the view is perspective camera 0 of node 5 (\"camera\"), the first camera in the node tree",
        "light 3 (\"Wide\") of node 10 (\"wide\") has an outer cone angle of 2 rad, past glTF's pi/2",
        "light 3 (\"Wide\") of node 10 (\"wide\") has an inner cone angle of 2.5 rad, past its outer one",
        "perspective camera 2 (\"Spare\") of node 9 (\"spare view\") is not used",
        "light 2 (\"Spot\") of node 7 (\"spot\") has a range of 10 m, which is ignored",
        "node 4 (\"floor\") is skinned: drawn in its bind pose",
        "the file's 1 animation(s) are ignored",
        "the file uses KHR_materials_volume, which the importer does not read: absorption",
        "the file uses KHR_texture_transform, which the importer does not read",
        "mesh 2 (\"floor\") primitive 1 draws Lines, not triangles: skipped",
        "mesh 0 (\"box\") has vertex colours (COLOR_0), which are ignored",
        "mesh 0 (\"box\") has morph targets, which are ignored",
        "orthographic camera 1 (\"Plan\") of node 8 (\"plan view\") is not used",
        "material 0 (\"glass\") transmits with roughness 0.1: rendered as smooth glass",
        "material 1 (\"mirror\") is metal with roughness 0.3: rendered as a smooth mirror",
        "material 2 (\"floor\") emits radiance [1, 0.5, 0] (emissive factor times strength): \
         seen directly and in reflections and refractions, but it lights nothing",
        "material 2 (\"floor\") is alpha-blended (BLEND) with alpha 1 times its texture's, which \
         is not supported yet: rendered opaque",
    ];
    println!("{}", notes.join("\n"));
    for line in expected {
        let found = notes.iter().filter(|n| n.starts_with(line)).count();
        assert_eq!(found, 1, "{line:?} in {notes:#?}");
    }
    assert_eq!(notes.len(), expected.len(), "{notes:#?}");
    assert!(notes.iter().all(|n| !n.contains('\n')), "one line each");
}

/// An orthographic camera met first is the view (Blender's orthographic cameras): its `ymag` is
/// the view's half height, a note names it, and another note says that its `xmag` is not
/// used where it differs (the width follows the image). A zero `ymag` is an error that names
/// the node; a negative one is its size; an unused camera's flaws are not read.
#[test]
fn an_orthographic_camera_is_the_view() {
    let mut f = fixture();
    f.json["cameras"][0] = json!({ "name": "Top", "type": "orthographic", "orthographic": { "xmag": 3.0, "ymag": 2.0, "znear": 0.1, "zfar": 20.0 } });
    let (s, notes) = scene::gltf_io::import_slice_noted(&f.gltf_bytes(), "ortho.gltf").unwrap();
    let c = s.camera;
    assert_eq!(c.orthographic, Some(2.0));
    assert_eq!(c.eye, Vec3::new(0.0, 1.0, 5.0));
    assert!(
        (c.target - c.eye)
            .normalize()
            .abs_diff_eq(Vec3::NEG_Z, 1e-6)
    );
    let expected = [
        "the view is orthographic camera 0 (\"Top\") of node 5 (\"camera\"), the first camera",
        "orthographic camera 0 (\"Top\") of node 5 (\"camera\") has xmag 3 and ymag 2: the view \
         is 4 high and as wide as the rendered image's aspect makes it (xmag is not used)",
    ];
    for line in expected {
        let found = notes.iter().filter(|n| n.starts_with(line)).count();
        assert_eq!(found, 1, "{line:?} in {notes:#?}");
    }
    // Every ray of the view is parallel: the corners' directions are the centre's.
    let (o0, d0) = c.ray(0.5, 0.5, 32, 16);
    let (o1, d1) = c.ray(31.5, 15.5, 32, 16);
    assert_eq!(d0, d1);
    // 32 x 16 pixels: 4 m high, 8 m wide; the corners' centres are a pixel's width in.
    assert!(
        (o1 - o0).abs_diff_eq(Vec3::new(7.75, -3.75, 0.0), 1e-5),
        "{}",
        o1 - o0
    );
    // A negative ymag (which glTF discourages but allows) is its size; 0 is an error that
    // names the node.
    f.json["cameras"][0]["orthographic"]["ymag"] = json!(-1.5);
    let s = scene::gltf_io::import_slice(&f.gltf_bytes(), "ortho.gltf").unwrap();
    assert_eq!(s.camera.orthographic, Some(1.5));
    f.json["cameras"][0]["orthographic"]["ymag"] = json!(0.0);
    let e = scene::gltf_io::import_slice(&f.gltf_bytes(), "ortho.gltf").unwrap_err();
    assert!(e.to_string().contains("node 5"), "{e}");
    // A camera that is not used is not read: its flaw is a note's business, not an error.
    f.json["cameras"].as_array_mut().unwrap().insert(
        0,
        json!({ "type": "perspective", "perspective": { "yfov": 0.5, "znear": 0.05 } }),
    );
    f.json["nodes"][5]["camera"] = json!(1);
    f.json["nodes"]
        .as_array_mut()
        .unwrap()
        .push(json!({ "name": "front", "camera": 0 }));
    f.json["scenes"][0]["nodes"] = json!([6, 0, 4, 5]);
    let (s, notes) = scene::gltf_io::import_slice_noted(&f.gltf_bytes(), "ortho.gltf").unwrap();
    assert_eq!(s.camera.orthographic, None);
    assert!(
        notes
            .iter()
            .any(|n| n
                .starts_with("orthographic camera 1 (\"Top\") of node 5 (\"camera\") is not used")),
        "{notes:#?}"
    );
}

/// The importer decodes the two texture formats of core glTF: PNG (the fixture's image, checked
/// texel for texel by `check_fixture`) and JPEG, here a 16 x 16 image of one colour, which the
/// encoder keeps within 2 of each channel.
#[test]
fn a_jpeg_texture_is_decoded() {
    use image::ImageEncoder;
    let colour = [200u8, 120, 40];
    let texels: Vec<u8> = colour.iter().copied().cycle().take(16 * 16 * 3).collect();
    let mut jpeg = Vec::new();
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut jpeg, 95)
        .write_image(&texels, 16, 16, image::ExtendedColorType::Rgb8)
        .unwrap();
    let mut f = fixture();
    f.json["images"][0]["uri"] = json!(format!("data:image/jpeg;base64,{}", base64(&jpeg)));
    let s = load(&f).unwrap();
    let t = &s.textures[0];
    assert_eq!((t.width, t.height), (16, 16));
    for texel in t.rgba8.chunks(4) {
        for (got, want) in texel[..3].iter().zip(colour) {
            assert!(got.abs_diff(want) <= 2, "{texel:?} against {colour:?}");
        }
        assert_eq!(texel[3], 255, "JPEG has no alpha");
    }
}

/// A mask or a blend whose alpha is one constant (no texture) is exact: a mask at or above its
/// cutoff and a blend of alpha 1 are opaque, without a note; a mask below its cutoff and a
/// blend of alpha 0 leave their primitives out, with a note. A blend in between is rendered
/// opaque, with a note.
#[test]
fn alpha_without_a_texture_is_exact() {
    let mirror_objects = |s: &scene::Scene| {
        s.objects
            .iter()
            .filter(|o| matches!(o.material, scene::Material::Metal { .. }))
            .count()
    };
    let import = |mode: &str, alpha: f64| {
        let mut f = fixture();
        f.json["materials"][1]["alphaMode"] = json!(mode);
        f.json["materials"][1]["alphaCutoff"] = json!(0.5);
        f.json["materials"][1]["pbrMetallicRoughness"]["baseColorFactor"][3] = json!(alpha);
        scene::gltf_io::import_slice_noted(&f.gltf_bytes(), "alpha.gltf").unwrap()
    };
    let about_alpha = |notes: &[String]| -> Vec<String> {
        notes
            .iter()
            .filter(|n| n.contains("alpha"))
            .cloned()
            .collect()
    };
    for (mode, alpha) in [("MASK", 0.5), ("MASK", 0.8), ("BLEND", 1.0)] {
        let (s, notes) = import(mode, alpha);
        assert_eq!(mirror_objects(&s), 1, "{mode} {alpha}");
        assert!(about_alpha(&notes).is_empty(), "{mode} {alpha}: {notes:#?}");
    }
    for (mode, alpha, words) in [
        (
            "MASK",
            0.2,
            "alpha-masked (MASK, cutoff 0.5) with alpha 0.2",
        ),
        ("BLEND", 0.0, "alpha-blended (BLEND) with alpha 0"),
    ] {
        let (s, notes) = import(mode, alpha);
        assert_eq!(mirror_objects(&s), 0, "{mode} {alpha}");
        assert_eq!(
            about_alpha(&notes),
            vec![format!(
                "material 1 (\"mirror\") is {words}: nothing of it is seen, so its primitives are \
                 left out"
            )]
        );
    }
    // A texture only lowers the alpha: a textured mask below its cutoff is cut out too.
    let mut f = fixture();
    f.json["materials"][2]["alphaMode"] = json!("MASK");
    f.json["materials"][2]["pbrMetallicRoughness"]["baseColorFactor"][3] = json!(0.1);
    let (s, _) = scene::gltf_io::import_slice_noted(&f.gltf_bytes(), "alpha.gltf").unwrap();
    assert!(
        s.objects.iter().all(|o| o.name != "floor"),
        "the floor is cut out"
    );
    // A textured mask whose factor keeps some of it is an exact cut-out: glTF compares factor
    // times texture alpha with the cutoff, so the texture's threshold is cutoff / factor.
    f.json["materials"][2]["pbrMetallicRoughness"]["baseColorFactor"][3] = json!(0.8);
    f.json["materials"][2]["alphaCutoff"] = json!(0.4);
    let (s, notes) = scene::gltf_io::import_slice_noted(&f.gltf_bytes(), "alpha.gltf").unwrap();
    let floor = s.objects.iter().find(|o| o.name == "floor").unwrap();
    let (texture, threshold) = floor.material.cutout().expect("the floor is cut out");
    assert!((threshold - 0.5).abs() < 1e-6, "{threshold}");
    assert!(texture < s.textures.len());
    assert!(about_alpha(&notes).is_empty(), "{notes:#?}");
    // Metal reads no texture: its textured mask is rendered opaque, with a note.
    let mut g = fixture();
    g.json["materials"][1]["alphaMode"] = json!("MASK");
    g.json["materials"][1]["pbrMetallicRoughness"]["baseColorTexture"] = json!({ "index": 0 });
    let (s, notes) = scene::gltf_io::import_slice_noted(&g.gltf_bytes(), "alpha.gltf").unwrap();
    assert_eq!(mirror_objects(&s), 1);
    assert_eq!(
        about_alpha(&notes),
        vec![
            "material 1 (\"mirror\") is alpha-masked (MASK, cutoff 0.5) with a texture, but it \
             imports as metal, which reads no texture: rendered opaque (only diffuse surfaces \
             are cut out)"
                .to_string()
        ]
    );
    // A file whose every triangle is cut out says so.
    for m in 0..3 {
        f.json["materials"][m]["alphaMode"] = json!("BLEND");
        f.json["materials"][m]["pbrMetallicRoughness"]["baseColorFactor"] =
            json!([1.0, 1.0, 1.0, 0.0]);
    }
    let e = scene::gltf_io::import_slice(&f.gltf_bytes(), "alpha.gltf").unwrap_err();
    assert!(
        e.to_string()
            .contains("every triangle primitive of the file (3) is cut out by its alpha"),
        "{e}"
    );
    let (s, notes) = import("BLEND", 0.4);
    assert_eq!(mirror_objects(&s), 1);
    assert_eq!(
        about_alpha(&notes),
        vec![
            "material 1 (\"mirror\") is alpha-blended (BLEND) with alpha 0.4, which is not \
              supported yet: rendered opaque"
                .to_string()
        ]
    );
}
