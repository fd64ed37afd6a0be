//! A renderer's own object uploaded alone, for a technique's pass in the renderer's frame
//! ([`HostedPass`]: `impostors::ImpostorPass`, `image_space_refraction::RefractorPass`): the
//! technique draws the object from this copy and asks the renderer ([`gpu::DrawScene`]) for
//! everything else.

use crate::{Camera, GpuScene, Material, Mesh, Object, Scene, Technique, TechniqueError};
use crate::{Frame, TechniqueResult};
use glam::{Mat4, Vec2, Vec3};
use gpu::{DrawScene, EyeView, HostedMesh, Objects, SceneView, TargetFormats, wgpu};

/// A technique that draws its objects over a frame that already holds everything else, asking
/// the frame's renderer for the views of the world it needs.
pub trait DrawOver: Technique {
    /// The objects of `objects` drawn into `color` and `depth` (a renderer's targets, holding
    /// its frame) as `view` sees them, with `host` drawing the world on request.
    fn draw_over(
        &mut self,
        frame: &mut Frame,
        hosted: (&GpuScene, &dyn DrawScene),
        view: &EyeView,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
    ) -> TechniqueResult<()>;
}

/// One renderer's object drawn by technique `T` over the renderer's frame: the pass a technique
/// crate hands a user (`impostors::ImpostorPass` and `image_space_refraction::RefractorPass`
/// wrap one each and say how to make it).
pub struct HostedPass<T> {
    technique: T,
    object: HostedObject,
}

impl<T: DrawOver> HostedPass<T> {
    /// `technique` (already made for `formats`) prepared on the renderer's object: `mesh` of
    /// `material`, its index `host_index`. Formats the device cannot draw into are refused.
    pub fn new(
        ctx: &gpu::Context,
        formats: TargetFormats,
        (mesh, material, host_index): (&HostedMesh, Material, usize),
        mut technique: T,
    ) -> TechniqueResult<Self> {
        formats.check(ctx)?;
        let mut object = HostedObject::new(ctx, mesh, material, host_index)?;
        object.prepare(ctx, &mut technique)?;
        Ok(Self { technique, object })
    }

    /// Moves the object by `offset` from where its mesh puts it, from the next frame on.
    pub fn set_position(&mut self, offset: Vec3) {
        self.object.set_offset(offset);
    }

    /// Records the object into `color` and `depth` as seen by `view`, asking `host` for the
    /// world around it, depth-tested against the renderer's frame.
    pub fn draw(
        &mut self,
        frame: &mut Frame,
        host: &dyn DrawScene,
        view: &EyeView,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
    ) -> TechniqueResult<()> {
        let (object, host) = self.object.for_frame(frame, host);
        let hosted: (&GpuScene, &dyn DrawScene) = (object, &host);
        self.technique.draw_over(frame, hosted, view, color, depth)
    }
}

/// The renderer's object, uploaded alone (no lights: the maps the technique asks for hold
/// the renderer's lit world), and its index among the renderer's objects.
pub struct HostedObject {
    uploaded: GpuScene,
    host_index: usize,
    /// The offset `set_offset` asked for, applied at the next frame.
    pending_offset: Option<Vec3>,
}

impl HostedObject {
    /// `mesh` of `material`, the renderer's object `host_index`, uploaded.
    pub fn new(
        ctx: &gpu::Context,
        mesh: &HostedMesh,
        material: Material,
        host_index: usize,
    ) -> TechniqueResult<Self> {
        let scene = object_scene(mesh, material)?;
        Ok(Self {
            uploaded: GpuScene::new(ctx, &scene)?,
            host_index,
            pending_offset: None,
        })
    }

    /// Prepares `technique` on the object (its maps, pipelines), recorded and submitted now;
    /// a validation error (a target format the device cannot render into, say) is a
    /// [`TechniqueError`], not wgpu's panic.
    pub fn prepare(
        &mut self,
        ctx: &gpu::Context,
        technique: &mut dyn Technique,
    ) -> TechniqueResult<()> {
        let uploaded = &mut self.uploaded;
        ctx.validated(|| {
            let mut encoder = ctx.device.create_command_encoder(&Default::default());
            let prepared = Frame::untimed(ctx, &mut encoder, |frame| {
                uploaded.set_time(frame, 0.0);
                technique.prepare(frame, uploaded)
            });
            ctx.queue.submit([encoder.finish()]);
            prepared
        })?
    }

    /// Moves the object by `offset` from where its mesh puts it, from the next frame on.
    pub fn set_offset(&mut self, offset: Vec3) {
        self.pending_offset = Some(offset);
    }

    /// The uploaded object at its current offset (recorded into `frame`), and the renderer as
    /// host with the object's index turned into the renderer's own.
    pub fn for_frame<'a>(
        &'a mut self,
        frame: &mut Frame,
        host: &'a dyn DrawScene,
    ) -> (&'a GpuScene, HostForObject<'a>) {
        if let Some(offset) = self.pending_offset.take() {
            let placed = Mat4::from_translation(offset);
            self.uploaded.set_transform(frame, 0, placed);
        }
        let index = self.host_index;
        (&self.uploaded, HostForObject { host, index })
    }
}

/// The one-object scene of a renderer's object.
fn object_scene(mesh: &HostedMesh, material: Material) -> TechniqueResult<Scene> {
    if mesh.positions.len() != mesh.normals.len() {
        return Err(TechniqueError::Unsupported(format!(
            "the renderer's object has {} positions but {} normals",
            mesh.positions.len(),
            mesh.normals.len()
        )));
    }
    let mesh = Mesh {
        positions: mesh.positions.clone(),
        normals: mesh.normals.clone(),
        uvs: vec![Vec2::ZERO; mesh.positions.len()],
        indices: mesh.indices.clone(),
    };
    Ok(Scene {
        name: "hosted object".into(),
        objects: vec![Object::new("hosted", mesh, material, Mat4::IDENTITY)],
        textures: Vec::new(),
        lights: Vec::new(),
        camera: Camera {
            eye: Vec3::new(0.0, 0.0, 3.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y_deg: 45.0,
        },
        camera_path: Default::default(),
        volumes: Vec::new(),
        medium: None,
        background: Vec3::ZERO,
    })
}

/// The renderer as host of the object: its index in the one-object upload (0) turned into the
/// renderer's own in every list a technique passes.
pub struct HostForObject<'a> {
    host: &'a dyn DrawScene,
    index: usize,
}

impl DrawScene for HostForObject<'_> {
    fn draw_scene(&self, frame: &mut Frame, view: &SceneView) {
        // The upload holds one object, index 0: a list names it or nothing.
        let renamed = |list: &[usize]| -> Vec<usize> {
            list.iter()
                .filter(|&&i| i == 0)
                .map(|_| self.index)
                .collect()
        };
        let (only, all_but);
        let objects = match view.objects {
            Objects::All => Objects::All,
            Objects::Only(list) => {
                only = renamed(list);
                Objects::Only(&only)
            }
            Objects::AllBut(list) => {
                all_but = renamed(list);
                Objects::AllBut(&all_but)
            }
        };
        let view = SceneView {
            objects,
            view_proj: view.view_proj,
            eye: view.eye,
            color: view.color,
            color_format: view.color_format,
            depth: view.depth,
        };
        self.host.draw_scene(frame, &view);
    }
}
