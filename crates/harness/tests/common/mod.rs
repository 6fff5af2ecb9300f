//! Helpers shared by the harness test binaries (`suite`, `stability`).

#![allow(dead_code)]

use glam::Vec3;
use soft_shadow_core::SceneGeometry;
use soft_shadow_reference::scenes::SceneSpec;

/// Geometry and G-buffer receivers of a scene, without the reference (cheap).
pub struct Receivers {
    /// Flattened geometry.
    pub geometry: SceneGeometry,
    /// Receiver positions.
    pub positions: Vec<Vec3>,
    /// Receiver normals.
    pub normals: Vec<Vec3>,
    /// What the camera sees, for a distant light's cascades.
    pub seen: Option<soft_shadow_core::SeenDepth>,
}

/// Renders the CPU G-buffer of `spec` at `size²` and returns its receivers.
pub fn receivers(spec: &SceneSpec, size: u32) -> Receivers {
    let (geometry, positions, normals) =
        soft_shadow_reference::scenes::scene_receivers(spec, size).expect("catalogue scene builds");
    let seen = soft_shadow_core::SeenDepth::of_points(spec.camera.view(size, size), &positions);
    Receivers {
        geometry,
        positions,
        normals,
        seen,
    }
}

/// The same receivers as the techniques take them.
impl Receivers {
    /// Borrowed as [`soft_shadow_core::Receivers`].
    pub fn as_receivers(&self) -> soft_shadow_core::Receivers<'_> {
        soft_shadow_core::Receivers::new(&self.positions, &self.normals)
    }

    /// The views of `light` over the geometry and what the camera sees.
    pub fn views(&self, light: &soft_shadow_core::Light) -> soft_shadow_core::LightViews {
        soft_shadow_core::LightViews::plan_seen(
            light,
            &self.geometry,
            self.seen.as_ref(),
            &self.positions,
        )
    }
}

pub use harness::testing::gpu_for_test;

/// The CPU backend, and the GPU one where there is a context.
pub fn backends(gpu: Option<&soft_shadow_core::GpuContext>) -> Vec<soft_shadow_core::Backend> {
    let mut b = vec![soft_shadow_core::Backend::Cpu];
    if gpu.is_some() {
        b.push(soft_shadow_core::Backend::Gpu);
    }
    b
}

/// One CPU context for the whole test binary (its pool shared by the tests running in it).
pub fn cpu() -> &'static soft_shadow_core::CpuContext {
    static CPU: std::sync::OnceLock<soft_shadow_core::CpuContext> = std::sync::OnceLock::new();
    CPU.get_or_init(soft_shadow_core::CpuContext::new)
}

/// The context `backend` runs in: [`cpu`], or `gpu` (which the GPU backend needs).
pub fn context(
    backend: soft_shadow_core::Backend,
    gpu: Option<&soft_shadow_core::GpuContext>,
) -> soft_shadow_core::Context<'_> {
    match (backend, gpu) {
        (soft_shadow_core::Backend::Gpu, Some(g)) => soft_shadow_core::Context::Gpu(g),
        (soft_shadow_core::Backend::Gpu, None) => panic!("the GPU backend without a GPU context"),
        (soft_shadow_core::Backend::Cpu, _) => soft_shadow_core::Context::Cpu(cpu()),
    }
}

/// A receiver whose `V` differs between the backends by more than this is *apart*: one whose
/// depth lies within a rasterizer's precision of a caster's, or under a sliver whose coverage
/// the rasterizers decide differently. A GPU rasterizer snaps vertices to its sub-pixel grid and
/// interpolates in its own precision, so an isolated receiver may flip between lit and shadowed
/// (lavapipe follows the CPU rasterizer exactly; an NVIDIA H200 flipped 1 receiver of 8448 on
/// `torus` at 96², and on `light-plane`'s edge-on cube face moved 9 of 7655 by up to 0.19).
pub const APART: f32 = 0.1;

/// The share of receivers that may be [`APART`] in a configuration whose backends agree.
pub const MAX_APART: f64 = 2e-3;

/// The RMS of `V * 255` over the receivers that are not [`APART`], below which backends agree.
pub const MAX_RMS_REST: f64 = 1.0;

/// How far a GPU path's `V` lies from its CPU path's: the one measure of every test that holds
/// the backends to each other.
#[derive(Clone, Copy, Debug)]
pub struct Agreement {
    /// Receivers compared.
    pub receivers: usize,
    /// Receivers [`APART`].
    pub apart: usize,
    /// The largest difference.
    pub worst: f32,
    /// RMS of `V * 255` over every receiver.
    pub rms: f64,
    /// RMS of `V * 255` over the receivers that are not apart.
    pub rms_rest: f64,
}

impl Agreement {
    /// Compares `cpu` with `gpu`, receiver by receiver.
    pub fn of(cpu: &[f32], gpu: &[f32]) -> Agreement {
        assert_eq!(
            cpu.len(),
            gpu.len(),
            "the backends return one V per receiver"
        );
        let (mut apart, mut worst, mut all, mut rest) = (0, 0.0f32, 0.0f64, 0.0f64);
        for (c, g) in cpu.iter().zip(gpu) {
            let d = (c - g).abs();
            let sq = (d as f64 * 255.0).powi(2);
            all += sq;
            if d > APART || d.is_nan() {
                apart += 1;
                worst = worst.max(if d.is_nan() { f32::INFINITY } else { d });
            } else {
                worst = worst.max(d);
                rest += sq;
            }
        }
        let n = cpu.len().max(1) as f64;
        let kept = (cpu.len() - apart).max(1) as f64;
        Agreement {
            receivers: cpu.len(),
            apart,
            worst,
            rms: (all / n).sqrt(),
            rms_rest: (rest / kept).sqrt(),
        }
    }

    /// Whether the backends agree: at most [`MAX_APART`] of the receivers apart, and the others
    /// within [`MAX_RMS_REST`].
    pub fn holds(&self) -> bool {
        self.apart as f64 <= MAX_APART * self.receivers as f64 && self.rms_rest < MAX_RMS_REST
    }
}

impl std::fmt::Display for Agreement {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "CPU/GPU rms {:.3}, {} of {} receivers apart (up to {:.3}), rms of the rest {:.3}",
            self.rms, self.apart, self.receivers, self.worst, self.rms_rest
        )
    }
}

/// The checks of a test over many configurations that failed, reported together at its end, so
/// one run names every configuration that fails and not only the first.
#[derive(Debug, Default)]
pub struct Failures(Vec<String>);

impl Failures {
    /// Records `what` when `holds` is false.
    pub fn check(&mut self, holds: bool, what: impl FnOnce() -> String) {
        if !holds {
            self.0.push(what());
        }
    }

    /// Prints and judges the [`Agreement`] of `cpu` and `gpu` in the configuration `what`.
    pub fn agree(&mut self, what: &str, cpu: &[f32], gpu: &[f32]) {
        let a = Agreement::of(cpu, gpu);
        println!("{what}: {a}");
        self.check(a.holds(), || format!("{what}: {a}"));
    }

    /// Fails the test with every recorded failure.
    #[track_caller]
    pub fn assert_none(self) {
        assert!(
            self.0.is_empty(),
            "{} checks failed:\n{}",
            self.0.len(),
            self.0.join("\n")
        );
    }
}

/// Whether `ctx` rasterizes as the CPU rasterizer does, texel for texel: a software rasterizer
/// (lavapipe), whose rules and precision the CPU's follows. A hardware rasterizer snaps vertices
/// to its sub-pixel grid and interpolates in its own precision, so its maps differ from the
/// CPU's by more than rounding (on an NVIDIA H200: depths by up to 6.5e-4 of a view's range on
/// 6% of the bunny's covered texels, 11% of `thin`'s depth-image texels by more than a storage
/// step): there the tests hold each technique's `V` to the CPU's ([`Agreement`]) and print how
/// far its maps lie, and they hold the rasterizer itself to wider bounds.
pub fn rasterizes_as_the_cpu(ctx: &soft_shadow_core::GpuContext) -> bool {
    ctx.info.device_type == wgpu::DeviceType::Cpu
}

/// A `w x h` texture of `format` for `usage` (and copies from it).
pub fn texture(
    gpu: &soft_shadow_core::GpuContext,
    label: &str,
    (w, h, layers): (u32, u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: layers,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: usage | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

/// A `w x h` float texture with `texels`, bound as a non-filterable `texture_2d<f32>`.
pub fn upload(
    gpu: &soft_shadow_core::GpuContext,
    label: &str,
    w: u32,
    h: u32,
    texels: &[[f32; 4]],
) -> wgpu::Texture {
    let tex = texture(
        gpu,
        label,
        (w, h, 1),
        wgpu::TextureFormat::Rgba32Float,
        wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
    );
    gpu.queue.write_texture(
        tex.as_image_copy(),
        bytemuck::cast_slice(texels),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(w * 16),
            rows_per_image: Some(h),
        },
        tex.size(),
    );
    tex
}
