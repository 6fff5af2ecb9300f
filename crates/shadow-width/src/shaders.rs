//! The crate's WGSL and its programs, each declared once with its bindings: the width kernels
//! (`width.wgsl`), jump flooding (`jump_flood.wgsl`) and evaluation (`visibility.wgsl`).

use crate::eval::EvalParams;
use bytemuck::{Pod, Zeroable};
use soft_shadow_core::MapParams;
use soft_shadow_core::gpu::shader::{
    DEPTH_ARRAY, Group, Library, Program, ShaderModule, VisibilityShader, storage, uniform,
};

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
/// The width kernels' parameters (`width.wgsl`).
pub(crate) struct WidthParams {
    pub(crate) map: MapParams,
    pub(crate) resolution: u32,
    pub(crate) step: u32,
    pub(crate) neighbours: u32,
    pub(crate) cap: f32,
    /// `(dx, dy, distance, 0)` per neighbour of a propagation pass ([`crate::width::propagate::offsets`]).
    pub(crate) offsets: [[f32; 4]; 8],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
/// The jump flood's parameters (`jump_flood.wgsl`).
pub(crate) struct FloodParams {
    pub(crate) resolution: u32,
    pub(crate) step: u32,
    pub(crate) _pad: [u32; 2],
}

/// The crate's WGSL: the width kernels and the visibility module.
pub static SHADERS: Library = Library {
    name: "shadow-width",
    modules: &[
        ShaderModule {
            path: "shadow_width::width",
            source: include_str!("width.wgsl"),
        },
        ShaderModule {
            path: "shadow_width::visibility",
            source: include_str!("visibility.wgsl"),
        },
        ShaderModule {
            path: "shadow_width::jump_flood",
            source: include_str!("jump_flood.wgsl"),
        },
    ],
    depends: &[&soft_shadow_core::gpu::shader::SHADERS],
    programs: &[&WIDTH, &JUMP_FLOOD],
};

/// `width.wgsl`: parameters, the depth array, the float buffers (source, destination), the seed
/// buffers (source, destination) and the envelope scratch (vertices, boundaries).
pub(crate) static WIDTH: Program = Program {
    library: &SHADERS,
    module: "shadow_width::width",
    defs: &[],
    groups: &[Group::compute(&[
        uniform::<WidthParams>(),
        DEPTH_ARRAY,
        storage::<f32>(true),
        storage::<f32>(false),
        storage::<u32>(true),
        storage::<u32>(false),
        storage::<u32>(false),
        storage::<f32>(false),
    ])],
};

/// `visibility()` over the parameters, the depth array, the width map and the attenuation table.
pub static VISIBILITY: VisibilityShader = VisibilityShader {
    library: &SHADERS,
    module: "shadow_width::visibility",
    maps: Group::compute(&[
        uniform::<EvalParams>(),
        DEPTH_ARRAY,
        storage::<f32>(true),
        storage::<f32>(true),
    ]),
};

/// `jump_flood.wgsl`: parameters, the source seeds, the destination.
pub(crate) static JUMP_FLOOD: Program = Program {
    library: &SHADERS,
    module: "shadow_width::jump_flood",
    defs: &[],
    groups: &[Group::compute(&[
        uniform::<FloodParams>(),
        storage::<u32>(true),
        storage::<u32>(false),
    ])],
};
