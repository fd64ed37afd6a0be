//! The passes of a scene with a scattering medium: god rays, froxel fog, the composite.

use super::*;

/// The passes of a scene with a scattering medium: god rays, froxels, the composite.
pub(super) struct MediumPasses {
    pub(super) shafts_layout: wgpu::BindGroupLayout,
    pub(super) composite_layout: wgpu::BindGroupLayout,
    pub(super) froxel_layout: wgpu::BindGroupLayout,
    pub(super) bands: wgpu::RenderPipeline,
    pub(super) blur: wgpu::RenderPipeline,
    pub(super) attenuate: wgpu::RenderPipeline,
    pub(super) add_inscatter: wgpu::RenderPipeline,
    pub(super) caustic_map: wgpu::RenderPipeline,
    pub(super) froxel_scatter: wgpu::ComputePipeline,
    pub(super) froxel_integrate: wgpu::ComputePipeline,
    pub(super) froxel_lookup: wgpu::RenderPipeline,
    /// The engine froxels' light visibility: shadow maps in which transparent surfaces (glass,
    /// water) cast no shadow, as engines draw them (`froxel-fog` only).
    pub(super) engine_shadows: Option<CasterShadowMaps>,
}

impl MediumPasses {
    pub(super) fn new(
        ctx: &Context,
        scene: &GpuScene,
        ldi_layout: &wgpu::BindGroupLayout,
        variant: &Variant,
    ) -> Self {
        use wgpu::ShaderStages as S;
        let map = bind::texture_2d_unfilterable();
        let shafts_layout = bind::layout(
            ctx,
            "shafts",
            S::VERTEX_FRAGMENT,
            &[bind::storage(true), bind::uniform(), map],
        );
        let composite_layout = bind::layout(ctx, "medium composite", S::FRAGMENT, &[map]);
        let froxel_layout = froxel_layout(ctx);
        let engine_shadows = engine_shadows(ctx, scene, variant);
        let with =
            |own: &wgpu::BindGroupLayout| scene.pipeline_layout_with(ctx, &[ldi_layout, own]);
        let (shafts, composite, froxels) = (SHAFTS_WGSL, COMPOSITE_WGSL, FROXELS_WGSL);
        let hdr = |blend| [pass::color_target(gpu::HDR_FORMAT, Some(blend))];
        let triangles = wgpu::PrimitiveTopology::TriangleList;
        Self {
            bands: bufferless_pipeline(
                ctx,
                "god-ray bands",
                &with(&shafts_layout),
                shafts,
                ("band_vs", "band_fs"),
                triangles,
                Some(ADD),
            ),
            blur: bufferless_pipeline(
                ctx,
                "god-ray blur",
                &with(&shafts_layout),
                shafts,
                (gpu::fullscreen::VERTEX_ENTRY, "blur_fs"),
                triangles,
                None,
            ),
            attenuate: render_pipeline(
                ctx,
                "medium transmittance",
                &with(&composite_layout),
                composite,
                (gpu::fullscreen::VERTEX_ENTRY, "attenuate_fs"),
                triangles,
                &hdr(MULTIPLY_RGB_KEEP_ALPHA),
            ),
            add_inscatter: render_pipeline(
                ctx,
                "medium in-scattering",
                &with(&composite_layout),
                composite,
                (gpu::fullscreen::VERTEX_ENTRY, "inscatter_fs"),
                triangles,
                &hdr(ADD_RGB_KEEP_ALPHA),
            ),
            caustic_map: render_pipeline(
                ctx,
                "froxel caustic map",
                &with(&froxel_layout),
                froxels,
                ("caustic_map_vs", "caustic_map_fs"),
                wgpu::PrimitiveTopology::PointList,
                &[
                    pass::color_target(MAP_FORMAT, Some(ADD)),
                    pass::color_target(MAP_FORMAT, Some(ADD)),
                ],
            ),
            froxel_scatter: compute_pipeline(
                ctx,
                "froxel scattering",
                &with(&froxel_layout),
                froxels,
                "froxel_scatter_main",
            ),
            froxel_integrate: compute_pipeline(
                ctx,
                "froxel integration",
                &with(&froxel_layout),
                froxels,
                "froxel_integrate_main",
            ),
            froxel_lookup: bufferless_pipeline(
                ctx,
                "froxel lookup",
                &with(&froxel_layout),
                froxels,
                (gpu::fullscreen::VERTEX_ENTRY, "froxel_lookup_fs"),
                triangles,
                None,
            ),
            shafts_layout,
            composite_layout,
            froxel_layout,
            engine_shadows,
        }
    }
}

impl MediumPasses {
    pub(super) fn shaft_view(&self, view: &View, settings: &Settings) -> ShaftViewGpu {
        let s = crate::shafts::ShaftView::new(&view.camera, view.width, view.height);
        ShaftViewGpu {
            view_proj: s.view_proj.to_cols_array_2d(),
            eye: s.eye.extend(s.pixel_area).to_array(),
            forward: s
                .forward
                .extend(settings.shaft_blur * view.height as f32)
                .to_array(),
            size: [view.width, view.height, 0, 0],
        }
    }

    /// God rays: every beam of the march's rounds drawn as a band into the in-scattering
    /// buffer (section 3.2).
    pub(super) fn draw_bands(
        &self,
        frame: &mut Frame,
        groups: &Groups,
        targets: &MediaTargets,
        view: &View,
        settings: &Settings,
    ) {
        let ctx = frame.gpu;
        let beams = (targets.beams.size() / 48) as u32;
        let mut params = self.shaft_view(view, settings);
        params.size[2] = beams;
        let params = Uniform::new(ctx, "shaft view", &params);
        let group = bind::group(
            ctx,
            "god-ray bands",
            &self.shafts_layout,
            &[
                targets.beams.as_entire_binding(),
                params.binding(),
                bind::view(&targets.blurred),
            ],
        );
        let mut pass = pass::begin(
            frame.encoder,
            "god-ray bands",
            &[pass::color(&targets.inscatter, pass::Load::Keep)],
            None,
            None,
        );
        pass.set_pipeline(&self.bands);
        groups.set(&mut pass, &group);
        pass.draw(0..6, 0..beams);
    }

    /// God rays: the separable Gaussian blur of the in-scattering buffer (a constant
    /// screen-space support, as the paper's).
    pub(super) fn blur(
        &self,
        frame: &mut Frame,
        groups: &Groups,
        targets: &MediaTargets,
        view: &View,
        settings: &Settings,
    ) {
        if settings.shaft_blur <= 0.0 {
            return;
        }
        let ctx = frame.gpu;
        for (direction, from, to) in [
            (0, &targets.inscatter, &targets.blurred),
            (1, &targets.blurred, &targets.inscatter),
        ] {
            let mut params = self.shaft_view(view, settings);
            params.size[3] = direction;
            let params = Uniform::new(ctx, "shaft blur", &params);
            let group = bind::group(
                ctx,
                "god-ray blur",
                &self.shafts_layout,
                &[
                    targets.beams.as_entire_binding(),
                    params.binding(),
                    bind::view(from),
                ],
            );
            let mut pass = pass::begin(
                frame.encoder,
                "god-ray blur",
                &[pass::color(to, CLEAR_BLACK)],
                None,
                None,
            );
            pass.set_pipeline(&self.blur);
            groups.set(&mut pass, &group);
            gpu::fullscreen::draw(&mut pass);
        }
    }

    /// The froxels' uniform: the hybrid's caustic map's light view (the first light's view of
    /// the casters, as its transfer map), the grid and its slices, and the temporal terms:
    /// this frame's jitter, the history's weight and the last frame's view (`previous`).
    pub(super) fn froxel_params(
        &self,
        targets: &MediaTargets,
        scene: &GpuScene,
        view: &View,
        settings: &Settings,
        temporal: FroxelTemporal,
    ) -> TechniqueResult<FroxelParamsGpu> {
        let medium = scene
            .scene
            .medium
            .as_ref()
            .expect("a medium: checked by the caller");
        let slices = crate::shafts::Slices::of_medium(medium, view.camera.eye, settings.slices);
        let photons = self.engine_shadows.is_none();
        let (light_view_proj, light, axis) = match scene.scene.lights.first() {
            Some(light) if photons => {
                let (centre, radius) = light_outside_casters(&scene.scene, light, scene.time())?;
                let lv = scene::lightmap::LightView::of_sphere(
                    light.position,
                    centre,
                    radius,
                    settings.caustic_map,
                );
                (
                    lv.view_proj,
                    light.position.extend(lv.pixel_area),
                    lv.axis.extend(1.0),
                )
            }
            _ => (Mat4::IDENTITY, glam::Vec4::ZERO, glam::Vec4::ZERO),
        };
        let [x, y, z] = targets.froxel_grid;
        let previous = temporal.previous;
        Ok(FroxelParamsGpu {
            light_view_proj: light_view_proj.to_cols_array_2d(),
            light: light.to_array(),
            axis: axis.to_array(),
            grid: [x, y, z, settings.froxel_size],
            slices: [
                slices.near,
                slices.far,
                view.width as f32,
                view.height as f32,
            ],
            prev_view_proj: previous
                .map_or(Mat4::IDENTITY, |p| p.view_proj)
                .to_cols_array_2d(),
            prev_eye: previous
                .map_or(glam::Vec4::ZERO, |p| p.eye.extend(1.0))
                .to_array(),
            prev_slices: previous.map_or([0.0; 4], |p| [p.near, p.far, 0.0, 0.0]),
            temporal: [
                temporal.jitter.x,
                temporal.jitter.y,
                temporal.jitter.z,
                temporal.blend,
            ],
        })
    }

    /// The froxels' bind group: `(read, write, history)` index [`MediaTargets::froxels`].
    pub(super) fn froxel_group(
        &self,
        ctx: &Context,
        params: &Uniform<FroxelParamsGpu>,
        targets: &MediaTargets,
        scene: &GpuScene,
        maps: [&wgpu::TextureView; 2],
        (read, write, history): (usize, usize, usize),
    ) -> wgpu::BindGroup {
        // The engine's maps (transparent surfaces cast no shadow), else the scene's own.
        let (cubes, fitted) = match &self.engine_shadows {
            Some(maps) => (maps.cube_view(), maps.fitted_view()),
            None => scene.shadow_views(),
        };
        bind::group(
            ctx,
            "froxels",
            &self.froxel_layout,
            &[
                params.binding(),
                targets.beams.as_entire_binding(),
                bind::view(maps[0]),
                bind::view(maps[1]),
                bind::view(&targets.froxels[read]),
                bind::view(&targets.froxels[write]),
                bind::view(&targets.froxels[history]),
                bind::view(cubes),
                bind::view(fitted),
            ],
        )
    }

    /// Froxels: the caustic map of the first light, one point per photon's last beam.
    pub(super) fn draw_caustic_map(
        &self,
        frame: &mut Frame,
        groups: &Groups,
        targets: &MediaTargets,
        scene: &GpuScene,
        settings: &Settings,
    ) -> TechniqueResult<()> {
        let ctx = frame.gpu;
        // The view's size does not enter the caustic map.
        let view = View {
            camera: scene.scene.camera,
            time: scene.time(),
            width: 1,
            height: 1,
        };
        let params = Uniform::new(
            ctx,
            "froxel params",
            &self.froxel_params(targets, scene, &view, settings, FroxelTemporal::NONE)?,
        );
        let group = self.froxel_group(
            ctx,
            &params,
            targets,
            scene,
            [&targets.inscatter, &targets.blurred],
            (1, 0, 2),
        );
        let mut pass = pass::begin(
            frame.encoder,
            "froxel caustic map",
            &[
                pass::color(&targets.caustic_maps[0], pass::Load::Keep),
                pass::color(&targets.caustic_maps[1], pass::Load::Keep),
            ],
            None,
            None,
        );
        pass.set_pipeline(&self.caustic_map);
        groups.set(&mut pass, &group);
        pass.draw(0..(targets.beams.size() / 48) as u32, 0..1);
        Ok(())
    }

    /// Froxels: light the grid (the engine's visibility drawn first), blend it with the last
    /// frame's grid reprojected, integrate it front to back, look it up per pixel into the
    /// in-scattering buffer.
    pub(super) fn froxels(
        &self,
        frame: &mut Frame,
        groups: &Groups,
        targets: &MediaTargets,
        scene: &GpuScene,
        view: &View,
        settings: &Settings,
    ) -> TechniqueResult<()> {
        let ctx = frame.gpu;
        if let Some(maps) = &self.engine_shadows {
            maps.render(frame, scene);
        }
        let (index, previous) = targets.froxel_history.get();
        let temporal = FroxelTemporal::of_frame(index, previous, settings.temporal_blend);
        let params = self.froxel_params(targets, scene, view, settings, temporal)?;
        targets.froxel_history.set((
            index + 1,
            Some(FroxelView {
                view_proj: view.camera.view_proj(view.width, view.height),
                eye: view.camera.eye,
                // This frame's slices, as the uniform holds them (near, far).
                near: params.slices[0],
                far: params.slices[1],
            }),
        ));
        let params = Uniform::new(ctx, "froxel params", &params);
        let maps = [&targets.caustic_maps[0], &targets.caustic_maps[1]];
        // This frame's grid and the last frame's (its history) alternate between 0 and 2.
        let (grid, history) = if index % 2 == 0 { (0, 2) } else { (2, 0) };
        let [x, y, z] = targets.froxel_grid;
        for (pipeline, bindings, workgroups) in [
            (
                &self.froxel_scatter,
                (1, grid, history),
                [x.div_ceil(4), y.div_ceil(4), z.div_ceil(4)],
            ),
            (
                &self.froxel_integrate,
                (grid, 1, history),
                [x.div_ceil(8), y.div_ceil(8), 1],
            ),
        ] {
            let group = self.froxel_group(ctx, &params, targets, scene, maps, bindings);
            let mut pass = frame
                .encoder
                .begin_compute_pass(&wgpu::ComputePassDescriptor::default());
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, groups.camera, &[]);
            pass.set_bind_group(1, groups.scene, &[]);
            pass.set_bind_group(2, groups.ldi, &[]);
            pass.set_bind_group(3, &group, &[]);
            pass.dispatch_workgroups(workgroups[0], workgroups[1], workgroups[2]);
        }
        let group = self.froxel_group(ctx, &params, targets, scene, maps, (1, grid, history));
        let mut pass = pass::begin(
            frame.encoder,
            "froxel lookup",
            &[pass::color(&targets.inscatter, CLEAR_BLACK)],
            None,
            None,
        );
        pass.set_pipeline(&self.froxel_lookup);
        groups.set(&mut pass, &group);
        gpu::fullscreen::draw(&mut pass);
        Ok(())
    }

    /// Every variant in a medium: the image times the transmittance to its first surface,
    /// plus the in-scattering buffer.
    pub(super) fn composite(
        &self,
        frame: &mut Frame,
        groups: &Groups,
        targets: &MediaTargets,
        target: &Target,
    ) {
        let ctx = frame.gpu;
        let group = bind::group(
            ctx,
            "medium composite",
            &self.composite_layout,
            &[bind::view(&targets.inscatter)],
        );
        for pipeline in [&self.attenuate, &self.add_inscatter] {
            let mut pass = pass::begin(
                frame.encoder,
                "medium composite",
                &[pass::color(&target.color_view, pass::Load::Keep)],
                None,
                None,
            );
            pass.set_pipeline(pipeline);
            groups.set(&mut pass, &group);
            gpu::fullscreen::draw(&mut pass);
        }
    }
}

/// The froxel passes' bindings (`froxels.wgsl`, group 3): their parameters, the photons'
/// beams, the caustic map's flux and direction, the froxel grid read and written (a storage
/// texture), last frame's grid, and the engine shadows' cube and fitted maps.
fn froxel_layout(ctx: &Context) -> wgpu::BindGroupLayout {
    use wgpu::ShaderStages as S;
    let map = bind::texture_2d_unfilterable();
    let all = S::VERTEX_FRAGMENT | S::COMPUTE;
    bind::layout_with_stages(
        ctx,
        "froxels",
        &[
            (all, bind::uniform()),
            (all, bind::storage(true)),
            (all, map),
            (all, map),
            (all, bind::texture(wgpu::TextureViewDimension::D3, false)),
            (
                S::COMPUTE | S::FRAGMENT,
                wgpu::BindingType::StorageTexture {
                    access: wgpu::StorageTextureAccess::WriteOnly,
                    format: MAP_FORMAT,
                    view_dimension: wgpu::TextureViewDimension::D3,
                },
            ),
            (all, bind::texture(wgpu::TextureViewDimension::D3, false)),
            (
                all,
                bind::texture(wgpu::TextureViewDimension::CubeArray, false),
            ),
            (
                all,
                bind::texture(wgpu::TextureViewDimension::D2Array, false),
            ),
        ],
    )
}

/// The engine froxels' light visibility (`froxel-fog` only): shadow maps in which the glass
/// casts no shadow.
fn engine_shadows(ctx: &Context, scene: &GpuScene, variant: &Variant) -> Option<CasterShadowMaps> {
    let transparent: Vec<usize> = (scene.scene.objects.iter().enumerate())
        .filter(|(_, o)| matches!(o.material, scene::Material::Glass { .. }))
        .map(|(i, _)| i)
        .collect();
    (variant.shafts == Some(Shafts::Froxels))
        .then(|| CasterShadowMaps::new(ctx, scene, ObjectFilter::Except(transparent)))
}
