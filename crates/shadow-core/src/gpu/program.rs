//! Programs built on a device from their declarations ([`Program`]): the shader module composed
//! by naga_oil, the bind group layouts and the pipeline layout, built once per context and
//! cached; compute pipelines and [`Kernel`]s from them.

use super::GpuContext;
use super::shader::{self, Group, Library, Program, VisibilityShader};
use naga_oil::compose::Composer;
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

/// A program on one device.
pub struct BuiltProgram {
    /// The composed module.
    pub module: wgpu::ShaderModule,
    /// Bind group `i`'s layout at index `i`.
    pub layouts: Vec<wgpu::BindGroupLayout>,
    /// The pipeline layout of every group in order.
    pub pipeline_layout: wgpu::PipelineLayout,
}

impl BuiltProgram {
    /// The compute pipeline of entry point `entry`.
    pub fn compute(&self, ctx: &GpuContext, entry: &str) -> wgpu::ComputePipeline {
        ctx.device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: Some(&self.pipeline_layout),
                module: &self.module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
    }
}

/// One compute entry point of a one-group program, with that group's layout.
pub struct Kernel {
    /// The bind group layout.
    pub layout: wgpu::BindGroupLayout,
    /// The pipeline.
    pub pipeline: wgpu::ComputePipeline,
}

impl Kernel {
    /// Entry point `entry` of `program` on `ctx`.
    pub fn new(ctx: &GpuContext, program: &'static Program, entry: &str) -> Self {
        let p = ctx.program(program);
        Self {
            layout: p.layouts[0].clone(),
            pipeline: p.compute(ctx, entry),
        }
    }
}

/// Programs built on one context, and a composer per library.
#[derive(Default)]
struct ProgramCache {
    built: Mutex<HashMap<usize, Arc<BuiltProgram>>>,
    composers: Mutex<HashMap<usize, Composer>>,
}

/// A bind group layout of `group`, visible to `stages`.
pub fn layout(
    ctx: &GpuContext,
    label: &str,
    group: &Group,
    stages: wgpu::ShaderStages,
) -> wgpu::BindGroupLayout {
    ctx.device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(label),
            entries: &group.entries(stages),
        })
}

/// The pipeline layout of `groups`, group 0 first.
pub fn pipeline_layout(
    ctx: &GpuContext,
    label: &str,
    groups: &[&wgpu::BindGroupLayout],
) -> wgpu::PipelineLayout {
    let groups: Vec<Option<&wgpu::BindGroupLayout>> = groups.iter().copied().map(Some).collect();
    ctx.device
        .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(label),
            bind_group_layouts: &groups,
            immediate_size: 0,
        })
}

/// A wgpu shader module of a composed naga module.
pub fn shader_module(ctx: &GpuContext, label: &str, module: naga::Module) -> wgpu::ShaderModule {
    ctx.device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(label),
            source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(module)),
        })
}

/// Module `path` of `library` with `defs`, composed with the technique `alias` where given.
///
/// # Panics
///
/// When the module does not compose: a bug of the library that ships it, which the workspace's
/// shader test (composing every program of every library) catches before a release.
pub(crate) fn compose(
    ctx: &GpuContext,
    library: &'static Library,
    path: &str,
    defs: &[(&str, u32)],
    alias: Option<&'static VisibilityShader>,
) -> naga::Module {
    let cache = ctx.cached(|_| ProgramCache::default());
    let key = alias.map_or(library as *const Library as usize, |a| {
        a as *const _ as usize
    });
    let mut composers = cache.composers.lock().unwrap_or_else(|e| e.into_inner());
    let composer = match composers.entry(key) {
        std::collections::hash_map::Entry::Occupied(e) => e.into_mut(),
        std::collections::hash_map::Entry::Vacant(v) => {
            v.insert(shader::composer(library, alias).unwrap_or_else(|e| panic!("{e}")))
        }
    };
    shader::compose_in(composer, library, path, defs).unwrap_or_else(|e| panic!("{e}"))
}

impl GpuContext {
    /// `program` built on this device (composed, its layouts made from its declaration), once.
    ///
    /// # Panics
    ///
    /// When the program does not compose: a bug of the library that ships it, which the
    /// workspace's shader test (composing every program of every library) catches.
    pub fn program(&self, program: &'static Program) -> Arc<BuiltProgram> {
        let cache = self.cached(|_| ProgramCache::default());
        let key = program as *const Program as usize;
        if let Some(p) = cache
            .built
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .get(&key)
        {
            return p.clone();
        }
        let module = compose(self, program.library, program.module, program.defs, None);
        let built = Arc::new(build(self, program.module, module, program.groups));
        cache
            .built
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .insert(key, built.clone());
        built
    }
}

/// The module and layouts of `groups` (each visible to its own stages).
pub(crate) fn build(
    ctx: &GpuContext,
    label: &str,
    module: naga::Module,
    groups: &[Group],
) -> BuiltProgram {
    let layouts: Vec<wgpu::BindGroupLayout> = groups
        .iter()
        .map(|g| layout(ctx, label, g, g.stages))
        .collect();
    let refs: Vec<&wgpu::BindGroupLayout> = layouts.iter().collect();
    BuiltProgram {
        module: shader_module(ctx, label, module),
        pipeline_layout: pipeline_layout(ctx, label, &refs),
        layouts,
    }
}
