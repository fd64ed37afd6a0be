//! Small glTF files for the reliability tests: a scene exported by `scene::gltf_io`, opened
//! as JSON plus its binary chunk, edited the way a broken or unusual file would be, and
//! written back as `.glb` or `.gltf`.

use glam::Vec3;
use scene::mesh::{cuboid, quad};
use scene::{Camera, Light, Material, Object, Scene};
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

/// A glTF file being edited: its JSON and its binary buffer.
#[derive(Clone, Debug)]
pub struct Glb {
    pub json: Value,
    pub bin: Vec<u8>,
}

/// A small lit scene: a grey floor, a grey box and a glass box, one point light, a camera
/// looking at them from the front and above.
pub fn small_scene() -> Scene {
    let grey = Material::diffuse(0.7, 0.7, 0.7);
    Scene {
        name: "small".into(),
        objects: vec![
            Object::new(
                "floor",
                quad(
                    Vec3::new(-2.0, 0.0, 2.0),
                    Vec3::X * 4.0,
                    Vec3::NEG_Z * 4.0,
                    glam::Vec2::ONE,
                ),
                grey.clone(),
                glam::Mat4::IDENTITY,
            ),
            Object::new(
                "box",
                cuboid(Vec3::new(-0.9, 0.0, -0.3), Vec3::new(-0.3, 0.6, 0.3)),
                grey,
                glam::Mat4::IDENTITY,
            ),
            Object::new(
                "glass",
                cuboid(Vec3::new(0.3, 0.0, -0.3), Vec3::new(0.9, 0.6, 0.3)),
                Material::glass(1.5),
                glam::Mat4::IDENTITY,
            )
            .with_roles(scene::Roles::REFRACTOR | scene::Roles::CAUSTIC_CASTER),
        ],
        textures: vec![],
        lights: vec![Light {
            name: "light".into(),
            position: Vec3::new(0.5, 2.5, 1.5),
            intensity: Vec3::splat(6.0),
            kind: scene::LightKind::Point,
        }],
        camera: Camera {
            eye: Vec3::new(0.0, 1.6, 3.0),
            target: Vec3::new(0.0, 0.3, 0.0),
            up: Vec3::Y,
            fov_y_deg: 50.0,
            orthographic: None,
        },
        camera_path: Default::default(),
        volumes: vec![],
        medium: None,
        background: Vec3::ZERO,
    }
}

impl Glb {
    /// The exporter's `.glb` of `scene`, opened.
    pub fn from_scene(scene: &Scene) -> Self {
        let bytes = scene::gltf_io::to_glb_bytes(scene).expect("the scene exports");
        Self::parse(&bytes)
    }

    /// Opens a `.glb` (JSON chunk and BIN chunk).
    pub fn parse(bytes: &[u8]) -> Self {
        let word = |o: usize| u32::from_le_bytes(bytes[o..o + 4].try_into().unwrap()) as usize;
        let json_len = word(12);
        let json = serde_json::from_slice(&bytes[20..20 + json_len]).expect("JSON chunk");
        let bin_start = 20 + json_len;
        let bin = if bytes.len() > bin_start + 8 {
            let len = word(bin_start);
            bytes[bin_start + 8..bin_start + 8 + len].to_vec()
        } else {
            Vec::new()
        };
        Glb { json, bin }
    }

    /// The `.glb` bytes.
    pub fn to_bytes(&self) -> Vec<u8> {
        scene::gltf_io::glb(serde_json::to_vec(&self.json).unwrap(), self.bin.clone())
    }

    /// Writes `<dir>/<name>.glb` and returns its path.
    pub fn write_glb(&self, dir: &Path, name: &str) -> PathBuf {
        std::fs::create_dir_all(dir).unwrap();
        let path = dir.join(format!("{name}.glb"));
        std::fs::write(&path, self.to_bytes()).unwrap();
        path
    }

    /// Writes `<dir>/<name>.gltf` whose buffer is the external file named by `buffer_uri`
    /// (written as `<dir>/<name>.bin` when `buffer_uri` is `None`).
    pub fn write_gltf(&self, dir: &Path, name: &str, buffer_uri: Option<&str>) -> PathBuf {
        std::fs::create_dir_all(dir).unwrap();
        let mut json = self.json.clone();
        let uri = match buffer_uri {
            Some(uri) => uri.to_string(),
            None => {
                std::fs::write(dir.join(format!("{name}.bin")), &self.bin).unwrap();
                format!("{name}.bin")
            }
        };
        json["buffers"][0]["uri"] = json!(uri);
        let path = dir.join(format!("{name}.gltf"));
        std::fs::write(&path, serde_json::to_vec_pretty(&json).unwrap()).unwrap();
        path
    }

    /// Index of the node named `name`.
    pub fn node(&self, name: &str) -> usize {
        self.json["nodes"]
            .as_array()
            .unwrap()
            .iter()
            .position(|n| n["name"] == name)
            .unwrap_or_else(|| panic!("no node \"{name}\""))
    }

    /// Removes every `KHR_lights_punctual` light (the file then has no light at all).
    pub fn remove_lights(&mut self) {
        if let Some(ext) = self.json.get_mut("extensions") {
            ext.as_object_mut().unwrap().remove("KHR_lights_punctual");
        }
        for node in self.json["nodes"].as_array_mut().unwrap() {
            if let Some(ext) = node.get_mut("extensions") {
                ext.as_object_mut().unwrap().remove("KHR_lights_punctual");
            }
        }
    }

    /// The bytes of accessor `index` in the binary buffer (tightly packed, as exported).
    pub fn accessor_bytes(&mut self, index: usize) -> &mut [u8] {
        let accessor = &self.json["accessors"][index];
        let view = &self.json["bufferViews"][accessor["bufferView"].as_u64().unwrap() as usize];
        let start = view["byteOffset"].as_u64().unwrap_or(0) as usize;
        let len = view["byteLength"].as_u64().unwrap() as usize;
        &mut self.bin[start..start + len]
    }

    /// The accessor of attribute `semantic` (`NORMAL`) of mesh `mesh`'s first primitive.
    pub fn attribute(&self, mesh: usize, semantic: &str) -> usize {
        self.json["meshes"][mesh]["primitives"][0]["attributes"][semantic]
            .as_u64()
            .unwrap() as usize
    }

    /// Sets `extras.scene_model` of material `index` (the exact material the importer uses).
    pub fn set_material_extras(&mut self, index: usize, value: Value) {
        self.json["materials"][index]["extras"]["scene_model"] = value;
    }

    /// Replaces the camera node's exact extras and its core transform so that the camera at
    /// `eye` looks at `target` with the given `up` (which may be degenerate: the importer
    /// keeps the extras' camera as it is when it agrees with the node).
    pub fn set_camera(&mut self, eye: Vec3, target: Vec3, up: Vec3) {
        let i = self.node("camera");
        let forward = (target - eye).normalize();
        let helper = if forward.y.abs() < 0.9 {
            Vec3::Y
        } else {
            Vec3::Z
        };
        let right = forward.cross(helper).normalize();
        let node_up = right.cross(forward);
        let rot = glam::Quat::from_mat3(&glam::Mat3::from_cols(right, node_up, -forward));
        let node = &mut self.json["nodes"][i];
        node["translation"] = json!(eye.to_array());
        node["rotation"] = json!(rot.to_array());
        node["extras"]["scene_model"]["eye"] = json!(eye.to_array());
        node["extras"]["scene_model"]["target"] = json!(target.to_array());
        node["extras"]["scene_model"]["up"] = json!(up.to_array());
    }
}

/// Standard base64 with padding (for `data:` URIs in hand-written glTF).
pub fn base64(bytes: &[u8]) -> String {
    data_encoding::BASE64.encode(bytes)
}
