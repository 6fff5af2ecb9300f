//! The technique traits: what a technique is ([`TechniqueInfo`]), its kernels and the checked
//! entry points every caller uses ([`ShadowTechnique`]), and the object-safe form a registry
//! holds ([`DynTechnique`], whose maps [`AnyMaps`] evaluate themselves).
//!
//! A technique implements only what differs: its names and the lights it models, its limits
//! (largest resolution, memory estimate), its CPU kernels, its GPU recording, its visibility
//! shader and the bind group that shader reads. The checks (parameters, light, resolution,
//! memory budget, geometry, receivers) and the GPU error scopes run here, once, before a
//! kernel sees its input: a kernel takes [`Checked`] input, which only this crate makes.

use crate::coverage::Coverage;
use crate::cpu::CpuContext;
use crate::error::{Result, ShadowError};
use crate::geometry::SceneGeometry;
use crate::gpu::GpuContext;
#[cfg(feature = "gpu")]
use crate::gpu::GpuScene;
#[cfg(feature = "gpu")]
use crate::gpu::shader::{self, VisibilityShader};
#[cfg(feature = "gpu")]
use crate::gpu::visibility::{self, ReceiverTextures};
use crate::light::{Light, LightKind};
use crate::receivers::Receivers;
use crate::views::{LightViews, Region, ViewMaps};

/// The [`ShadowTechnique::GpuMaps`] of a technique type built without its GPU path (its crate's
/// `gpu` feature off): no value of it exists.
#[derive(Debug)]
pub enum NoGpuMaps {}

/// The error of a technique type built without its GPU path asked for GPU work.
#[cfg(feature = "gpu")]
fn no_gpu_path(technique: &str) -> ShadowError {
    ShadowError::Gpu(format!(
        "{technique} was built without its GPU path (its crate's `gpu` feature)"
    ))
}

/// Largest map side the CPU paths accept (a 16384² f32 map is 1 GiB).
pub const MAX_CPU_RESOLUTION: u32 = 16384;

/// Where a step runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Backend {
    /// Plain Rust (rayon where it pays).
    Cpu,
    /// wgpu render and compute passes (WGSL).
    Gpu,
}

impl Backend {
    /// `"cpu"` or `"gpu"`, as in reports.
    pub fn name(self) -> &'static str {
        match self {
            Backend::Cpu => "cpu",
            Backend::Gpu => "gpu",
        }
    }
}

/// Where one generation runs, with the context it runs in.
#[derive(Clone, Copy, Debug)]
pub enum Context<'a> {
    /// On the CPU, reusing this context's buffers.
    Cpu(&'a CpuContext),
    /// On this GPU.
    Gpu(&'a GpuContext),
}

impl<'a> Context<'a> {
    /// The backend.
    pub fn backend(&self) -> Backend {
        match self {
            Context::Cpu(_) => Backend::Cpu,
            Context::Gpu(_) => Backend::Gpu,
        }
    }

    /// The GPU context, on the GPU backend.
    pub fn gpu(&self) -> Option<&'a GpuContext> {
        match *self {
            Context::Gpu(g) => Some(g),
            Context::Cpu(_) => None,
        }
    }
}

/// A value this crate has checked: only this crate makes one, so a kernel that takes one runs
/// on checked input only. Reads as the value it holds.
#[derive(Clone, Copy, Debug)]
pub struct Checked<T>(T);

impl<T> std::ops::Deref for Checked<T> {
    type Target = T;
    fn deref(&self) -> &T {
        &self.0
    }
}

/// The inputs of one generation: the scene's plain geometry, one light, the region of the view
/// being generated and a map resolution.
#[derive(Clone, Copy, Debug)]
pub struct Generation<'a> {
    /// Casters and receivers.
    pub geometry: &'a SceneGeometry,
    /// The light.
    pub light: &'a Light,
    /// What this view covers ([`crate::views`]): the whole, a cube face or a cascade.
    pub region: Region,
    /// The map side in texels.
    pub resolution: u32,
}

impl Generation<'_> {
    /// What this view's maps cover for the light ([`Coverage::new`] within the region).
    pub fn coverage(&self) -> Coverage {
        self.coverage_of(self.light)
    }

    /// What this view's maps cover for `light` (a part of the light, such as one segment of a
    /// triangle light), within the region; a cube face's holds the casters inside the face of
    /// the whole light's cube ([`Coverage::casters`]).
    pub fn coverage_of(&self, light: &Light) -> Coverage {
        Coverage::new(self.geometry, light)
            .within(self.region, self.resolution)
            .in_face_of(&[&self.geometry.casters], self.light)
    }

    /// [`Generation::coverage_of`] for maps that also hold the receivers (`linear-light`'s grid
    /// maps): a cube face's depth range starts just before the nearest caster or receiver it
    /// holds, so that none of them is clipped from the maps.
    pub fn coverage_with_receivers_of(&self, light: &Light) -> Coverage {
        Coverage::new(self.geometry, light)
            .within(self.region, self.resolution)
            .in_face_of(
                &[&self.geometry.casters, &self.geometry.receivers],
                self.light,
            )
    }
}

impl<'a> Checked<Generation<'a>> {
    /// The same checked input for the view of `region`.
    fn in_region(&self, region: Region) -> Checked<Generation<'a>> {
        Checked(Generation { region, ..self.0 })
    }
}

/// How a configuration's generation time grows, in the terms a cost model fits it in
/// (`shadow-frame`'s `Auto`): time = `a + b·t1 + c·t2 + d·t3` with the terms of
/// [`CostForm::terms`]: the triangles, a texel term, and a term for work per triangle that grows
/// with the map.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[non_exhaustive]
pub enum CostForm {
    /// A fixed number of passes over the map (`side²`), and rasterization whose per-triangle
    /// work grows with the rows each triangle spans (`triangles·side`).
    Texels,
    /// One pass over the map per doubling of a step or a level (jump flooding, doubling
    /// propagation, N-Buffers): `side²·log2(side)`, and `triangles·side`.
    TexelPasses,
    /// A ribbon of texels per silhouette edge, as wide as the penumbra (silhouette extrusion):
    /// `side²`, and `triangles·side²`.
    Ribbons,
}

impl CostForm {
    /// Every form.
    pub const ALL: [CostForm; 3] = [CostForm::Texels, CostForm::TexelPasses, CostForm::Ribbons];

    /// The terms after the constant for a scene of `triangles` casters at map side `side`:
    /// triangles / 10³, the texel term / 10⁶, the per-triangle map term / 10⁹ (`triangles·side`)
    /// or / 10¹² (`triangles·side²`).
    pub fn terms(self, triangles: usize, side: u32) -> [f64; 3] {
        let (t, s) = (triangles as f64, side.max(2) as f64);
        let texels = s * s;
        match self {
            CostForm::Texels => [t / 1e3, texels / 1e6, t * s / 1e9],
            CostForm::TexelPasses => [t / 1e3, texels * s.log2() / 1e6, t * s / 1e9],
            CostForm::Ribbons => [t / 1e3, texels / 1e6, t * texels / 1e12],
        }
    }

    /// Short name (`"texels"`, `"texel-passes"`, `"ribbons"`).
    pub fn name(self) -> &'static str {
        match self {
            CostForm::Texels => "texels",
            CostForm::TexelPasses => "texel-passes",
            CostForm::Ribbons => "ribbons",
        }
    }

    /// The form named `name` ([`CostForm::name`]).
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|f| f.name() == name)
    }
}

/// `constructor` with `fields` assigned after it, as one Rust expression:
/// `{ let mut t = constructor; t.field = value; t }` (`constructor` alone where no field is).
/// [`TechniqueInfo::call`] writes a configuration with it.
pub fn call_with(constructor: String, fields: &[String]) -> String {
    if fields.is_empty() {
        return constructor;
    }
    let mut s = format!("{{ let mut t = {constructor};");
    for f in fields {
        s.push_str(&format!(" t.{f};"));
    }
    s.push_str(" t }");
    s
}

/// What a technique is, object-safe: its names, the lights it models and its limits.
pub trait TechniqueInfo: Send + Sync {
    /// Technique name as in reports (`"pcf"`, `"occlusion-slices"`, ...).
    fn name(&self) -> &'static str;
    /// Variant label of these parameters (`"r2"`, `"nbuffer-8"`, ...).
    fn variant(&self) -> String;
    /// The Rust expression that builds these parameters, as a user writes it
    /// (`"ShadowMapBaseline::new(Filter::Pcf { radius: 2 })"`): what the report's variant label
    /// stands for ([`call_with`] writes the fields a constructor does not take).
    fn call(&self) -> String;
    /// Whether this technique models lights of `kind`.
    fn models(&self, kind: LightKind) -> bool;
    /// Checks the parameters: a value out of its documented range is
    /// [`ShadowError::InvalidParameter`] naming it.
    fn validate(&self) -> Result<()> {
        Ok(())
    }
    /// Largest map side on `backend`; on the GPU, within `device`'s limits (on the CPU they do
    /// not count). Generation checks a side against it once, before any kernel runs, so
    /// kernels do not check the side again.
    fn max_resolution(&self, backend: Backend, device: DeviceLimits) -> u32 {
        match backend {
            Backend::Cpu => MAX_CPU_RESOLUTION,
            Backend::Gpu => device.max_texture_side,
        }
    }
    /// Bytes one generation for `light` at `resolution` allocates (maps and scratch, about the
    /// same on both backends), checked against the context's budget before anything is
    /// allocated. The default counts one `f32` map.
    fn memory_estimate(&self, _light: &Light, resolution: u32) -> u64 {
        crate::memory::maps(1, resolution, 4)
    }
    /// How this configuration's generation time grows with the map side; the default is a fixed
    /// number of passes ([`CostForm::Texels`]).
    fn cost_form(&self) -> CostForm {
        CostForm::Texels
    }
    /// Whether a cube face's maps depend only on what lies inside the face's pyramid grown by
    /// the light's radius (the pyramid of every light point, [`LightViews::faces_meeting`]),
    /// given the same coverage of the whole light ([`crate::coverage::Coverage::new`]): then a
    /// caster that changed outside a face leaves that face's maps as they are, and the frame
    /// pipeline makes again only the faces it meets ([`AnyMaps::remake_views`]). The default,
    /// `false`, makes every face again; a technique whose generation reads beyond the face
    /// (silhouette ribbons, skins) keeps it.
    fn face_local(&self) -> bool {
        false
    }
}

/// What bounds a map's side on a GPU ([`TechniqueInfo::max_resolution`]): the device's
/// largest 2D texture side and its largest storage buffer binding, from its `wgpu::Limits`
/// (`GpuContext::device_limits`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DeviceLimits {
    /// `max_texture_dimension_2d`.
    pub max_texture_side: u32,
    /// `max_storage_buffer_binding_size`, in bytes.
    pub max_storage_buffer_bytes: u64,
}

impl DeviceLimits {
    /// The limits of a device with `limits`.
    #[cfg(feature = "gpu")]
    pub fn from_limits(limits: &wgpu::Limits) -> Self {
        Self {
            max_texture_side: limits.max_texture_dimension_2d,
            max_storage_buffer_bytes: limits.max_storage_buffer_binding_size,
        }
    }

    /// The largest side of a square of `bytes_per_texel`-byte texels that one storage buffer
    /// binding holds.
    pub fn storage_side(&self, bytes_per_texel: u64) -> u32 {
        let texels = self.max_storage_buffer_bytes / bytes_per_texel.max(1);
        let mut side = (texels as f64).sqrt() as u64;
        // The float root may land one off either way.
        while side * side > texels {
            side -= 1;
        }
        while (side + 1) * (side + 1) <= texels {
            side += 1;
        }
        side.min(u32::MAX as u64) as u32
    }
}

/// The checks every generation passes before a kernel runs: parameters, light valid and
/// modelled, resolution in range, memory estimate of every view within `budget`, geometry
/// non-empty.
#[allow(clippy::too_many_arguments)]
fn check<'a>(
    t: &(impl TechniqueInfo + ?Sized),
    backend: Backend,
    device: DeviceLimits,
    budget: u64,
    geometry: &'a SceneGeometry,
    light: &'a Light,
    resolution: u32,
    views: &LightViews,
) -> Result<Checked<Generation<'a>>> {
    t.validate()?;
    light.validate()?;
    if !t.models(light.kind()) {
        return Err(ShadowError::UnsupportedLight {
            technique: t.name().to_string(),
            light: light.kind().name(),
        });
    }
    let max = t.max_resolution(backend, device);
    if resolution == 0 || resolution > max {
        return Err(ShadowError::InvalidResolution {
            requested: resolution,
            max,
        });
    }
    let need = t
        .memory_estimate(light, resolution)
        .saturating_mul(views.len() as u64);
    if need > budget {
        return Err(ShadowError::OverBudget {
            what: format!(
                "{} {} at {resolution}² ({} view{})",
                t.name(),
                t.variant(),
                views.len(),
                if views.len() == 1 { "" } else { "s" }
            ),
            need,
            budget,
        });
    }
    geometry.validate()?;
    Ok(Checked(Generation {
        geometry,
        light,
        region: Region::Whole,
        resolution,
    }))
}

/// The receivers after [`Receivers::validate`].
fn checked_receivers<'a>(receivers: &Receivers<'a>) -> Result<Checked<Receivers<'a>>> {
    receivers.validate()?;
    Ok(Checked(*receivers))
}

/// A soft-shadow technique: parameters (the implementing value), a generation step that builds
/// light-space maps and an evaluation step that turns maps plus receivers into visibility `V`,
/// on the CPU and on the GPU.
///
/// # Contract
///
/// - The required methods are the technique's kernels; they take [`Checked`] input and are
///   called through the provided methods, which check first: [`ShadowError::InvalidParameter`],
///   [`ShadowError::InvalidLight`], [`ShadowError::UnsupportedLight`] for a kind
///   [`models`](TechniqueInfo::models) rejects, [`ShadowError::InvalidResolution`] for 0 or
///   above [`max_resolution`](TechniqueInfo::max_resolution), [`ShadowError::OverBudget`] over
///   the context's memory budget, [`ShadowError::InvalidScene`] for empty geometry and
///   [`ShadowError::InvalidReceivers`] for receivers of unequal length or non-finite values.
/// - A light's shadow is a set of views ([`crate::views`]): the provided methods run a
///   generation kernel once per view (its [`Generation::region`]) and evaluate each receiver in
///   the view that holds it ([`LightViews::weight`]), so a kernel fits its maps to its input's
///   [`Generation::coverage`] and knows nothing of the others. The methods without a
///   [`LightViews`] argument plan the views themselves ([`LightViews::plan`] without a camera:
///   cube faces for a local light among its casters, one view otherwise).
/// - On the GPU, [`record_gpu`](Self::record_gpu) records generation into the caller's encoder
///   from geometry already on the GPU ([`GpuScene`]); the maps are ready once that encoder's
///   work has run (`record_gpu_in` for views the caller planned). `generate_gpu` and
///   `generate_gpu_on` are blocking wrappers of `record_gpu_in` that return after the GPU has
///   finished, so timing `generate_gpu_on` measures the GPU work without uploads.
///   wgpu validation and out-of-memory errors become [`ShadowError::Gpu`].
/// - The GPU evaluation is one WGSL function per view, `visibility(world_pos, normal) -> f32`
///   ([`VISIBILITY`](Self::VISIBILITY), [`crate::gpu::visibility`]): the blocking
///   `evaluate_gpu`, the G-buffer pass [`record_visibility`](Self::record_visibility) and a
///   renderer's own shader all call it.
/// - Evaluation returns one visibility `V` per receiver, in `[0, 1]` and finite: the fraction of
///   the light the point sees under the light's emission profile (1 lit, 0 umbra).
/// - The GPU path computes the same function as the CPU path: RMS of `V * 255` below 1.0 on every
///   catalogue scene, checked by tests on a real Vulkan driver.
pub trait ShadowTechnique: TechniqueInfo + Clone + 'static {
    /// One view's maps produced on the CPU.
    type CpuMaps: Send + Sync + 'static;
    /// One view's maps produced on (and kept on) the GPU.
    type GpuMaps: Send + Sync + 'static;

    /// The CPU generation kernel: the light-space maps of one view of checked input (fitted to
    /// [`Generation::coverage`]), their storage from `cpu`'s pool.
    fn cpu_maps(&self, cpu: &CpuContext, input: Checked<Generation<'_>>) -> Self::CpuMaps;

    /// The CPU evaluation kernel: `V` per checked receiver from one view's maps. Maps made with
    /// other parameters than these are [`ShadowError::MapsMismatch`].
    fn cpu_visibility(
        &self,
        maps: &Self::CpuMaps,
        receivers: Checked<Receivers<'_>>,
    ) -> Result<Vec<f32>>;

    /// The GPU generation: records the maps of one view of checked input into `enc` (nothing
    /// is submitted, mapped or uploaded beyond small parameter buffers).
    #[cfg(feature = "gpu")]
    ///
    /// The default, for a technique type built without its GPU path (its crate's `gpu`
    /// feature off while another crate turned this crate's on), is [`ShadowError::Gpu`].
    fn gpu_maps(
        &self,
        _gpu: &GpuContext,
        _enc: &mut wgpu::CommandEncoder,
        _scene: &GpuScene,
        _input: Checked<Generation<'_>>,
    ) -> Result<Self::GpuMaps> {
        Err(no_gpu_path(self.name()))
    }

    /// The GPU evaluation: the WGSL module that defines
    /// `fn visibility(world_pos: vec3<f32>, normal: vec3<f32>) -> f32` (the same function as
    /// [`evaluate_cpu`](Self::evaluate_cpu) over one view's maps, with `normal` a unit normal
    /// facing the viewer) over the maps' bindings in `@group(#{MAPS_GROUP})`, and the layout of
    /// that group. It depends on the type only, not on the parameters (those reach it through
    /// the bind group). The default, for a technique type built without its GPU path, is
    /// [`shader::NO_GPU_PATH`], which composes to nothing.
    #[cfg(feature = "gpu")]
    const VISIBILITY: &'static VisibilityShader = &shader::NO_GPU_PATH;

    /// A bind group of one view's `maps` (and these parameters) for `layout`, the layout of
    /// [`VISIBILITY`](Self::VISIBILITY)'s maps. Maps made with other parameters than these are
    /// [`ShadowError::MapsMismatch`].
    #[cfg(feature = "gpu")]
    fn bind_maps(
        &self,
        _gpu: &GpuContext,
        _layout: &wgpu::BindGroupLayout,
        _maps: &Self::GpuMaps,
    ) -> Result<wgpu::BindGroup> {
        Err(no_gpu_path(self.name()))
    }

    /// Gives one view's `maps` textures and buffers back to `gpu`'s pool
    /// ([`crate::gpu::pool`]); [`recycle_gpu`](Self::recycle_gpu) calls it for every view.
    #[cfg(feature = "gpu")]
    fn recycle_maps(&self, _gpu: &GpuContext, _maps: Self::GpuMaps) {}

    /// Builds the light-space maps on the CPU, in `cpu` (its pool and memory budget), for the
    /// views [`LightViews::plan`] chooses without a camera.
    fn generate_cpu(
        &self,
        cpu: &CpuContext,
        geometry: &SceneGeometry,
        light: &Light,
        resolution: u32,
    ) -> Result<ViewMaps<Self::CpuMaps>> {
        let views = LightViews::plan(light, geometry, None);
        self.generate_cpu_in(cpu, geometry, light, &views, resolution)
    }

    /// Builds the light-space maps of `views` on the CPU, one generation per view.
    fn generate_cpu_in(
        &self,
        cpu: &CpuContext,
        geometry: &SceneGeometry,
        light: &Light,
        views: &LightViews,
        resolution: u32,
    ) -> Result<ViewMaps<Self::CpuMaps>> {
        let input = check(
            self,
            Backend::Cpu,
            DeviceLimits::default(),
            cpu.memory_budget(),
            geometry,
            light,
            resolution,
            views,
        )?;
        let maps = views
            .regions()
            .iter()
            .map(|r| self.cpu_maps(cpu, input.in_region(*r)))
            .collect();
        Ok(ViewMaps::new(views.clone(), maps))
    }

    /// Visibility per receiver from CPU maps, each receiver from the view that holds it.
    fn evaluate_cpu(
        &self,
        maps: &ViewMaps<Self::CpuMaps>,
        receivers: &Receivers,
    ) -> Result<Vec<f32>> {
        self.validate()?;
        let receivers = checked_receivers(receivers)?;
        crate::views::combine(maps.views(), &receivers, |i, sub| {
            self.cpu_visibility(&maps.maps()[i], Checked(sub))
        })
    }

    /// Records the generation of the light-space maps of `scene` into `enc` (nothing is
    /// submitted, mapped or uploaded beyond small parameter buffers), for the views
    /// [`LightViews::plan`] chooses without a camera: the maps hold their contents once the
    /// caller has submitted `enc`.
    #[cfg(feature = "gpu")]
    fn record_gpu(
        &self,
        gpu: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        light: &Light,
        resolution: u32,
    ) -> Result<ViewMaps<Self::GpuMaps>> {
        let views = LightViews::plan(light, scene.geometry(), None);
        self.record_gpu_in(gpu, enc, scene, light, &views, resolution)
    }

    /// Records the generation of the maps of `views` into `enc`, one generation per view.
    #[cfg(feature = "gpu")]
    fn record_gpu_in(
        &self,
        gpu: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        light: &Light,
        views: &LightViews,
        resolution: u32,
    ) -> Result<ViewMaps<Self::GpuMaps>> {
        let input = check(
            self,
            Backend::Gpu,
            gpu.device_limits(),
            gpu.memory_budget(),
            scene.geometry(),
            light,
            resolution,
            views,
        )?;
        gpu.checked(&format!("{} generation", self.name()), || {
            let maps = views
                .regions()
                .iter()
                .map(|r| self.gpu_maps(gpu, enc, scene, input.in_region(*r)))
                .collect::<Result<Vec<_>>>()?;
            Ok(ViewMaps::new(views.clone(), maps))
        })
    }

    /// Builds the light-space maps on the GPU and waits: uploads `geometry`, plans the views
    /// without a camera, then [`generate_gpu_on`](Self::generate_gpu_on).
    #[cfg(feature = "gpu")]
    fn generate_gpu(
        &self,
        gpu: &GpuContext,
        geometry: &SceneGeometry,
        light: &Light,
        resolution: u32,
    ) -> Result<ViewMaps<Self::GpuMaps>> {
        let scene = GpuScene::new(gpu, geometry)?;
        let views = LightViews::plan(light, geometry, None);
        self.generate_gpu_on(gpu, &scene, light, &views, resolution)
    }

    /// Records [`record_gpu_in`](Self::record_gpu_in) into a fresh encoder, submits it and
    /// waits for the GPU.
    #[cfg(feature = "gpu")]
    fn generate_gpu_on(
        &self,
        gpu: &GpuContext,
        scene: &GpuScene,
        light: &Light,
        views: &LightViews,
        resolution: u32,
    ) -> Result<ViewMaps<Self::GpuMaps>> {
        gpu.checked(&format!("{} generation", self.name()), || {
            let mut enc = gpu.device.create_command_encoder(&Default::default());
            let maps = self.record_gpu_in(gpu, &mut enc, scene, light, views, resolution)?;
            gpu.queue.submit([enc.finish()]);
            gpu.wait()?;
            Ok(maps)
        })
    }

    /// Gives every view's textures and buffers back to `gpu`'s pool ([`crate::gpu::pool`]) for
    /// the next generation of the same size: call it once the maps are no longer read (work
    /// already recorded with them still runs first). A renderer that recycles last frame's maps
    /// before recording the next allocates no texture per frame (the new maps' parameter
    /// buffers, texture views and bind groups are small). Dropping the maps instead frees them.
    #[cfg(feature = "gpu")]
    fn recycle_gpu(&self, gpu: &GpuContext, maps: ViewMaps<Self::GpuMaps>) {
        for m in maps.into_maps() {
            self.recycle_maps(gpu, m);
        }
    }

    /// The bind groups [`record_visibility`](Self::record_visibility) reads: per view, the
    /// maps (the group a renderer's own shader binds, at the group its
    /// [`visibility_wgsl`](Self::visibility_wgsl) names, to call `visibility()`, with the
    /// layout [`crate::gpu::visibility::pipelines`] holds for this type) and how a receiver
    /// picks the view.
    #[cfg(feature = "gpu")]
    fn maps_bind_group(
        &self,
        gpu: &GpuContext,
        maps: &ViewMaps<Self::GpuMaps>,
    ) -> Result<MapsBinding> {
        self.validate()?;
        let p = pipelines::<Self>(gpu);
        gpu.checked(&format!("{} maps", self.name()), || {
            let groups = maps
                .maps()
                .iter()
                .map(|m| self.bind_maps(gpu, &p.maps_layout, m))
                .collect::<Result<Vec<_>>>()?;
            Ok(visibility::binding(gpu, &p, maps.views(), groups))
        })
    }

    /// Visibility per receiver from GPU maps, computed on the GPU and read back (blocking).
    #[cfg(feature = "gpu")]
    fn evaluate_gpu(
        &self,
        gpu: &GpuContext,
        maps: &ViewMaps<Self::GpuMaps>,
        receivers: &Receivers,
    ) -> Result<Vec<f32>> {
        let receivers = checked_receivers(receivers)?;
        let binding = self.maps_bind_group(gpu, maps)?;
        gpu.checked(&format!("{} evaluation", self.name()), || {
            let p = pipelines::<Self>(gpu);
            visibility::evaluate_buffers(gpu, &p, &binding, &receivers)
        })
    }

    /// WGSL that defines `fn visibility(world_pos: vec3<f32>, normal: vec3<f32>) -> f32` over
    /// one view's maps' bindings in `@group(group)` (laid out as
    /// [`VISIBILITY`](Self::VISIBILITY)'s maps: [`MapsBinding::maps`] binds them), for a
    /// renderer's own shader. Its other top-level names carry naga_oil's module decoration; a
    /// renderer with its own naga_oil composer can import the module instead
    /// ([`crate::gpu::shader::Library::add_to`]).
    #[cfg(feature = "gpu")]
    fn visibility_wgsl(group: u32) -> Result<String> {
        if std::ptr::eq(Self::VISIBILITY, &shader::NO_GPU_PATH) {
            return Err(no_gpu_path(std::any::type_name::<Self>()));
        }
        flattened(Self::VISIBILITY, group)
    }

    /// Records the evaluation of every texel of the caller's G-buffer `target` into `enc`, with
    /// the maps bound by `maps_bind` (from [`maps_bind_group`](Self::maps_bind_group)): one
    /// pass per view, each adding the receivers it holds; no readback.
    #[cfg(feature = "gpu")]
    fn record_visibility(
        &self,
        gpu: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        maps_bind: &MapsBinding,
        target: &ReceiverTextures,
    ) {
        visibility::record_texels(gpu, &pipelines::<Self>(gpu), enc, maps_bind, target);
    }
}

#[cfg(feature = "gpu")]
pub use visibility::MapsBinding;

/// The evaluation pipelines of technique type `T` on `gpu`, built once.
#[cfg(feature = "gpu")]
fn pipelines<T: ShadowTechnique>(
    gpu: &GpuContext,
) -> std::sync::Arc<visibility::VisibilityPipelines> {
    visibility::pipelines(gpu, T::VISIBILITY)
}

/// The technique's visibility module flattened to WGSL with its maps in `@group(group)`.
#[cfg(feature = "gpu")]
fn flattened(technique: &VisibilityShader, group: u32) -> Result<String> {
    let mut composer =
        shader::composer(technique.library, None).map_err(|e| ShadowError::Gpu(e.to_string()))?;
    let module = shader::compose_in(
        &mut composer,
        technique.library,
        technique.module,
        &[(shader::MAPS_GROUP, group)],
    )
    .map_err(|e| ShadowError::Gpu(e.to_string()))?;
    shader::wgsl(&module).map_err(|e| ShadowError::Gpu(e.to_string()))
}

/// Maps of either backend with the technique that made them, as [`DynTechnique`] hands them
/// out: they evaluate themselves, so a registry holds no map type and casts none.
pub struct AnyMaps(Box<dyn ErasedMaps>);

/// What [`AnyMaps`] can do, per technique type and backend.
trait ErasedMaps: Send + Sync {
    fn backend(&self) -> Backend;
    /// Whether `ctx` is where these maps were made (their backend and, for GPU maps, their
    /// context): only there can they be made again or recycled.
    fn made_in(&self, ctx: Context<'_>) -> bool;
    fn views(&self) -> &LightViews;
    fn remake(
        &mut self,
        ctx: Context<'_>,
        geometry: &SceneGeometry,
        light: &Light,
        planned: &LightViews,
        resolution: u32,
        indices: &[usize],
    ) -> Result<()>;
    /// [`remake`](Self::remake) on the GPU, recorded into `enc` (CPU maps are
    /// [`ShadowError::MapsMismatch`]).
    #[cfg(feature = "gpu")]
    #[allow(clippy::too_many_arguments)]
    fn remake_into(
        &mut self,
        gpu: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        geometry: &SceneGeometry,
        light: &Light,
        planned: &LightViews,
        resolution: u32,
        indices: &[usize],
    ) -> Result<()>;
    fn evaluate(&self, gpu: Option<&GpuContext>, receivers: &Receivers) -> Result<Vec<f32>>;
    #[cfg(feature = "gpu")]
    fn record_visibility(
        &self,
        gpu: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        target: &ReceiverTextures,
    ) -> Result<()>;
    fn recycle(self: Box<Self>, gpu: Option<&GpuContext>);
}

struct CpuMapsOf<T: ShadowTechnique>(T, ViewMaps<T::CpuMaps>);
/// GPU maps with their technique, their bind groups once a frame has recorded `V` from them
/// (made again after the maps change), and the serial of the context that made them
/// ([`GpuContext::serial`]).
#[cfg(feature = "gpu")]
struct GpuMapsOf<T: ShadowTechnique>(
    T,
    ViewMaps<T::GpuMaps>,
    std::sync::OnceLock<MapsBinding>,
    u64,
);

/// `maps`, made by `technique` in `gpu`, as [`AnyMaps`].
#[cfg(feature = "gpu")]
fn gpu_maps<T: ShadowTechnique>(
    technique: &T,
    gpu: &GpuContext,
    maps: ViewMaps<T::GpuMaps>,
) -> AnyMaps {
    AnyMaps(Box::new(GpuMapsOf(
        technique.clone(),
        maps,
        std::sync::OnceLock::new(),
        gpu.serial(),
    )))
}

#[cfg(feature = "gpu")]
fn need_gpu(gpu: Option<&GpuContext>) -> Result<&GpuContext> {
    gpu.ok_or_else(|| {
        ShadowError::NoAdapter("GPU maps were evaluated without a GPU context".into())
    })
}

/// Brings `maps` to the views `planned`: those at `indices` made by `generate` (given the views
/// to make; not called where there are none), the others kept. Returns the maps replaced.
fn remade<M>(
    maps: &mut ViewMaps<M>,
    planned: &LightViews,
    indices: &[usize],
    generate: impl FnOnce(&LightViews) -> Result<ViewMaps<M>>,
) -> Result<Vec<M>> {
    if indices.is_empty() {
        maps.splice(planned, &[], Vec::new());
        return Ok(Vec::new());
    }
    let fresh = generate(&planned.only(indices))?;
    Ok(maps.splice(planned, indices, fresh.into_maps()))
}

impl<T: ShadowTechnique> ErasedMaps for CpuMapsOf<T> {
    fn backend(&self) -> Backend {
        Backend::Cpu
    }
    fn made_in(&self, ctx: Context<'_>) -> bool {
        ctx.backend() == Backend::Cpu
    }
    fn views(&self) -> &LightViews {
        self.1.views()
    }
    fn remake(
        &mut self,
        ctx: Context<'_>,
        geometry: &SceneGeometry,
        light: &Light,
        planned: &LightViews,
        resolution: u32,
        indices: &[usize],
    ) -> Result<()> {
        let Self(t, maps) = self;
        remade(maps, planned, indices, |views| match ctx {
            Context::Cpu(cpu) => t.generate_cpu_in(cpu, geometry, light, views, resolution),
            _ => Err(ShadowError::MapsMismatch(
                "CPU maps are made again on the CPU".into(),
            )),
        })?;
        Ok(())
    }
    #[cfg(feature = "gpu")]
    fn remake_into(
        &mut self,
        _: &GpuContext,
        _: &mut wgpu::CommandEncoder,
        _: &SceneGeometry,
        _: &Light,
        _: &LightViews,
        _: u32,
        _: &[usize],
    ) -> Result<()> {
        Err(ShadowError::MapsMismatch(
            "CPU maps are made again on the CPU".into(),
        ))
    }
    fn evaluate(&self, _: Option<&GpuContext>, receivers: &Receivers) -> Result<Vec<f32>> {
        self.0.evaluate_cpu(&self.1, receivers)
    }
    #[cfg(feature = "gpu")]
    fn record_visibility(
        &self,
        _: &GpuContext,
        _: &mut wgpu::CommandEncoder,
        _: &ReceiverTextures,
    ) -> Result<()> {
        Err(ShadowError::MapsMismatch(
            "CPU maps write no GPU texture: generate them on the GPU".into(),
        ))
    }
    fn recycle(self: Box<Self>, _: Option<&GpuContext>) {}
}

#[cfg(feature = "gpu")]
impl<T: ShadowTechnique> ErasedMaps for GpuMapsOf<T> {
    fn backend(&self) -> Backend {
        Backend::Gpu
    }
    fn made_in(&self, ctx: Context<'_>) -> bool {
        matches!(ctx, Context::Gpu(gpu) if gpu.serial() == self.3)
    }
    fn views(&self) -> &LightViews {
        self.1.views()
    }
    fn remake(
        &mut self,
        ctx: Context<'_>,
        geometry: &SceneGeometry,
        light: &Light,
        planned: &LightViews,
        resolution: u32,
        indices: &[usize],
    ) -> Result<()> {
        // The bind groups hold the maps and views it replaces: the next frame binds anew.
        self.2 = std::sync::OnceLock::new();
        let Context::Gpu(gpu) = ctx else {
            return remade(&mut self.1, planned, indices, |_| {
                Err(ShadowError::MapsMismatch(
                    "GPU maps are made again on the GPU".into(),
                ))
            })
            .map(drop);
        };
        if indices.is_empty() {
            // Nothing to make: the maps serve the planned views as they are.
            return remade(&mut self.1, planned, indices, |_| unreachable!()).map(drop);
        }
        let name = self.0.name();
        gpu.checked(&format!("{name} generation"), || {
            let mut enc = gpu.device.create_command_encoder(&Default::default());
            self.remake_into(gpu, &mut enc, geometry, light, planned, resolution, indices)?;
            gpu.queue.submit([enc.finish()]);
            gpu.wait()
        })
    }
    fn remake_into(
        &mut self,
        gpu: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        geometry: &SceneGeometry,
        light: &Light,
        planned: &LightViews,
        resolution: u32,
        indices: &[usize],
    ) -> Result<()> {
        // The bind groups hold the maps and views it replaces: the next frame binds anew.
        self.2 = std::sync::OnceLock::new();
        let Self(t, maps, ..) = self;
        let replaced = remade(maps, planned, indices, |views| {
            let scene = GpuScene::new(gpu, geometry)?;
            t.record_gpu_in(gpu, enc, &scene, light, views, resolution)
        })?;
        // Work already recorded with them (the frames before) runs first.
        for old in replaced {
            t.recycle_maps(gpu, old);
        }
        Ok(())
    }
    fn evaluate(&self, gpu: Option<&GpuContext>, receivers: &Receivers) -> Result<Vec<f32>> {
        self.0.evaluate_gpu(need_gpu(gpu)?, &self.1, receivers)
    }
    fn record_visibility(
        &self,
        gpu: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        target: &ReceiverTextures,
    ) -> Result<()> {
        let binding = match self.2.get() {
            Some(b) => b,
            None => {
                // Two threads recording at once both make it; either serves.
                let _ = self.2.set(self.0.maps_bind_group(gpu, &self.1)?);
                self.2.get().expect("set above")
            }
        };
        self.0.record_visibility(gpu, enc, binding, target);
        Ok(())
    }
    fn recycle(self: Box<Self>, gpu: Option<&GpuContext>) {
        // Another context's pool (perhaps of another device) could not serve them: dropped.
        if let Some(gpu) = gpu.filter(|g| g.serial() == self.3) {
            let Self(t, maps, ..) = *self;
            t.recycle_gpu(gpu, maps);
        }
    }
}

impl AnyMaps {
    /// The backend that produced these maps.
    pub fn backend(&self) -> Backend {
        self.0.backend()
    }

    /// The views the maps were generated for (or followed since, [`AnyMaps::follow`]).
    pub fn views(&self) -> &LightViews {
        self.0.views()
    }

    /// Brings these maps, made at `resolution` in `ctx` for the same light and casters, to the
    /// views `planned` later, where the plans allow ([`LightViews::moved`]: cascades at the
    /// same split depths): the views whose windows moved are made again over `geometry`, the
    /// others serve as they are, and the maps evaluate with `planned`'s selection from then on.
    /// Returns how many views it made again (0: the maps serve as they are), or `None` where
    /// the plans differ more or `ctx` is not where the maps were made (another backend, or
    /// another GPU context), which are then left as they were: generate anew.
    pub fn follow(
        &mut self,
        ctx: Context<'_>,
        geometry: &SceneGeometry,
        light: &Light,
        planned: &LightViews,
        resolution: u32,
    ) -> Result<Option<usize>> {
        let Some(moved) = self.moved_views(ctx, planned, resolution) else {
            return Ok(None);
        };
        self.0
            .remake(ctx, geometry, light, planned, resolution, &moved)?;
        Ok(Some(moved.len()))
    }

    /// [`AnyMaps::follow`] in `gpu`, the views it makes again recorded into `enc` (nothing is
    /// submitted, mapped or uploaded beyond the casters and small parameter buffers): the maps
    /// hold their new views' contents once the caller has submitted `enc`. The views it
    /// replaces go back to `gpu`'s pool (work already recorded with them runs first). CPU maps
    /// are `None`, as for any context they were not made in.
    #[cfg(feature = "gpu")]
    pub fn follow_into(
        &mut self,
        gpu: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        geometry: &SceneGeometry,
        light: &Light,
        planned: &LightViews,
        resolution: u32,
    ) -> Result<Option<usize>> {
        let Some(moved) = self.moved_views(Context::Gpu(gpu), planned, resolution) else {
            return Ok(None);
        };
        self.0
            .remake_into(gpu, enc, geometry, light, planned, resolution, &moved)?;
        Ok(Some(moved.len()))
    }

    /// Makes the views at `indices` of these maps (made at `resolution` in `ctx` for the same
    /// light) again over `geometry`, keeping the others and the views as planned: for a
    /// technique whose faces are local ([`TechniqueInfo::face_local`]), the faces a changed
    /// caster meets ([`LightViews::faces_meeting`]). The views it replaces go back to the pool
    /// where `ctx` made them; maps of another context are [`ShadowError::MapsMismatch`].
    pub fn remake_views(
        &mut self,
        ctx: Context<'_>,
        geometry: &SceneGeometry,
        light: &Light,
        resolution: u32,
        indices: &[usize],
    ) -> Result<()> {
        if !self.0.made_in(ctx) {
            return Err(ShadowError::MapsMismatch(
                "maps are made again only where they were made".into(),
            ));
        }
        let planned = self.views().clone();
        self.0
            .remake(ctx, geometry, light, &planned, resolution, indices)
    }

    /// [`AnyMaps::remake_views`] in `gpu`, recorded into `enc` (nothing is submitted, mapped
    /// or uploaded beyond the casters and small parameter buffers).
    #[cfg(feature = "gpu")]
    pub fn remake_views_into(
        &mut self,
        gpu: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        geometry: &SceneGeometry,
        light: &Light,
        resolution: u32,
        indices: &[usize],
    ) -> Result<()> {
        if !self.0.made_in(Context::Gpu(gpu)) {
            return Err(ShadowError::MapsMismatch(
                "maps are made again only where they were made".into(),
            ));
        }
        let planned = self.views().clone();
        self.0
            .remake_into(gpu, enc, geometry, light, &planned, resolution, indices)
    }

    /// The views of `planned` whose windows moved from these maps', where `ctx` made them and
    /// the plans allow following ([`AnyMaps::follow`]).
    fn moved_views(
        &self,
        ctx: Context<'_>,
        planned: &LightViews,
        resolution: u32,
    ) -> Option<Vec<usize>> {
        if !self.0.made_in(ctx) {
            return None;
        }
        self.views().moved(planned, resolution)
    }

    /// Visibility per receiver, on the backend that produced the maps (`gpu` is required for
    /// GPU maps).
    pub fn evaluate(&self, gpu: Option<&GpuContext>, receivers: &Receivers) -> Result<Vec<f32>> {
        self.0.evaluate(gpu, receivers)
    }

    /// Records `V` of every texel of the G-buffer `target` into `enc` from GPU maps
    /// ([`ShadowTechnique::record_visibility`]); nothing is read back. CPU maps are
    /// [`ShadowError::MapsMismatch`].
    #[cfg(feature = "gpu")]
    pub fn record_visibility(
        &self,
        gpu: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        target: &ReceiverTextures,
    ) -> Result<()> {
        self.0.record_visibility(gpu, enc, target)
    }

    /// Gives GPU maps back to `gpu`'s pool ([`ShadowTechnique::recycle_gpu`]) where `gpu` made
    /// them (maps of another context are dropped); CPU maps are dropped, their storage going
    /// back to the pool of the context that made them.
    pub fn recycle(self, gpu: Option<&GpuContext>) {
        self.0.recycle(gpu);
    }
}

/// The object-safe form of a [`ShadowTechnique`], for a registry of techniques of different
/// types: every [`ShadowTechnique`] is one.
pub trait DynTechnique: TechniqueInfo {
    /// Generation in `ctx` for the views [`LightViews::plan`] chooses without a camera (see
    /// [`ShadowTechnique::generate_cpu`] and [`ShadowTechnique::generate_gpu`]).
    fn generate(
        &self,
        ctx: Context<'_>,
        geometry: &SceneGeometry,
        light: &Light,
        resolution: u32,
    ) -> Result<AnyMaps> {
        let views = LightViews::plan(light, geometry, None);
        self.generate_in(ctx, geometry, light, &views, resolution)
    }
    /// Generation of `views` in `ctx` (see [`ShadowTechnique::generate_cpu_in`] and
    /// [`ShadowTechnique::generate_gpu_on`]).
    fn generate_in(
        &self,
        ctx: Context<'_>,
        geometry: &SceneGeometry,
        light: &Light,
        views: &LightViews,
        resolution: u32,
    ) -> Result<AnyMaps>;
    /// GPU generation of `views` from a scene already on the GPU (nothing uploaded but
    /// parameters).
    #[cfg(feature = "gpu")]
    fn generate_gpu_on(
        &self,
        gpu: &GpuContext,
        scene: &GpuScene,
        light: &Light,
        views: &LightViews,
        resolution: u32,
    ) -> Result<AnyMaps>;
    /// GPU generation of `views` recorded into `enc`: uploads `geometry`, then
    /// [`ShadowTechnique::record_gpu_in`] (nothing is submitted, mapped or uploaded beyond the
    /// casters and small parameter buffers): the maps hold their contents once the caller has
    /// submitted `enc`.
    #[cfg(feature = "gpu")]
    #[allow(clippy::too_many_arguments)]
    fn record_in(
        &self,
        gpu: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        geometry: &SceneGeometry,
        light: &Light,
        views: &LightViews,
        resolution: u32,
    ) -> Result<AnyMaps>;
    /// See [`ShadowTechnique::visibility_wgsl`].
    #[cfg(feature = "gpu")]
    fn visibility_wgsl(&self, group: u32) -> Result<String>;
    /// See [`ShadowTechnique::VISIBILITY`].
    #[cfg(feature = "gpu")]
    fn visibility_shader(&self) -> &'static VisibilityShader;
    /// A renderer's frame in one call: records the generation of `views` of `light` at
    /// `resolution` from `scene` and `V` for every texel of the G-buffer `target` into `enc`,
    /// then gives the maps back to `gpu`'s pool for the next frame's generation
    /// ([`ShadowTechnique::record_gpu_in`], [`ShadowTechnique::maps_bind_group`],
    /// [`ShadowTechnique::record_visibility`], [`ShadowTechnique::recycle_gpu`]). Nothing is
    /// read back.
    #[cfg(feature = "gpu")]
    #[allow(clippy::too_many_arguments)]
    fn record_frame(
        &self,
        gpu: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        light: &Light,
        views: &LightViews,
        resolution: u32,
        target: &ReceiverTextures,
    ) -> Result<()>;
}

impl<T: ShadowTechnique> DynTechnique for T {
    fn generate_in(
        &self,
        ctx: Context<'_>,
        geometry: &SceneGeometry,
        light: &Light,
        views: &LightViews,
        resolution: u32,
    ) -> Result<AnyMaps> {
        match ctx {
            Context::Cpu(cpu) => Ok(AnyMaps(Box::new(CpuMapsOf(
                self.clone(),
                self.generate_cpu_in(cpu, geometry, light, views, resolution)?,
            )))),
            #[cfg(feature = "gpu")]
            Context::Gpu(gpu) => {
                let scene = GpuScene::new(gpu, geometry)?;
                DynTechnique::generate_gpu_on(self, gpu, &scene, light, views, resolution)
            }
            #[cfg(not(feature = "gpu"))]
            Context::Gpu(gpu) => match *gpu {},
        }
    }
    #[cfg(feature = "gpu")]
    fn generate_gpu_on(
        &self,
        gpu: &GpuContext,
        scene: &GpuScene,
        light: &Light,
        views: &LightViews,
        resolution: u32,
    ) -> Result<AnyMaps> {
        let maps = ShadowTechnique::generate_gpu_on(self, gpu, scene, light, views, resolution)?;
        Ok(gpu_maps(self, gpu, maps))
    }
    #[cfg(feature = "gpu")]
    fn record_in(
        &self,
        gpu: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        geometry: &SceneGeometry,
        light: &Light,
        views: &LightViews,
        resolution: u32,
    ) -> Result<AnyMaps> {
        let scene = GpuScene::new(gpu, geometry)?;
        let maps = self.record_gpu_in(gpu, enc, &scene, light, views, resolution)?;
        Ok(gpu_maps(self, gpu, maps))
    }
    #[cfg(feature = "gpu")]
    fn visibility_wgsl(&self, group: u32) -> Result<String> {
        T::visibility_wgsl(group)
    }
    #[cfg(feature = "gpu")]
    fn visibility_shader(&self) -> &'static VisibilityShader {
        T::VISIBILITY
    }
    #[cfg(feature = "gpu")]
    fn record_frame(
        &self,
        gpu: &GpuContext,
        enc: &mut wgpu::CommandEncoder,
        scene: &GpuScene,
        light: &Light,
        views: &LightViews,
        resolution: u32,
        target: &ReceiverTextures,
    ) -> Result<()> {
        let maps = self.record_gpu_in(gpu, enc, scene, light, views, resolution)?;
        let maps_bind = self.maps_bind_group(gpu, &maps)?;
        self.record_visibility(gpu, enc, &maps_bind, target);
        // Done reading the maps: their textures serve the next generation.
        self.recycle_gpu(gpu, maps);
        Ok(())
    }
}
