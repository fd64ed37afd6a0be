//! Bind-group layouts and bind groups written as lists, the way Bevy's
//! `BindGroupLayoutEntries::sequential` does it: binding `i` is the `i`-th entry, so a layout
//! reads like the WGSL `@group` block it matches and no binding number is written twice.
//!
//! ```ignore
//! let layout = gpu::bind::layout(ctx, "impostor", FRAGMENT, &[
//!     bind::texture_cube(),   // @binding(0) var env: texture_cube<f32>;
//!     bind::sampler(),        // @binding(1) var env_sampler: sampler;
//!     bind::uniform(),        // @binding(2) var<uniform> params: Params;
//! ]);
//! let group = gpu::bind::group(ctx, "impostor", &layout, &[
//!     bind::view(&env.cube_view), bind::sampler_resource(&ctx.samplers.linear_clamp),
//!     params.binding(),
//! ]);
//! ```

use crate::Context;
use std::marker::PhantomData;
use wgpu::util::DeviceExt;

pub use wgpu::ShaderStages;

/// A uniform buffer (`var<uniform>`).
pub const fn uniform() -> wgpu::BindingType {
    wgpu::BindingType::Buffer {
        ty: wgpu::BufferBindingType::Uniform,
        has_dynamic_offset: false,
        min_binding_size: None,
    }
}

/// A storage buffer (`var<storage, read>` or `var<storage, read_write>`).
pub const fn storage(read_only: bool) -> wgpu::BindingType {
    wgpu::BindingType::Buffer {
        ty: wgpu::BufferBindingType::Storage { read_only },
        has_dynamic_offset: false,
        min_binding_size: None,
    }
}

/// A float texture of any view dimension; `filterable: false` for 32-bit float formats read
/// with `textureLoad` or a non-filtering sampler.
pub const fn texture(
    view_dimension: wgpu::TextureViewDimension,
    filterable: bool,
) -> wgpu::BindingType {
    wgpu::BindingType::Texture {
        sample_type: wgpu::TextureSampleType::Float { filterable },
        view_dimension,
        multisampled: false,
    }
}

/// `texture_2d<f32>`, filterable.
pub const fn texture_2d() -> wgpu::BindingType {
    texture(wgpu::TextureViewDimension::D2, true)
}

/// `texture_2d<f32>` that is only loaded (32-bit float formats).
pub const fn texture_2d_unfilterable() -> wgpu::BindingType {
    texture(wgpu::TextureViewDimension::D2, false)
}

/// `texture_2d_array<f32>`, filterable.
pub const fn texture_2d_array() -> wgpu::BindingType {
    texture(wgpu::TextureViewDimension::D2Array, true)
}

/// `texture_cube<f32>`, filterable.
pub const fn texture_cube() -> wgpu::BindingType {
    texture(wgpu::TextureViewDimension::Cube, true)
}

/// A depth texture (`texture_depth_2d`, `texture_depth_2d_array`, ...).
pub const fn depth_texture(view_dimension: wgpu::TextureViewDimension) -> wgpu::BindingType {
    wgpu::BindingType::Texture {
        sample_type: wgpu::TextureSampleType::Depth,
        view_dimension,
        multisampled: false,
    }
}

/// A write-only storage texture (`texture_storage_2d<format, write>`).
pub const fn storage_texture_2d(format: wgpu::TextureFormat) -> wgpu::BindingType {
    wgpu::BindingType::StorageTexture {
        access: wgpu::StorageTextureAccess::WriteOnly,
        format,
        view_dimension: wgpu::TextureViewDimension::D2,
    }
}

/// A filtering sampler (`sampler`).
pub const fn sampler() -> wgpu::BindingType {
    wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering)
}

/// A non-filtering sampler (for 32-bit float textures).
pub const fn sampler_non_filtering() -> wgpu::BindingType {
    wgpu::BindingType::Sampler(wgpu::SamplerBindingType::NonFiltering)
}

/// A layout whose binding `i` is `types[i]`, all visible to `stages`.
pub fn layout(
    ctx: &Context,
    label: &str,
    stages: wgpu::ShaderStages,
    types: &[wgpu::BindingType],
) -> wgpu::BindGroupLayout {
    let entries: Vec<_> = types.iter().map(|ty| (stages, *ty)).collect();
    layout_with_stages(ctx, label, &entries)
}

/// A layout whose binding `i` is `entries[i]`, each with its own visibility.
pub fn layout_with_stages(
    ctx: &Context,
    label: &str,
    entries: &[(wgpu::ShaderStages, wgpu::BindingType)],
) -> wgpu::BindGroupLayout {
    let entries: Vec<_> = entries
        .iter()
        .enumerate()
        .map(|(binding, (visibility, ty))| wgpu::BindGroupLayoutEntry {
            binding: binding as u32,
            visibility: *visibility,
            ty: *ty,
            count: None,
        })
        .collect();
    ctx.device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(label),
            entries: &entries,
        })
}

/// A bind group whose binding `i` is `resources[i]`.
pub fn group(
    ctx: &Context,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    resources: &[wgpu::BindingResource<'_>],
) -> wgpu::BindGroup {
    let entries: Vec<_> = resources
        .iter()
        .enumerate()
        .map(|(binding, resource)| wgpu::BindGroupEntry {
            binding: binding as u32,
            resource: resource.clone(),
        })
        .collect();
    ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
}

/// A texture view as a binding resource.
pub fn view(view: &wgpu::TextureView) -> wgpu::BindingResource<'_> {
    wgpu::BindingResource::TextureView(view)
}

/// A sampler as a binding resource.
pub fn sampler_resource(sampler: &wgpu::Sampler) -> wgpu::BindingResource<'_> {
    wgpu::BindingResource::Sampler(sampler)
}

/// A uniform buffer holding one `T`, written whole: the Rust side of a `var<uniform>` block.
/// `T` must match the WGSL struct's layout (16-byte aligned members, explicit padding).
pub struct Uniform<T> {
    buffer: wgpu::Buffer,
    _value: PhantomData<T>,
}

impl<T: bytemuck::Pod> Uniform<T> {
    pub fn new(ctx: &Context, label: &str, value: &T) -> Self {
        let buffer = ctx
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytemuck::bytes_of(value),
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            });
        Self {
            buffer,
            _value: PhantomData,
        }
    }

    /// Replaces the value; takes effect at the next queue submission.
    pub fn write(&self, ctx: &Context, value: &T) {
        ctx.queue
            .write_buffer(&self.buffer, 0, bytemuck::bytes_of(value));
    }

    pub fn binding(&self) -> wgpu::BindingResource<'_> {
        self.buffer.as_entire_binding()
    }

    pub fn buffer(&self) -> &wgpu::Buffer {
        &self.buffer
    }
}

/// Uniform buffers with their bind groups in numbered slots, each made the first time its slot
/// is asked for and reused in every frame after, its value rewritten: what a technique that
/// binds per-object or per-light parameters every frame keeps for as long as it lives, instead
/// of a new buffer and bind group per frame (which cost a GPU object each, and on Mesa 22's
/// lavapipe megabytes that are never given back: see the harness README, "Memory").
///
/// A slot holds one value per submission: the value written last before the frame is
/// submitted is what every pass of that frame reads (queue writes are applied at submission),
/// so give each (object, light, ...) its own slot.
pub struct UniformGroups<T> {
    /// Per slot: the uniform, its group and the value it holds (written only when it changes).
    slots: std::cell::RefCell<Vec<Option<(Uniform<T>, wgpu::BindGroup, T)>>>,
    label: &'static str,
}

impl<T: bytemuck::Pod> UniformGroups<T> {
    /// No slot made yet; `label` names the buffers.
    pub fn new(label: &'static str) -> Self {
        Self {
            slots: Default::default(),
            label,
        }
    }

    /// The bind group of `slot` with its uniform set to `value`; the first time, the uniform
    /// is made and `make` builds the group around it (its other resources must stay the same
    /// for the slot's life).
    pub fn get(
        &self,
        ctx: &Context,
        slot: usize,
        value: &T,
        make: impl FnOnce(&Uniform<T>) -> wgpu::BindGroup,
    ) -> wgpu::BindGroup {
        let mut slots = self.slots.borrow_mut();
        if slots.len() <= slot {
            slots.resize_with(slot + 1, || None);
        }
        match &mut slots[slot] {
            Some((uniform, group, held)) => {
                if bytemuck::bytes_of(held) != bytemuck::bytes_of(value) {
                    uniform.write(ctx, value);
                    *held = *value;
                }
                group.clone()
            }
            None => {
                let uniform = Uniform::new(ctx, self.label, value);
                let group = make(&uniform);
                slots[slot] = Some((uniform, group.clone(), *value));
                group
            }
        }
    }

    /// Slots made so far.
    pub fn len(&self) -> usize {
        self.slots.borrow().iter().flatten().count()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// The samplers the workspace's shaders use, made once per [`Context`].
pub struct Samplers {
    /// Bilinear, clamped to the edge: environment and distance cube maps, light maps,
    /// screen-space buffers.
    pub linear_clamp: wgpu::Sampler,
    /// Bilinear, repeating: tiled albedo and interior textures.
    pub linear_repeat: wgpu::Sampler,
    /// Nearest texel, clamped: exact texel reads through a sampler (shadow depth).
    pub nearest_clamp: wgpu::Sampler,
}

impl Samplers {
    pub(crate) fn new(device: &wgpu::Device) -> Self {
        let linear = |label, address_mode| {
            device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some(label),
                address_mode_u: address_mode,
                address_mode_v: address_mode,
                address_mode_w: address_mode,
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                ..Default::default()
            })
        };
        Self {
            linear_clamp: linear("linear clamp", wgpu::AddressMode::ClampToEdge),
            linear_repeat: linear("linear repeat", wgpu::AddressMode::Repeat),
            nearest_clamp: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("nearest clamp"),
                ..Default::default()
            }),
        }
    }
}
