//! A complete scene: its objects, lights, camera and volumes, the queries on them, and what makes one valid (`Scene::validate` and its limits).

use super::*;

/// A complete scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    pub name: String,
    pub objects: Vec<Object>,
    pub textures: Vec<Texture>,
    pub lights: Vec<Light>,
    pub camera: Camera,
    pub camera_path: CameraPath,
    pub volumes: Vec<Volume>,
    /// A homogeneous scattering medium (the murky pool's water), or none.
    pub medium: Option<crate::Medium>,
    /// Radiance of rays that leave the scene.
    pub background: Vec3,
}

impl Scene {
    /// Indices of the objects with any of `roles`.
    pub fn objects_with(&self, roles: Roles) -> Vec<usize> {
        (0..self.objects.len())
            .filter(|&i| self.objects[i].roles.intersects(roles))
            .collect()
    }
    /// Indices of the objects with a specular material (metal or glass): the objects that
    /// techniques keeping a map per specular object make maps for.
    pub fn specular_objects(&self) -> Vec<usize> {
        (0..self.objects.len())
            .filter(|&i| self.objects[i].material.is_specular())
            .collect()
    }
    /// The objects a technique treats specially (everything but plain diffuse scenery).
    pub fn special_objects(&self) -> Vec<usize> {
        (0..self.objects.len())
            .filter(|&i| !self.objects[i].roles.is_empty())
            .collect()
    }
    pub fn triangle_count(&self) -> usize {
        self.objects.iter().map(|o| o.mesh.triangle_count()).sum()
    }
    /// The camera at `time`: on the camera path if the scene has one, else the default view.
    pub fn camera_at(&self, time: f32) -> Camera {
        self.camera_path.sample(time).unwrap_or(self.camera)
    }

    /// Lights a scene that has no light the way model viewers do, and says so: a white key
    /// light above and to the right of the camera, as bright as needed for a white diffuse
    /// surface at the centre of the objects' bounds to show a radiance of 0.6, and, when the
    /// background is black, a uniform sky of radiance [`DEFAULT_SKY`] that specular surfaces
    /// reflect. The importer calls it for a glTF file without `KHR_lights_punctual`
    /// lights (without it every pixel would be black and every technique would score a
    /// perfect, meaningless, 0 error). Returns the note the harness prints and records.
    pub fn add_default_lighting(&mut self) -> String {
        let (lo, hi) = world_bounds(&self.objects);
        let (center, radius) = if lo.cmple(hi).all() {
            ((lo + hi) * 0.5, ((hi - lo).length() * 0.5).max(1e-3))
        } else {
            (self.camera.target, 1.0)
        };
        let (_, right, up) = self.camera.basis();
        let reach = self.camera.eye.distance(center).min(radius).max(1e-3);
        let position = self.camera.eye + (0.4 * up + 0.2 * right) * reach;
        let d2 = position.distance_squared(center).max(1e-6);
        let intensity = Vec3::splat(0.6 * std::f32::consts::PI * d2);
        self.lights.push(Light {
            name: "default key light".into(),
            position,
            intensity,
            kind: crate::LightKind::Point,
        });
        let mut note = format!(
            "the scene has no light: added a default key light of {:.3} W/sr at \
             ({:.3}, {:.3}, {:.3}), above and right of the camera",
            intensity.x, position.x, position.y, position.z
        );
        if self.background == Vec3::ZERO {
            self.background = DEFAULT_SKY;
            note.push_str(&format!(
                ", and a uniform sky of radiance ({}, {}, {})",
                DEFAULT_SKY.x, DEFAULT_SKY.y, DEFAULT_SKY.z
            ));
        }
        note
    }

    /// Checks every number that reaches the renderers: a NaN or infinite transform, position,
    /// light or camera, or a texture index out of range, is an error here rather than a NaN
    /// image later.
    pub fn validate(&self) -> Result<(), crate::SceneError> {
        let bad = |what: String| Err(crate::SceneError::Invalid(what));
        let triangles = self.triangle_count();
        if triangles > MAX_TRIANGLES {
            return bad(format!(
                "the scene has {triangles} triangles; the renderers keep every world-space \
                 triangle (the reference in one BVH, about 400 bytes each while it is built) and \
                 accept at most {MAX_TRIANGLES}"
            ));
        }
        for o in &self.objects {
            if let Some(why) = self.object_problem(o) {
                return bad(why);
            }
        }
        for l in &self.lights {
            if let Some(why) = light_problem(l) {
                return bad(why);
            }
        }
        if !(self.background.is_finite() && self.background.min_element() >= 0.0) {
            return bad(format!(
                "the background radiance {} is negative or not finite",
                self.background
            ));
        }
        for v in &self.volumes {
            v.validate()?;
        }
        if let Some(m) = &self.medium {
            m.validate()?;
        }
        let c = &self.camera;
        if !c.eye.is_finite() || !c.target.is_finite() || c.eye == c.target {
            return bad("the camera is not finite or looks at its own eye".into());
        }
        let farthest_eye = self
            .camera_path
            .keys
            .iter()
            .map(|(_, k)| k.eye.abs().max_element())
            .fold(c.eye.abs().max_element(), f32::max);
        if !(farthest_eye <= MAX_WORLD_COORDINATE) {
            return bad(format!(
                "the camera (or its path) is {farthest_eye:e} m from the origin, beyond the \
                 {MAX_WORLD_COORDINATE:e} m the renderers accept"
            ));
        }
        match c.orthographic {
            Some(h) if !(h > 0.0 && h <= MAX_WORLD_COORDINATE) => {
                return bad(format!(
                    "the orthographic camera's half height {h} is not in (0, \
                     {MAX_WORLD_COORDINATE:e}] m"
                ));
            }
            Some(_) => {}
            None if !(c.fov_y_deg > 0.0 && c.fov_y_deg < 180.0) => {
                return bad(format!(
                    "camera field of view {} is not in (0, 180)",
                    c.fov_y_deg
                ));
            }
            None => {}
        }
        let mixed = self.camera_path.keys.iter().find(|(_, k)| {
            k.is_orthographic() != c.is_orthographic()
                || k.orthographic
                    .is_some_and(|h| !(h > 0.0 && h <= MAX_WORLD_COORDINATE))
        });
        if let Some((time, _)) = mixed {
            return bad(format!(
                "the camera path's key at {time} s is not a camera of the scene's kind ({}) \
                 with a valid view",
                if c.is_orthographic() {
                    "orthographic"
                } else {
                    "pinhole"
                }
            ));
        }
        Ok(())
    }

    /// What is wrong with object `o` (the first problem [`Scene::validate`] reports), if
    /// anything.
    fn object_problem(&self, o: &Object) -> Option<String> {
        if !o.transform.is_finite() {
            return Some(format!("object \"{}\" has a non-finite transform", o.name));
        }
        if !o.emission.is_finite() || o.emission.min_element() < 0.0 {
            return Some(format!(
                "object \"{}\" has emission {}; it needs finite values of 0 or more",
                o.name, o.emission
            ));
        }
        if o.emission != Vec3::ZERO && o.material.is_specular() {
            return Some(format!(
                "object \"{}\" is {} and emits {}; only diffuse surfaces emit",
                o.name,
                o.material.kind_name(),
                o.emission
            ));
        }
        if o.mesh.positions.iter().any(|p| !p.is_finite())
            || o.mesh.normals.iter().any(|n| !n.is_finite())
        {
            return Some(format!("object \"{}\" has non-finite vertices", o.name));
        }
        if o.mesh.normals.len() != o.mesh.positions.len()
            || o.mesh.uvs.len() != o.mesh.positions.len()
        {
            return Some(format!(
                "object \"{}\" has mismatched vertex attributes",
                o.name
            ));
        }
        if o.mesh.indices.len() % 3 != 0
            || o.mesh
                .indices
                .iter()
                .any(|&i| i as usize >= o.mesh.positions.len())
        {
            return Some(format!(
                "object \"{}\" has invalid triangle indices",
                o.name
            ));
        }
        if let Some(why) = transform_problem(o.transform) {
            return Some(format!("object \"{}\" has a {why} transform", o.name));
        }
        if let Some(n) = o
            .mesh
            .normals
            .iter()
            .position(|n| !(n.length_squared().is_finite() && n.length_squared() >= 1e-12))
        {
            return Some(format!(
                "object \"{}\" has a zero-length or non-finite normal at vertex {n} \
                 (`Mesh::repair_normals` replaces such normals by geometric ones)",
                o.name
            ));
        }
        if let Some(why) = o.morph.as_ref().and_then(|m| check_morph(o, m).err()) {
            return Some(why);
        }
        if let Some(why) = o.material.check() {
            return Some(format!("object \"{}\" has a {why}", o.name));
        }
        if let Some(extent) = o.world_extent() {
            if !(extent <= MAX_WORLD_COORDINATE) {
                return Some(format!(
                    "object \"{}\" reaches {extent:e} m from the origin; the renderers \
                     work in single precision and accept world coordinates up to \
                     {MAX_WORLD_COORDINATE:e} m",
                    o.name
                ));
            }
        }
        if let Material::Diffuse {
            texture, cutout, ..
        } = o.material
        {
            if let Some(t) = texture.filter(|&t| t >= self.textures.len()) {
                return Some(format!("object \"{}\" uses missing texture {t}", o.name));
            }
            if let Some(c) = cutout {
                if texture.is_none() {
                    return Some(format!(
                        "object \"{}\" has an alpha cut-out but no texture to read alpha from",
                        o.name
                    ));
                }
                if !(c > 0.0 && c <= 1.0) {
                    return Some(format!(
                        "object \"{}\" has an alpha cut-out of {c}; it must lie in (0, 1]",
                        o.name
                    ));
                }
            }
        }
        None
    }
}

/// The proxy box of a box-projected (parallax-corrected) reflection probe: the world bounds
/// of the scene's non-specular objects at time 0 (in the Cornell scenes, the room). Engines
/// place this box by hand around a probe; the room's bounds are what an artist would draw
/// there. `None` for a scene with no diffuse object: a probe is then looked up by direction.
/// `impostors/box-projected` and `image-space-refraction/thickness-proxy-probe` use it.
pub fn probe_proxy_box(scene: &Scene) -> Option<(Vec3, Vec3)> {
    let diffuse = scene.objects.iter().filter(|o| !o.material.is_specular());
    let (lo, hi) = bounds_of(diffuse);
    lo.cmple(hi).all().then_some((lo, hi))
}

/// What is wrong with light `l` (the first problem [`Scene::validate`] reports), if anything.
fn light_problem(l: &Light) -> Option<String> {
    if !l.position.is_finite() || !l.intensity.is_finite() {
        return Some(format!("light \"{}\" is not finite", l.name));
    }
    if l.intensity.min_element() < 0.0 {
        return Some(format!(
            "light \"{}\" has a negative intensity {}",
            l.name, l.intensity
        ));
    }
    if !(l.position.abs().max_element() <= MAX_WORLD_COORDINATE) {
        return Some(format!(
            "light \"{}\" is {:e} m from the origin, beyond the {MAX_WORLD_COORDINATE:e} m \
             the renderers accept",
            l.name,
            l.position.abs().max_element()
        ));
    }
    l.kind_problem()
}

/// Where an engine's reflection probe serving the scene's specular objects is placed: the
/// centre of their bounds (base meshes, time 0), where an artist puts the probe for them.
/// The centre of the proxy box ([`probe_proxy_box`]) is not safe: in `chess` it lies inside
/// the board, whose probe then sees the board's inside. `None` without specular objects.
pub fn probe_centre(scene: &Scene) -> Option<Vec3> {
    let (lo, hi) = bounds_of(scene.objects.iter().filter(|o| o.material.is_specular()));
    lo.cmple(hi).all().then_some((lo + hi) * 0.5)
}

/// World-space bounds (min, max) of the objects' vertices under their transforms, without
/// motion or deformation (the base meshes); empty bounds are (+inf, -inf).
pub fn world_bounds(objects: &[Object]) -> (Vec3, Vec3) {
    bounds_of(objects.iter())
}

/// [`world_bounds`] of any objects, borrowed.
pub(super) fn bounds_of<'a>(objects: impl Iterator<Item = &'a Object>) -> (Vec3, Vec3) {
    objects
        .flat_map(|o| {
            o.mesh
                .positions
                .iter()
                .map(|p| o.transform.transform_point3(*p))
        })
        .fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(p), hi.max(p)),
        )
}

/// Why `morph` cannot deform `o`, as a sentence, or `Ok`: the target has one finite position
/// and one finite, non-zero normal per vertex of the mesh, and the keys have finite,
/// increasing times and finite weights in [0, 1].
pub(super) fn check_morph(o: &Object, morph: &Morph) -> Result<(), String> {
    let name = &o.name;
    let vertices = o.mesh.positions.len();
    if morph.positions.len() != vertices || morph.normals.len() != vertices {
        return Err(format!(
            "object \"{name}\" has a morph target of {} positions and {} normals for a mesh \
             of {vertices} vertices (a target has one of each per vertex)",
            morph.positions.len(),
            morph.normals.len()
        ));
    }
    if morph.positions.iter().any(|p| !p.is_finite()) {
        return Err(format!(
            "object \"{name}\" has a non-finite morph target position"
        ));
    }
    if let Some(n) = morph
        .normals
        .iter()
        .position(|n| !(n.length_squared().is_finite() && n.length_squared() >= 1e-12))
    {
        return Err(format!(
            "object \"{name}\" has a zero-length or non-finite morph target normal at vertex {n}"
        ));
    }
    if let Some((t, w)) = morph.keys.iter().find(|(_, w)| !(0.0..=1.0).contains(w)) {
        return Err(format!(
            "object \"{name}\" has a morph weight {w} at t = {t}, outside [0, 1]"
        ));
    }
    if morph.keys.iter().any(|(t, _)| !t.is_finite())
        || morph.keys.windows(2).any(|k| !(k[0].0 < k[1].0))
    {
        return Err(format!(
            "object \"{name}\" has morph keys whose times are not finite and increasing"
        ));
    }
    Ok(())
}

/// Radiance of the uniform sky [`Scene::add_default_lighting`] gives a scene with a black
/// background.
pub const DEFAULT_SKY: Vec3 = Vec3::new(0.25, 0.28, 0.32);

/// Most triangles a scene may have (over all objects, counted once per object: a mesh shared
/// by 2000 nodes counts 2000 times). The reference flattens every object into one BVH of
/// world-space triangles, about 400 bytes per triangle while it is built: 4 million take
/// about 1.6 GB and 15 s on two cores; 2000 spheres of 9024 triangles (18 million) took 66 s
/// and 6.9 GB before this limit.
pub const MAX_TRIANGLES: usize = 4_000_000;

/// Largest world coordinate (metres, any axis) of a vertex, light or camera the renderers
/// accept. They compute in single precision: at 10 km a coordinate still resolves 1 mm, and
/// the rasterizer's far plane ([`Camera::FAR`]) is 1 km from the eye anyway.
pub const MAX_WORLD_COORDINATE: f32 = 1.0e4;

/// Largest condition number (Frobenius norms of the 3x3 part and of its inverse) of an object
/// transform: beyond it the transform flattens the object into (nearly) a plane or a line,
/// and normals transformed by its inverse transpose lose all precision. A uniform scale of any
/// size has condition 3; only the *shape* of the transform is judged, never its size (a node
/// scaled by 1e-4 around vertices scaled by 1e4 is fine).
pub const MAX_TRANSFORM_CONDITION: f32 = 1.0e6;

/// Largest Frobenius norm of an object transform's inverse (a uniform scale of 1e-15 has
/// about 1.7e15): past it, squared lengths of normals transformed by the normal matrix
/// overflow single precision.
pub(super) const MAX_INVERSE_SCALE: f32 = 1.0e16;

/// `None` for a usable object transform, else why not ("singular", "nearly singular").
pub(super) fn transform_problem(transform: Mat4) -> Option<&'static str> {
    let frobenius = |m: Mat3| {
        (m.x_axis.length_squared() + m.y_axis.length_squared() + m.z_axis.length_squared()).sqrt()
    };
    // Scaled to unit norm first: the condition number does not depend on the scale, and the
    // determinant and inverse of a tiny uniform scale (1e-20) stay representable.
    let norm = frobenius(Mat3::from_mat4(transform));
    if !(norm > 0.0 && norm.is_finite()) {
        return Some("singular");
    }
    let m = Mat3::from_mat4(transform) * (1.0 / norm);
    let inverse = m.inverse();
    if m.determinant() == 0.0 || !inverse.is_finite() {
        return Some("singular");
    }
    // The exact inverse is what the shaders use (normal matrix, world-to-object): it must stay
    // small enough that a transformed unit vector's squared length is finite.
    let exact_inverse = Mat3::from_mat4(transform).inverse();
    if !(frobenius(exact_inverse) <= MAX_INVERSE_SCALE) {
        return Some("too strongly shrinking (scale below 1e-15)");
    }
    let condition = frobenius(m) * frobenius(inverse);
    (!(condition <= MAX_TRANSFORM_CONDITION)).then_some("nearly singular (flattening)")
}

impl Volume {
    /// The numbers a renderer needs are finite and in range: radius > 0, density >= 0,
    /// falloff >= 0, noise in [0, 1], noise frequency > 0.
    pub fn validate(&self) -> Result<(), crate::SceneError> {
        let p = &self.profile;
        let finite = self.center.is_finite()
            && self.color.is_finite()
            && self.radius.is_finite()
            && self.density.is_finite()
            && p.falloff.is_finite()
            && p.noise.is_finite()
            && p.noise_frequency.is_finite()
            && self
                .motion
                .keys
                .iter()
                .all(|(t, v)| t.is_finite() && v.is_finite());
        let in_range = self.radius > 0.0
            && self.density >= 0.0
            && p.falloff >= 0.0
            && (0.0..=1.0).contains(&p.noise)
            && p.noise_frequency > 0.0;
        let bad = |what: &str| {
            Err(crate::SceneError::Invalid(format!(
                "volume \"{}\" {what}",
                self.name
            )))
        };
        if !finite {
            bad("is not finite")
        } else if !in_range {
            bad(
                "needs radius > 0, density >= 0, falloff >= 0, noise in [0, 1] and noise frequency > 0",
            )
        } else {
            Ok(())
        }
    }
}
