//! The extras schema: the exact workspace data under `extras.scene_model` (see the module docs).

use super::*;

pub(super) type V3 = [f64; 3];

pub(super) fn v3(v: Vec3) -> V3 {
    [v.x as f64, v.y as f64, v.z as f64]
}
pub(super) fn vec3(a: V3) -> Vec3 {
    Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32)
}

#[derive(Serialize, Deserialize)]
pub(super) struct SceneExtras {
    pub(super) version: u32,
    pub(super) name: String,
    pub(super) background: V3,
    #[serde(default)]
    pub(super) camera_path: Vec<CameraKeyExtras>,
    #[serde(default)]
    pub(super) volumes: Vec<VolumeExtras>,
    /// The homogeneous scattering medium, when the scene has one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) medium: Option<MediumExtras>,
}

#[derive(Serialize, Deserialize)]
pub(super) struct MediumExtras {
    pub(super) name: String,
    pub(super) min: V3,
    pub(super) max: V3,
    pub(super) scattering: V3,
    pub(super) absorption: V3,
    pub(super) anisotropy: f64,
}

impl MediumExtras {
    pub(super) fn from_medium(m: &crate::Medium) -> Self {
        Self {
            name: m.name.clone(),
            min: v3(m.min),
            max: v3(m.max),
            scattering: v3(m.scattering),
            absorption: v3(m.absorption),
            anisotropy: m.anisotropy as f64,
        }
    }
    pub(super) fn medium(&self) -> crate::Medium {
        crate::Medium {
            name: self.name.clone(),
            min: vec3(self.min),
            max: vec3(self.max),
            scattering: vec3(self.scattering),
            absorption: vec3(self.absorption),
            anisotropy: self.anisotropy as f32,
        }
    }
}

#[derive(Serialize, Deserialize)]
pub(super) struct CameraExtras {
    pub(super) eye: V3,
    pub(super) target: V3,
    pub(super) up: V3,
    pub(super) fov_y_deg: f64,
    /// An orthographic camera's half height (`Camera::orthographic`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) orthographic: Option<f64>,
}

impl CameraExtras {
    pub(super) fn from_camera(c: &Camera) -> Self {
        Self {
            eye: v3(c.eye),
            target: v3(c.target),
            up: v3(c.up),
            fov_y_deg: c.fov_y_deg as f64,
            orthographic: c.orthographic.map(f64::from),
        }
    }
    pub(super) fn camera(&self) -> Camera {
        Camera {
            eye: vec3(self.eye),
            target: vec3(self.target),
            up: vec3(self.up),
            fov_y_deg: self.fov_y_deg as f32,
            orthographic: self.orthographic.map(|h| h as f32),
        }
    }
}

#[derive(Serialize, Deserialize)]
pub(super) struct CameraKeyExtras {
    pub(super) time: f64,
    #[serde(flatten)]
    pub(super) camera: CameraExtras,
}

#[derive(Serialize, Deserialize)]
pub(super) struct KeyExtras {
    pub(super) time: f64,
    pub(super) offset: V3,
}

pub(super) fn motion_extras(m: &Motion) -> Vec<KeyExtras> {
    m.keys
        .iter()
        .map(|(t, o)| KeyExtras {
            time: *t as f64,
            offset: v3(*o),
        })
        .collect()
}
pub(super) fn motion_from(keys: &[KeyExtras]) -> Motion {
    Motion {
        keys: keys
            .iter()
            .map(|k| (k.time as f32, vec3(k.offset)))
            .collect(),
    }
}

#[derive(Serialize, Deserialize)]
pub(super) struct VolumeExtras {
    pub(super) name: String,
    pub(super) center: V3,
    pub(super) radius: f64,
    pub(super) color: V3,
    pub(super) density: f64,
    /// Absent in files written before the density profile existed: a uniform ball.
    #[serde(default)]
    pub(super) profile: Option<ProfileExtras>,
    pub(super) particle: bool,
    #[serde(default)]
    pub(super) motion: Vec<KeyExtras>,
}

#[derive(Serialize, Deserialize)]
pub(super) struct ProfileExtras {
    pub(super) falloff: f64,
    pub(super) noise: f64,
    pub(super) noise_frequency: f64,
}

impl ProfileExtras {
    pub(super) fn from_profile(p: &DensityProfile) -> Self {
        Self {
            falloff: p.falloff as f64,
            noise: p.noise as f64,
            noise_frequency: p.noise_frequency as f64,
        }
    }
    pub(super) fn profile(&self) -> DensityProfile {
        DensityProfile {
            falloff: self.falloff as f32,
            noise: self.noise as f32,
            noise_frequency: self.noise_frequency as f32,
        }
    }
}

#[derive(Serialize, Deserialize)]
pub(super) struct BuildingExtras {
    pub(super) room_size: V3,
}

#[derive(Serialize, Deserialize)]
pub(super) struct ObjectExtras {
    #[serde(default)]
    pub(super) roles: Vec<String>,
    #[serde(default)]
    pub(super) motion: Vec<KeyExtras>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) building: Option<BuildingExtras>,
}

#[derive(Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub(super) enum MaterialExtras {
    Diffuse {
        albedo: V3,
        /// The exact emission (the core's emissive factor times strength rounds it).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        emission: Option<V3>,
    },
    Metal {
        n: V3,
        k: V3,
    },
    Glass {
        ior: f64,
    },
}

#[derive(Serialize, Deserialize)]
pub(super) struct LightExtras {
    pub(super) intensity: V3,
    /// A spot's or directional light's exact direction (the node's rotation carries it
    /// rounded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) direction: Option<V3>,
    /// A spot's exact inner and outer cone angles (the core's inner angle is written below
    /// the outer where they are equal).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) cone: Option<[f64; 2]>,
}

/// `{"scene_model": value}`.
pub(super) fn wrap<T: Serialize>(value: &T) -> Value {
    let mut map = serde_json::Map::new();
    map.insert(
        EXTRAS_KEY.to_string(),
        serde_json::to_value(value).unwrap_or(Value::Null),
    );
    Value::Object(map)
}

/// Reads `extras.scene` of a glTF object as `T`, `None` when absent.
pub(super) fn read_extras<T: for<'de> Deserialize<'de>>(
    extras: &gltf::json::Extras,
    what: &str,
) -> Result<Option<T>, String> {
    let Some(raw) = extras else { return Ok(None) };
    let value: Value = serde_json::from_str(raw.get())
        .map_err(|e| format!("the extras of {what} are not JSON: {e}"))?;
    match value.get(EXTRAS_KEY) {
        None | Some(Value::Null) => Ok(None),
        Some(v) => T::deserialize(v).map(Some).map_err(|e| {
            format!("the extras.{EXTRAS_KEY} of {what} do not follow the schema: {e}")
        }),
    }
}
