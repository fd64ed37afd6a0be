//! The baseline: the same rooms as real geometry, drawn by the shared raster pass.

use super::*;

/// The baseline: the same rooms as real geometry (a facade with window holes and planes
/// spanning each box hull, as the paper's polygonised building), drawn by the shared raster
/// pass. Box hulls that already have real interiors in the scene are kept as they are;
/// curved hulls (cylinder, sphere) stay solid.
pub struct PolygonInteriors {
    /// Multiplies each building's room size (parameter `room_scale`).
    pub room_scale: f32,
    /// Interior texture size, texels per side (parameter `texture_resolution`).
    pub texture_resolution: u32,
    state: Option<GpuScene>,
}

impl Default for PolygonInteriors {
    fn default() -> Self {
        Self {
            room_scale: 1.0,
            texture_resolution: 64,
            state: None,
        }
    }
}

/// The scene with real room geometry in every box building (what `interior-mapping/polygons` draws).
pub fn polygon_scene(scene: &Scene, room_scale: f32, texture_resolution: u32) -> Scene {
    let mut out = scene.clone();
    let base = out.textures.len();
    out.textures
        .extend(textures::scene_textures(texture_resolution));
    let mut added = Vec::new();
    for o in &mut out.objects {
        let Some(b) = o.building else { continue };
        if !o.name.contains("(box)") || has_window_holes(o) {
            continue;
        }
        let (lo, hi) = o.mesh.bounds();
        let room = b.room_size * room_scale;
        o.mesh = crate::geometry::facade_with_windows(lo, hi, room);
        o.name = o.name.replace("(box)", "(box, window holes)");
        for (family, name, texture) in [
            (1u32, "floors", 0usize),
            (4, "ceilings", 1),
            (0, "walls x", 2),
            (2, "walls z", 3),
        ] {
            let material = Material::Diffuse {
                albedo: Vec3::ONE,
                texture: Some(base + texture),
                cutout: None,
            };
            let mut planes = Object::new(
                &format!("{} {name}", o.name),
                crate::geometry::room_planes(lo, hi, room, family),
                material,
                o.transform,
            )
            .with_roles(Roles::BUILDING);
            planes.motion = o.motion.clone();
            added.push(planes);
        }
    }
    out.objects.extend(added);
    out
}

impl Technique for PolygonInteriors {
    fn id(&self) -> String {
        "interior-mapping/polygons".into()
    }
    fn description(&self) -> String {
        "baseline: the same rooms as real geometry (facade with window holes, room planes) through the shared raster pass".into()
    }
    fn params(&self) -> Vec<Param> {
        vec![
            Param {
                name: "room_scale",
                default: self.room_scale as f64,
                min: 0.05,
                max: 20.0,
                integer: false,
                help: "multiplies each building's room size",
            },
            Param {
                name: "texture_resolution",
                default: self.texture_resolution as f64,
                min: 16.0,
                max: 256.0,
                integer: true,
                help: "interior texture size (texels per side)",
            },
        ]
    }
    fn set_param(&mut self, name: &str, value: f64) -> TechniqueResult<()> {
        check_param(&self.id(), &self.params(), name, value)?;
        match name {
            "room_scale" => self.room_scale = value as f32,
            _ => self.texture_resolution = value as u32,
        }
        Ok(())
    }
    fn supports(&self, scene: &Scene) -> bool {
        has_buildings(scene)
    }
    fn prepare(&mut self, frame: &mut Frame, scene: &GpuScene) -> TechniqueResult<()> {
        let modified = polygon_scene(&scene.scene, self.room_scale, self.texture_resolution);
        self.state = Some(GpuScene::new(frame.gpu, &modified)?);
        Ok(())
    }
    fn render(
        &mut self,
        frame: &mut Frame,
        _scene: &GpuScene,
        view: &View,
        target: &Target,
    ) -> TechniqueResult<()> {
        let Some(state) = self.state.as_mut() else {
            return Err(not_prepared(self));
        };
        state.set_time(frame, view.time);
        let view_proj: Mat4 = view.camera.view_proj(view.width, view.height);
        let main = RasterTarget::of(target, true);
        state.raster(
            frame,
            &main,
            view_proj,
            view.camera.eye,
            &ObjectFilter::All,
            true,
        );
        Ok(())
    }
}
