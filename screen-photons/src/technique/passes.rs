//! The passes of a frame and the function that orders them ([`Passes::frame`]).

use super::*;

/// The pipelines and bind-group layouts (per scene: they use its layouts).
pub(super) struct Passes {
    /// A scene with a scattering medium only.
    pub(super) medium: Option<MediumPasses>,
    /// The bind-group layouts of the passes' own bindings (group 3; the LDIs' group 2).
    pub(super) layouts: Layouts,
    // The pipelines of the variant's passes only ([`Passes::new`]; [`made`] takes one out).
    pub(super) transfer: Option<wgpu::RenderPipeline>,
    pub(super) shadow_mask: Option<wgpu::ComputePipeline>,
    pub(super) shadowed: Option<wgpu::RenderPipeline>,
    pub(super) gather: Option<wgpu::ComputePipeline>,
    pub(super) lines: Option<wgpu::RenderPipeline>,
    pub(super) reduce: Option<wgpu::ComputePipeline>,
    /// The per-photon march: the DDA or the tolerance test in one invocation per photon.
    pub(super) per_photon: Option<wgpu::ComputePipeline>,
    pub(super) resolve: Option<wgpu::ComputePipeline>,
    pub(super) splat: Option<wgpu::RenderPipeline>,
    pub(super) apply: Option<wgpu::RenderPipeline>,
    pub(super) specular: wgpu::RenderPipeline,
}

/// A pipeline of the variant's passes: [`Passes::new`] made it (a variant asking for one it
/// did not make is a bug in this file, not an input error).
pub(super) fn made<T>(pipeline: &Option<T>) -> &T {
    pipeline
        .as_ref()
        .expect("Passes::new makes every pipeline the variant's passes use")
}

/// The bind-group layouts of the passes' own bindings: the LDIs' (group 2 of every pass) and
/// each pass's group 3.
pub(super) struct Layouts {
    pub(super) ldi: wgpu::BindGroupLayout,
    pub(super) transfer: wgpu::BindGroupLayout,
    pub(super) gather: wgpu::BindGroupLayout,
    pub(super) lines: wgpu::BindGroupLayout,
    pub(super) reduce: wgpu::BindGroupLayout,
    pub(super) dda: wgpu::BindGroupLayout,
    pub(super) resolve: wgpu::BindGroupLayout,
    pub(super) splat: wgpu::BindGroupLayout,
    pub(super) apply: wgpu::BindGroupLayout,
    pub(super) specular: wgpu::BindGroupLayout,
    pub(super) shadow_mask: wgpu::BindGroupLayout,
    pub(super) shadowed: wgpu::BindGroupLayout,
}

impl Layouts {
    fn new(ctx: &Context) -> Self {
        use bind::{layout, storage, uniform};
        use wgpu::ShaderStages as S;
        let layers = bind::texture(wgpu::TextureViewDimension::D2Array, false);
        let map = bind::texture_2d_unfilterable();
        let (read, write) = (storage(true), storage(false));
        let all = S::VERTEX_FRAGMENT | S::COMPUTE;
        Self {
            ldi: layout(
                ctx,
                "ldi",
                all,
                &[uniform(), layers, layers, layers, layers],
            ),
            transfer: layout(ctx, "transfer", S::FRAGMENT, &[uniform()]),
            gather: layout(
                ctx,
                "gather",
                S::COMPUTE,
                &[map, map, write, write, uniform()],
            ),
            lines: layout(ctx, "lines", S::VERTEX_FRAGMENT, &[read, uniform()]),
            reduce: layout(ctx, "reduce", S::COMPUTE, &[map, write, uniform()]),
            dda: layout(ctx, "dda", S::COMPUTE, &[read, write]),
            resolve: layout(
                ctx,
                "resolve",
                S::COMPUTE,
                &[write, read, write, uniform(), write],
            ),
            splat: layout(ctx, "splat", S::VERTEX_FRAGMENT, &[read, uniform()]),
            apply: layout(ctx, "apply", S::FRAGMENT, &[map]),
            specular: layout(ctx, "specular", S::FRAGMENT, &[uniform()]),
            shadow_mask: layout(ctx, "shadow mask", S::COMPUTE, &[write]),
            shadowed: layout(ctx, "shadowed", S::FRAGMENT, &[read]),
        }
    }
}

/// A pass that draws scene objects into the HDR target with the fragment entry `entry` of
/// `own` (composed with the scene's and the passes' modules, the LDI among them), blended by `blend`, with
/// the depth state `(write, compare)`.
fn hdr_pipeline(
    ctx: &Context,
    layout: &wgpu::PipelineLayout,
    label: &str,
    own: &str,
    entry: &str,
    blend: Option<wgpu::BlendState>,
    depth: (bool, wgpu::CompareFunction),
) -> wgpu::RenderPipeline {
    let module = pass_shader(ctx, label, own);
    let targets = [pass::color_target(gpu::HDR_FORMAT, blend)];
    scene::scene_pipeline_with(ctx, label, layout, &module, entry, &targets, depth)
}

/// The transfer map's pass: every object drawn from the light into two map targets.
fn transfer_pipeline(
    ctx: &Context,
    scene: &GpuScene,
    own: &wgpu::BindGroupLayout,
) -> wgpu::RenderPipeline {
    let module = scene::shader(ctx, "transfer map", TRANSFER_WGSL);
    let targets = [
        pass::color_target(MAP_FORMAT, None),
        pass::color_target(MAP_FORMAT, None),
    ];
    let layout = scene.pipeline_layout_with(ctx, &[own]);
    let depth = (true, wgpu::CompareFunction::Less);
    scene::scene_pipeline_with(
        ctx,
        "transfer map",
        &layout,
        &module,
        "transfer_fs",
        &targets,
        depth,
    )
}

/// The splats' pass: a quad per receiver point, added into the irradiance buffer.
fn splat_pipeline(ctx: &Context, layout: &wgpu::PipelineLayout) -> wgpu::RenderPipeline {
    let topology = wgpu::PrimitiveTopology::TriangleList;
    let entries = ("splat_vs", "splat_fs");
    bufferless_pipeline(
        ctx,
        "splats",
        layout,
        SPLAT_WGSL,
        entries,
        topology,
        Some(ADD),
    )
}

impl Passes {
    /// The layouts, and the pipelines of `variant`'s passes: the caustic passes (and the
    /// marcher it uses) for a caustic variant, the shadow mask for screen-space shadows, the
    /// refraction pass for all; in a scene with a scattering medium, the medium's passes for
    /// every variant (each variant's image is attenuated by it). On lavapipe a pipeline costs
    /// ~30 ms of compilation, so a variant that made them all spent most of its prepare on
    /// passes it never runs.
    pub(super) fn new(ctx: &Context, scene: &GpuScene, variant: &Variant) -> Self {
        let layouts = Layouts::new(ctx);
        let caustics = variant.caustics.is_some();
        let marches = |m: March| matches!(variant.caustics, Some((march, _)) if march == m);
        let shadows = variant.screen_space_shadows;
        let with =
            |own: &wgpu::BindGroupLayout| scene.pipeline_layout_with(ctx, &[&layouts.ldi, own]);
        let less = (true, wgpu::CompareFunction::Less);
        let compute =
            |label, own, source, entry| compute_pipeline(ctx, label, &with(own), source, entry);
        let per_photon = match variant.caustics {
            Some((March::Dda, _)) => Some(("dda march", "dda_main")),
            Some((March::Shader, _)) => Some(("tolerance march", "tolerance_main")),
            _ => None,
        };
        Self {
            medium: scene
                .scene
                .medium
                .is_some()
                .then(|| MediumPasses::new(ctx, scene, &layouts.ldi, variant)),
            shadow_mask: shadows.then(|| {
                compute(
                    "shadow mask",
                    &layouts.shadow_mask,
                    SHADOW_MASK_WGSL,
                    "shadow_main",
                )
            }),
            shadowed: shadows.then(|| {
                let layout = with(&layouts.shadowed);
                hdr_pipeline(
                    ctx,
                    &layout,
                    "screen-space shadowed",
                    SHADOWED_WGSL,
                    "shadowed_fs",
                    None,
                    less,
                )
            }),
            transfer: caustics.then(|| transfer_pipeline(ctx, scene, &layouts.transfer)),
            gather: caustics.then(|| {
                compute(
                    "gather photons",
                    &layouts.gather,
                    GATHER_WGSL,
                    "gather_main",
                )
            }),
            lines: marches(March::Lines).then(|| {
                let topology = wgpu::PrimitiveTopology::LineList;
                let entries = ("line_vs", "line_fs");
                bufferless_pipeline(
                    ctx,
                    "photon lines",
                    &with(&layouts.lines),
                    LINES_WGSL,
                    entries,
                    topology,
                    None,
                )
            }),
            reduce: marches(March::Lines)
                .then(|| compute("reduce rows", &layouts.reduce, REDUCE_WGSL, "reduce_main")),
            per_photon: per_photon
                .map(|(label, entry)| compute(label, &layouts.dda, DDA_WGSL, entry)),
            resolve: caustics.then(|| {
                compute(
                    "resolve photons",
                    &layouts.resolve,
                    RESOLVE_WGSL,
                    "resolve_main",
                )
            }),
            splat: caustics.then(|| splat_pipeline(ctx, &with(&layouts.splat))),
            apply: caustics.then(|| {
                let layout = with(&layouts.apply);
                let keep = (false, wgpu::CompareFunction::Equal);
                hdr_pipeline(
                    ctx,
                    &layout,
                    "caustic apply",
                    APPLY_WGSL,
                    "apply_fs",
                    Some(ADD_RGB_KEEP_ALPHA),
                    keep,
                )
            }),
            specular: {
                let layout = with(&layouts.specular);
                hdr_pipeline(
                    ctx,
                    &layout,
                    "screen-space refraction",
                    SPECULAR_WGSL,
                    "specular_fs",
                    None,
                    less,
                )
            },
            layouts,
        }
    }

    /// One frame: the passes in the order of the module's docs, each a method below that
    /// states what it reads and writes.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn frame(
        &self,
        frame: &mut Frame,
        scene: &GpuScene,
        view: &View,
        target: &Target,
        sized: &Sized,
        settings: &Settings,
        variant: &Variant,
    ) -> TechniqueResult<()> {
        let specular = scene.scene.specular_objects();
        frame.span("ldi", |frame| {
            self.peel(frame, scene, view, sized, &specular)
        })?;
        let (camera_group, ldi_group) = self.frame_groups(frame.gpu, scene, view, sized, settings);
        let inputs = FrameInputs {
            scene,
            view,
            target,
            sized,
            settings,
            variant,
            groups: Groups {
                camera: &camera_group,
                scene: scene.bind_group(),
                ldi: &ldi_group,
            },
            specular,
            media: sized.media.as_ref().zip(self.medium.as_ref()),
        };
        self.diffuse_surfaces(frame, &inputs);
        if let Some((targets, _)) = inputs.media {
            clear_media(frame, targets);
        }
        if let Some((march, splat)) = variant.caustics {
            self.caustics(frame, &inputs, march, splat)?;
        }
        frame.span("refraction", |frame| self.refraction(frame, &inputs));
        if let Some((targets, passes)) = inputs.media {
            frame.span("shafts", |frame| -> TechniqueResult<()> {
                match variant.shafts {
                    Some(Shafts::GodRays) => {
                        passes.blur(frame, &inputs.groups, targets, view, settings)
                    }
                    Some(Shafts::Froxels | Shafts::FroxelsWithPhotons) => {
                        passes.froxels(frame, &inputs.groups, targets, scene, view, settings)?
                    }
                    None => {}
                }
                Ok(())
            })?;
            frame.span("medium", |frame| {
                passes.composite(frame, &inputs.groups, targets, target);
            });
        }
        Ok(())
    }

    /// *LDI*. Reads: the scene, the view. Writes: the scene's and the specular objects' layered
    /// depth images (`sized.scene_ldi`, `sized.refractor_ldi`), each peeled only as deep as
    /// the view's depth complexity.
    fn peel(
        &self,
        frame: &mut Frame,
        scene: &GpuScene,
        view: &View,
        sized: &Sized,
        specular: &[usize],
    ) -> TechniqueResult<()> {
        let view_proj = view.camera.view_proj(view.width, view.height);
        let eye = view.camera.eye;
        let all = &ObjectFilter::All;
        sized.scene_ldi.peel(frame, scene, all, view_proj, eye)?;
        let only_specular = &ObjectFilter::Only(specular.to_vec());
        sized
            .refractor_ldi
            .peel(frame, scene, only_specular, view_proj, eye)?;
        Ok(())
    }

    /// The bind groups of the frame: the camera's, and the LDIs' with their parameters (the
    /// view, the scene's box at this time grown a little, since rays start on its surfaces,
    /// and the march's tolerances), which `sized.ldi_params` keeps for the tests.
    fn frame_groups(
        &self,
        ctx: &Context,
        scene: &GpuScene,
        view: &View,
        sized: &Sized,
        settings: &Settings,
    ) -> (wgpu::BindGroup, wgpu::BindGroup) {
        let view_proj = view.camera.view_proj(view.width, view.height);
        let eye = view.camera.eye;
        let (lo, hi) = scene_box(&scene.scene, scene.time());
        let margin = Vec3::splat((hi - lo).length() * 1e-3 + 1e-3);
        let ldi_params = LdiParamsGpu {
            view_proj: view_proj.to_cols_array_2d(),
            inv_view_proj: view_proj.inverse().to_cols_array_2d(),
            eye: eye.extend(1.0).to_array(),
            size: [view.width, view.height, settings.layers, sized.line_width],
            tests: [
                settings.tolerance,
                settings.thickness,
                settings.tolerance,
                0.0,
            ],
            bounds_min: (lo - margin).extend(0.0).to_array(),
            bounds_max: (hi + margin).extend(0.0).to_array(),
        };
        sized.ldi_params.set(Some(ldi_params));
        let ldi_params = Uniform::new(ctx, "ldi params", &ldi_params);
        let ldi_group = bind::group(
            ctx,
            "ldi",
            &self.layouts.ldi,
            &[
                ldi_params.binding(),
                bind::view(sized.scene_ldi.layers_view()),
                bind::view(sized.scene_ldi.surfaces_view()),
                bind::view(sized.refractor_ldi.layers_view()),
                bind::view(sized.refractor_ldi.surfaces_view()),
            ],
        );
        (scene.camera_bind_group(ctx, view_proj, eye), ldi_group)
    }

    /// The diffuse surfaces. Reads: the scene, the shadow maps (or, for the `shadows`
    /// variant, the LDI through the screen-space shadow mask). Writes: the target's colour
    /// and depth, cleared first.
    fn diffuse_surfaces(&self, frame: &mut Frame, inputs: &FrameInputs) {
        let FrameInputs {
            scene,
            view,
            target,
            sized,
            ..
        } = *inputs;
        if let (true, Some(mask)) = (inputs.variant.screen_space_shadows, &sized.shadow_mask) {
            let groups = &inputs.groups;
            let specular = &inputs.specular;
            self.screen_space_shadowed(frame, scene, groups, mask, sized.key, target, specular);
        } else {
            let view_proj = view.camera.view_proj(view.width, view.height);
            let all = &ObjectFilter::All;
            let clear = &RasterTarget::of(target, true);
            scene.raster(frame, clear, view_proj, view.camera.eye, all, false);
        }
    }

    /// *Caustics* and *splats*, per light. Reads: the scene, the LDIs. Writes: the irradiance
    /// buffer (cleared first), then the target's colour (the diffuse surfaces drawn again,
    /// adding `albedo / pi * E`); with a medium and photon shafts, the photons' beams or the
    /// caustic map.
    fn caustics(
        &self,
        frame: &mut Frame,
        inputs: &FrameInputs,
        march: March,
        splat: Splat,
    ) -> TechniqueResult<()> {
        let FrameInputs {
            scene,
            view,
            sized,
            settings,
            variant,
            media,
            ..
        } = *inputs;
        let groups = &inputs.groups;
        pass::begin(
            frame.encoder,
            "clear irradiance",
            &[pass::color(&sized.irradiance, CLEAR_BLACK)],
            None,
            None,
        );
        let keep_beams = media.is_some() && variant.shafts.is_some_and(Shafts::from_photons);
        for (light_index, light) in scene.scene.lights.iter().enumerate() {
            let spacing = frame.span("caustics", |frame| -> TechniqueResult<f32> {
                let (spacing, flux) = self.transfer(frame, scene, sized, settings, light)?;
                self.gather(frame, groups, sized, flux);
                for round in 0..=settings.bounces {
                    // The march alone (the paper: "intersection testing consumed over 80% of
                    // the time").
                    frame.span("march", |frame| self.march(frame, groups, sized, march));
                    let beams = media.map(|(targets, _)| &targets.beams);
                    let keep = beams.filter(|_| keep_beams);
                    self.resolve(frame, groups, sized, settings, round, keep);
                }
                Ok(spacing)
            })?;
            if let (Some((targets, passes)), true) = (media, keep_beams) {
                frame.span("shafts", |frame| -> TechniqueResult<()> {
                    match variant.shafts {
                        Some(Shafts::GodRays) => {
                            passes.draw_bands(frame, groups, targets, view, settings)
                        }
                        Some(Shafts::FroxelsWithPhotons) if light_index == 0 => {
                            passes.draw_caustic_map(frame, groups, targets, scene, settings)?
                        }
                        _ => {}
                    }
                    Ok(())
                })?;
            }
            frame.span("splat", |frame| {
                let radius = spacing * settings.splat_radius;
                self.splat(frame, groups, sized, view, splat, radius, settings);
            });
        }
        self.apply(frame, inputs);
        Ok(())
    }

    /// The gather. Reads: the transfer maps of one light and its unit flux. Writes: the photon
    /// buffer (one photon per specular pixel of the transfer map), the receivers' count.
    fn gather(&self, frame: &mut Frame, groups: &Groups, sized: &Sized, flux: Vec3) {
        let ctx = frame.gpu;
        let flux = Uniform::new(ctx, "unit flux", &flux.extend(0.0).to_array());
        let group = bind::group(
            ctx,
            "gather",
            &self.layouts.gather,
            &[
                bind::view(&sized.transfer[0]),
                bind::view(&sized.transfer[1]),
                sized.photons.photons.as_entire_binding(),
                sized.photons.receivers.as_entire_binding(),
                flux.binding(),
            ],
        );
        let workgroups = sized.photons.count.div_ceil(64);
        self.dispatch(frame, groups, made(&self.gather), &group, workgroups);
    }

    /// The march. Reads: the photon buffer, the scene's LDI. Writes: each photon's first
    /// surface (the hits buffer): the paper's lines, or one invocation per photon.
    fn march(&self, frame: &mut Frame, groups: &Groups, sized: &Sized, march: March) {
        if march == March::Lines {
            return self.march_lines(frame, groups, sized);
        }
        let group = bind::group(
            frame.gpu,
            "dda",
            &self.layouts.dda,
            &[
                sized.photons.photons.as_entire_binding(),
                sized.photons.hits.as_entire_binding(),
            ],
        );
        let workgroups = sized.photons.count.div_ceil(64);
        self.dispatch(frame, groups, made(&self.per_photon), &group, workgroups);
    }

    /// The caustics' apply. Reads: the irradiance buffer. Writes: the target's colour, the
    /// diffuse surfaces drawn again adding `albedo / pi * E` (depth kept).
    fn apply(&self, frame: &mut Frame, inputs: &FrameInputs) {
        let (sized, target) = (inputs.sized, inputs.target);
        let apply_group = bind::group(
            frame.gpu,
            "apply",
            &self.layouts.apply,
            &[bind::view(&sized.irradiance)],
        );
        let mut pass = pass::begin(
            frame.encoder,
            "caustic apply",
            &[pass::color(&target.color_view, pass::Load::Keep)],
            Some(pass::depth(&target.depth_view, pass::Load::Keep)),
            None,
        );
        pass.set_pipeline(made(&self.apply));
        inputs.groups.set(&mut pass, &apply_group);
        let diffuse = &ObjectFilter::Except(inputs.specular.clone());
        inputs.scene.draw_objects(&mut pass, diffuse);
    }

    /// *Refraction*. Reads: the refractor's and the scene's LDIs, the target's colour as the
    /// diffuse scene left it. Writes: the specular surfaces' colour and depth.
    fn refraction(&self, frame: &mut Frame, inputs: &FrameInputs) {
        let ctx = frame.gpu;
        let target = inputs.target;
        let mode = ModeGpu {
            value: (inputs.variant.refraction == Refraction::Dda) as u32,
            _pad: [0; 3],
        };
        let mode = Uniform::new(ctx, "specular mode", &mode);
        let specular_group =
            bind::group(ctx, "specular", &self.layouts.specular, &[mode.binding()]);
        let mut pass = pass::begin(
            frame.encoder,
            "screen-space refraction",
            &[pass::color(&target.color_view, pass::Load::Keep)],
            Some(pass::depth(&target.depth_view, pass::Load::Keep)),
            None,
        );
        pass.set_pipeline(&self.specular);
        inputs.groups.set(&mut pass, &specular_group);
        let specular = &ObjectFilter::Only(inputs.specular.clone());
        inputs.scene.draw_objects(&mut pass, specular);
    }

    /// The diffuse surfaces with screen-space shadow rays: the visibility mask (a compute
    /// pass over layer 0 of the LDI), then the surfaces drawn with it.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn screen_space_shadowed(
        &self,
        frame: &mut Frame,
        scene: &GpuScene,
        groups: &Groups,
        mask: &wgpu::Buffer,
        (width, height): (u32, u32),
        target: &Target,
        specular: &[usize],
    ) {
        let ctx = frame.gpu;
        frame.span("shadows", |frame| {
            let mask_group = bind::group(
                ctx,
                "shadow mask",
                &self.layouts.shadow_mask,
                &[mask.as_entire_binding()],
            );
            {
                let mut pass = frame
                    .encoder
                    .begin_compute_pass(&wgpu::ComputePassDescriptor::default());
                pass.set_pipeline(made(&self.shadow_mask));
                pass.set_bind_group(0, groups.camera, &[]);
                pass.set_bind_group(1, groups.scene, &[]);
                pass.set_bind_group(2, groups.ldi, &[]);
                pass.set_bind_group(3, &mask_group, &[]);
                pass.dispatch_workgroups(width.div_ceil(8), height.div_ceil(8), 1);
            }
        });
        let group = bind::group(
            ctx,
            "shadowed",
            &self.layouts.shadowed,
            &[mask.as_entire_binding()],
        );
        let background = scene.scene.background;
        let mut pass = pass::begin(
            frame.encoder,
            "screen-space shadowed",
            &[pass::color(
                &target.color_view,
                pass::Load::Clear(wgpu::Color {
                    r: background.x as f64,
                    g: background.y as f64,
                    b: background.z as f64,
                    a: scene::BACKGROUND_DISTANCE as f64,
                }),
            )],
            Some(pass::depth(&target.depth_view, CLEAR_FAR)),
            None,
        );
        pass.set_pipeline(made(&self.shadowed));
        groups.set(&mut pass, &group);
        scene.draw_objects(&mut pass, &ObjectFilter::Except(specular.to_vec()));
    }

    /// The transfer map of `light`: returns the photon spacing at the casters' centre (m)
    /// and the flux of a unit weight (the light's intensity times a pixel's solid angle).
    pub(super) fn transfer(
        &self,
        frame: &mut Frame,
        scene: &GpuScene,
        sized: &Sized,
        settings: &Settings,
        light: &scene::Light,
    ) -> TechniqueResult<(f32, Vec3)> {
        let ctx = frame.gpu;
        let (centre, radius) = light_outside_casters(&scene.scene, light, scene.time())?;
        let grid = settings.photons;
        let (view_proj, params, spacing) = light_view(light, centre, radius, grid, settings.jitter);
        let uniform = Uniform::new(ctx, "transfer params", &params);
        let group = bind::group(
            ctx,
            "transfer",
            &self.layouts.transfer,
            &[uniform.binding()],
        );
        let camera = scene.camera_bind_group(ctx, view_proj, light.position);
        let mut pass = pass::begin(
            frame.encoder,
            "transfer map",
            &[
                pass::color(&sized.transfer[0], CLEAR_BLACK),
                pass::color(&sized.transfer[1], CLEAR_BLACK),
            ],
            Some(pass::depth(&sized.transfer[2], CLEAR_FAR)),
            None,
        );
        pass.set_pipeline(made(&self.transfer));
        pass.set_bind_group(0, &camera, &[]);
        pass.set_bind_group(1, scene.bind_group(), &[]);
        pass.set_bind_group(2, &group, &[]);
        scene.draw_objects(&mut pass, &ObjectFilter::All);
        let flux = Vec3::from_slice(&params.intensity[..3]) * params.axis[3];
        Ok((spacing, flux))
    }

    pub(super) fn dispatch(
        &self,
        frame: &mut Frame,
        groups: &Groups,
        pipeline: &wgpu::ComputePipeline,
        own: &wgpu::BindGroup,
        workgroups: u32,
    ) {
        let mut pass = frame
            .encoder
            .begin_compute_pass(&wgpu::ComputePassDescriptor::default());
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, groups.camera, &[]);
        pass.set_bind_group(1, groups.scene, &[]);
        pass.set_bind_group(2, groups.ldi, &[]);
        pass.set_bind_group(3, own, &[]);
        pass.dispatch_workgroups(workgroups.max(1), 1, 1);
    }

    /// The paper's line marcher: batches of `rows` photons, each drawn as lines into the row
    /// buffer and reduced to the first hit per row.
    pub(super) fn march_lines(&self, frame: &mut Frame, groups: &Groups, sized: &Sized) {
        let ctx = frame.gpu;
        let rows = sized.line_rows_count;
        for first in (0..sized.photons.count).step_by(rows as usize) {
            let batch = Uniform::new(
                ctx,
                "line batch",
                &BatchGpu {
                    first,
                    rows,
                    width: sized.line_width,
                    _pad: 0,
                },
            );
            let lines_group = bind::group(
                ctx,
                "lines",
                &self.layouts.lines,
                &[sized.photons.photons.as_entire_binding(), batch.binding()],
            );
            {
                let mut pass = pass::begin(
                    frame.encoder,
                    "photon lines",
                    &[pass::color(&sized.line_rows, CLEAR_BLACK)],
                    None,
                    None,
                );
                pass.set_pipeline(made(&self.lines));
                groups.set(&mut pass, &lines_group);
                pass.draw(0..2, 0..rows);
            }
            let reduce_group = bind::group(
                ctx,
                "reduce",
                &self.layouts.reduce,
                &[
                    bind::view(&sized.line_rows),
                    sized.photons.hits.as_entire_binding(),
                    batch.binding(),
                ],
            );
            self.dispatch(
                frame,
                groups,
                made(&self.reduce),
                &reduce_group,
                rows.div_ceil(64),
            );
        }
    }

    /// Resolves round `round`'s hits; `beams`: keep each photon ray as a beam there.
    pub(super) fn resolve(
        &self,
        frame: &mut Frame,
        groups: &Groups,
        sized: &Sized,
        settings: &Settings,
        round: u32,
        beams: Option<&wgpu::Buffer>,
    ) {
        let ctx = frame.gpu;
        let params = Uniform::new(
            ctx,
            "resolve params",
            &ResolveParamsGpu {
                max_bounces: settings.bounces,
                round,
                keep_beams: beams.is_some() as u32,
                _pad: 0,
            },
        );
        let beams = beams.unwrap_or(&sized.no_beams);
        let group = bind::group(
            ctx,
            "resolve",
            &self.layouts.resolve,
            &[
                sized.photons.photons.as_entire_binding(),
                sized.photons.hits.as_entire_binding(),
                sized.photons.receivers.as_entire_binding(),
                params.binding(),
                beams.as_entire_binding(),
            ],
        );
        self.dispatch(
            frame,
            groups,
            made(&self.resolve),
            &group,
            sized.photons.count.div_ceil(64),
        );
    }

    #[allow(clippy::too_many_arguments)]
    pub(super) fn splat(
        &self,
        frame: &mut Frame,
        groups: &Groups,
        sized: &Sized,
        view: &View,
        splat: Splat,
        radius: f32,
        settings: &Settings,
    ) {
        let ctx = frame.gpu;
        let camera = view.camera;
        let (forward, _, _) = camera.basis();
        let tan_half = (camera.fov_y_deg.to_radians() * 0.5).tan();
        let focal = view.height as f32 / (2.0 * tan_half);
        // A sphere's projection off the view axis is wider than on it by up to the secant of
        // the angle to the view's corner (splat_vs sizes its quads with it).
        let aspect = view.width as f32 / view.height as f32;
        let corner_secant = (1.0 + tan_half * tan_half * (1.0 + aspect * aspect)).sqrt();
        let params = Uniform::new(
            ctx,
            "splat params",
            &SplatParamsGpu {
                inv_view_proj: camera
                    .view_proj(view.width, view.height)
                    .inverse()
                    .to_cols_array_2d(),
                forward: forward.extend(focal * corner_secant).to_array(),
                size: [
                    view.width as f32,
                    view.height as f32,
                    radius,
                    settings.tolerance.max(radius * 0.25),
                ],
                mode: (splat == Splat::Sprite) as u32,
                // Receiver i is the photon of transfer-map pixel i: one lattice per light.
                lattice: if settings.footprint {
                    settings.photons
                } else {
                    0
                },
                _pad: [0; 2],
            },
        );
        let group = bind::group(
            ctx,
            "splat",
            &self.layouts.splat,
            &[
                sized.photons.receivers.as_entire_binding(),
                params.binding(),
            ],
        );
        let mut pass = pass::begin(
            frame.encoder,
            "splats",
            &[pass::color(&sized.irradiance, pass::Load::Keep)],
            None,
            None,
        );
        pass.set_pipeline(made(&self.splat));
        groups.set(&mut pass, &group);
        pass.draw(0..6, 0..sized.photons.count);
    }
}

/// What the passes of one frame read: the scene and view, the target, the view-sized
/// resources, the settings and variant, the shared bind groups, the specular objects, and the
/// medium's targets and passes in a scene with one.
pub(super) struct FrameInputs<'a> {
    pub(super) scene: &'a GpuScene,
    pub(super) view: &'a View,
    pub(super) target: &'a Target,
    pub(super) sized: &'a Sized,
    pub(super) settings: &'a Settings,
    pub(super) variant: &'a Variant,
    pub(super) groups: Groups<'a>,
    pub(super) specular: Vec<usize>,
    pub(super) media: Option<(&'a MediaTargets, &'a MediumPasses)>,
}

/// Clears the medium's in-scattering buffer and caustic maps before a frame adds to them.
fn clear_media(frame: &mut Frame, targets: &MediaTargets) {
    let black = |view| pass::color(view, CLEAR_BLACK);
    let inscatter = [black(&targets.inscatter)];
    pass::begin(frame.encoder, "clear in-scattering", &inscatter, None, None);
    let maps = [
        black(&targets.caustic_maps[0]),
        black(&targets.caustic_maps[1]),
    ];
    pass::begin(frame.encoder, "clear caustic map", &maps, None, None);
}

/// The bind groups every pass of a frame shares.
pub(super) struct Groups<'a> {
    pub(super) camera: &'a wgpu::BindGroup,
    pub(super) scene: &'a wgpu::BindGroup,
    pub(super) ldi: &'a wgpu::BindGroup,
}

impl Groups<'_> {
    pub(super) fn set(&self, pass: &mut wgpu::RenderPass<'_>, own: &wgpu::BindGroup) {
        pass.set_bind_group(0, self.camera, &[]);
        pass.set_bind_group(1, self.scene, &[]);
        pass.set_bind_group(2, self.ldi, &[]);
        pass.set_bind_group(3, own, &[]);
    }
}
