//! WGSL modules composed by [`naga_oil`], and the one declaration of every binding.
//!
//! Every `.wgsl` file of the workspace is a module with an import path
//! (`#define_import_path soft_shadow_core::light_space`) that imports what it uses
//! (`#import soft_shadow_core::light_space::{MapView, shadow_coord}`); naga_oil resolves the
//! imports transitively. A crate lists its modules, and the libraries they import from, as a
//! [`Library`] (`soft_shadow_core::gpu::shader::SHADERS`, `occlusion_slices::SHADERS`, ...).
//!
//! Variants are shader defs, never edits of the text: a technique's visibility module binds its
//! maps in `@group(#{MAPS_GROUP})` ([`MAPS_GROUP`]), and a kernel's variants set their own defs
//! (`#if STORAGE == 2`). A [`Program`] is one entry module with the defs of one variant and the
//! layout of each bind group it reads, declared once in Rust ([`Group`], [`Binding`]): the bind
//! group layouts and the uniforms' `min_binding_size` are made from it, and [`check_bindings`]
//! holds it against naga's reflection of the composed module, so a WGSL binding and its Rust
//! declaration cannot drift apart.
//!
//! A renderer takes a technique's visibility module either flattened to one WGSL string
//! ([`crate::ShadowTechnique::visibility_wgsl`]) or as modules for its own naga_oil composer
//! ([`Library::add_to`], then `#import occlusion_slices::visibility::visibility`, with
//! `MAPS_GROUP` among its shader defs).

use naga_oil::compose::{
    ComposableModuleDescriptor, Composer, NagaModuleDescriptor, ShaderDefValue,
};
use std::collections::HashMap;

/// The shader def that places a technique's maps in a bind group: `@group(#{MAPS_GROUP})`.
pub const MAPS_GROUP: &str = "MAPS_GROUP";

/// The import path under which the evaluation entry points
/// (`soft_shadow_core::evaluate_receivers`, `soft_shadow_core::evaluate_texels`) import the
/// technique being evaluated (its [`VisibilityShader::module`]).
pub const TECHNIQUE_ALIAS: &str = "soft_shadow_core::technique";

/// One WGSL file: its import path and its text.
#[derive(Debug)]
pub struct ShaderModule {
    /// The path other modules import it by (its `#define_import_path`).
    pub path: &'static str,
    /// The WGSL text.
    pub source: &'static str,
}

/// A crate's WGSL modules, the libraries they import from, and the programs the crate builds.
#[derive(Debug)]
pub struct Library {
    /// The crate, for messages.
    pub name: &'static str,
    /// Its modules.
    pub modules: &'static [ShaderModule],
    /// The libraries its modules import from.
    pub depends: &'static [&'static Library],
    /// Every program the crate builds from them, every variant once (what the validation test
    /// composes).
    pub programs: &'static [&'static Program],
}

/// What one binding holds.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Binding {
    /// `var<uniform>` of a Rust struct of `size` bytes ([`uniform`]).
    Uniform {
        /// Size of the struct, bytes: the binding's `min_binding_size`.
        size: u64,
    },
    /// `var<storage, read>` (or `read_write`): a runtime-sized array whose elements take
    /// `min_size` bytes, or a sized type (struct, fixed-size array) of `min_size` bytes.
    Storage {
        /// Whether the shader only reads it.
        read_only: bool,
        /// One element of a runtime-sized array, or the whole sized type, in bytes: the
        /// binding's `min_binding_size`.
        min_size: u64,
    },
    /// A sampled texture read with `textureLoad`.
    Texture {
        /// Float (non-filterable), unsigned integer or depth.
        sample: wgpu::TextureSampleType,
        /// 2D or 2D array.
        dimension: wgpu::TextureViewDimension,
    },
    /// A storage texture, write-only or read-write.
    StorageTexture {
        /// The texel format.
        format: wgpu::TextureFormat,
        /// 2D or 2D array.
        dimension: wgpu::TextureViewDimension,
        /// Whether the shader also reads it (`read_write`; WebGPU allows it for `r32float`,
        /// `r32uint` and `r32sint`).
        read_write: bool,
    },
}

/// A uniform of Rust type `T` (`#[repr(C)]`, laid out as its WGSL struct).
pub const fn uniform<T>() -> Binding {
    Binding::Uniform {
        size: size_of::<T>() as u64,
    }
}

/// A storage buffer of a runtime-sized array of Rust elements `T`, or of one `T` (a struct, a
/// fixed-size array).
pub const fn storage<T>(read_only: bool) -> Binding {
    Binding::Storage {
        read_only,
        min_size: size_of::<T>() as u64,
    }
}

/// A non-filterable float texture (`texture_2d<f32>`, `texture_2d_array<f32>`).
pub const fn float_texture(dimension: wgpu::TextureViewDimension) -> Binding {
    Binding::Texture {
        sample: wgpu::TextureSampleType::Float { filterable: false },
        dimension,
    }
}

/// An unsigned-integer texture (`texture_2d<u32>`, `texture_2d_array<u32>`).
pub const fn uint_texture(dimension: wgpu::TextureViewDimension) -> Binding {
    Binding::Texture {
        sample: wgpu::TextureSampleType::Uint,
        dimension,
    }
}

/// A depth texture array (`texture_depth_2d_array`).
pub const DEPTH_ARRAY: Binding = Binding::Texture {
    sample: wgpu::TextureSampleType::Depth,
    dimension: wgpu::TextureViewDimension::D2Array,
};

/// A write-only storage texture of `format`.
pub const fn storage_texture(
    format: wgpu::TextureFormat,
    dimension: wgpu::TextureViewDimension,
) -> Binding {
    Binding::StorageTexture {
        format,
        dimension,
        read_write: false,
    }
}

/// A read-write storage texture of `format` (`r32float`, `r32uint` or `r32sint`).
pub const fn read_write_texture(
    format: wgpu::TextureFormat,
    dimension: wgpu::TextureViewDimension,
) -> Binding {
    Binding::StorageTexture {
        format,
        dimension,
        read_write: true,
    }
}

/// One bind group: its bindings in binding order from 0, visible to `stages`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Group {
    /// The stages that read it.
    pub stages: wgpu::ShaderStages,
    /// Binding `i` at index `i`.
    pub bindings: &'static [Binding],
}

impl Group {
    /// A group read by compute shaders.
    pub const fn compute(bindings: &'static [Binding]) -> Self {
        Self {
            stages: wgpu::ShaderStages::COMPUTE,
            bindings,
        }
    }

    /// The layout entries of this group, visible to `stages`.
    pub fn entries(&self, stages: wgpu::ShaderStages) -> Vec<wgpu::BindGroupLayoutEntry> {
        self.bindings
            .iter()
            .enumerate()
            .map(|(i, b)| wgpu::BindGroupLayoutEntry {
                binding: i as u32,
                visibility: stages,
                ty: match *b {
                    Binding::Uniform { size } => wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: std::num::NonZeroU64::new(size),
                    },
                    Binding::Storage {
                        read_only,
                        min_size,
                    } => wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Storage { read_only },
                        has_dynamic_offset: false,
                        min_binding_size: std::num::NonZeroU64::new(min_size),
                    },
                    Binding::Texture { sample, dimension } => wgpu::BindingType::Texture {
                        sample_type: sample,
                        view_dimension: dimension,
                        multisampled: false,
                    },
                    Binding::StorageTexture {
                        format,
                        dimension,
                        read_write,
                    } => wgpu::BindingType::StorageTexture {
                        access: if read_write {
                            wgpu::StorageTextureAccess::ReadWrite
                        } else {
                            wgpu::StorageTextureAccess::WriteOnly
                        },
                        format,
                        view_dimension: dimension,
                    },
                },
                count: None,
            })
            .collect()
    }
}

/// One program: an entry module of a library with the shader defs of one variant and the
/// layout of every bind group it reads.
#[derive(Debug)]
pub struct Program {
    /// The library that holds the module.
    pub library: &'static Library,
    /// Import path of the entry module.
    pub module: &'static str,
    /// Shader defs of this variant.
    pub defs: &'static [(&'static str, u32)],
    /// Bind group `i` at index `i`.
    pub groups: &'static [Group],
}

/// A technique's visibility function: the module that defines
/// `fn visibility(world_pos: vec3<f32>, normal: vec3<f32>) -> f32` over its maps in
/// `@group(#{MAPS_GROUP})`, and the layout of that group.
#[derive(Debug)]
pub struct VisibilityShader {
    /// The library that holds the module.
    pub library: &'static Library,
    /// Import path of the module.
    pub module: &'static str,
    /// The maps' bind group.
    pub maps: Group,
}

/// Why a module could not be composed or does not match its declaration.
#[derive(Debug, Clone, PartialEq)]
pub struct ShaderError(pub String);

impl std::fmt::Display for ShaderError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ShaderError {}

impl Library {
    /// Every module of this library and of those it depends on, once each.
    pub fn all_modules(&self) -> Vec<&'static ShaderModule> {
        let mut out: Vec<&'static ShaderModule> = Vec::new();
        self.collect(&mut out);
        out
    }

    fn collect(&self, out: &mut Vec<&'static ShaderModule>) {
        for d in self.depends {
            d.collect(out);
        }
        for m in self.modules {
            if !out.iter().any(|o| o.path == m.path) {
                out.push(m);
            }
        }
    }

    /// Adds every module of this library and of those it depends on to `composer`, each after
    /// the modules it imports (modules the composer holds already are kept). The evaluation
    /// entry points, which import the technique they evaluate ([`TECHNIQUE_ALIAS`]), are added
    /// only once the composer holds one ([`composer`]).
    pub fn add_to(&self, composer: &mut Composer) -> Result<(), ShaderError> {
        let waits_for_technique = |m: &ShaderModule| {
            let (_, imports, _) = naga_oil::compose::get_preprocessor_data(m.source);
            imports.iter().any(|d| d.import == TECHNIQUE_ALIAS)
        };
        let has_technique = composer.contains_module(TECHNIQUE_ALIAS);
        let mut pending: Vec<&ShaderModule> = self
            .all_modules()
            .into_iter()
            .filter(|m| has_technique || !waits_for_technique(m))
            .collect();
        while !pending.is_empty() {
            let before = pending.len();
            let mut i = 0;
            while i < pending.len() {
                let m = pending[i];
                if composer.contains_module(m.path) {
                    pending.remove(i);
                    continue;
                }
                let (_, imports, _) = naga_oil::compose::get_preprocessor_data(m.source);
                if imports.iter().all(|d| composer.contains_module(&d.import)) {
                    add(composer, m.source, m.path, None)?;
                    pending.remove(i);
                } else {
                    i += 1;
                }
            }
            if pending.len() == before {
                let missing: Vec<String> = pending
                    .iter()
                    .map(|m| {
                        let (_, imports, _) = naga_oil::compose::get_preprocessor_data(m.source);
                        let names: Vec<String> = imports
                            .into_iter()
                            .map(|d| d.import)
                            .filter(|d| !composer.contains_module(d))
                            .collect();
                        format!("{} imports {}", m.path, names.join(", "))
                    })
                    .collect();
                return Err(ShaderError(format!(
                    "{}: unresolved imports: {}",
                    self.name,
                    missing.join("; ")
                )));
            }
        }
        Ok(())
    }

    /// The module at `path`, in this library or one it depends on.
    pub fn module(&self, path: &str) -> Option<&'static ShaderModule> {
        self.all_modules().into_iter().find(|m| m.path == path)
    }
}

fn add(
    composer: &mut Composer,
    source: &str,
    path: &str,
    as_name: Option<&str>,
) -> Result<(), ShaderError> {
    composer
        .add_composable_module(ComposableModuleDescriptor {
            source,
            file_path: path,
            as_name: as_name.map(str::to_string),
            ..Default::default()
        })
        .map(|_| ())
        .map_err(|e| ShaderError(format!("{path}: {}", e.emit_to_string(composer))))
}

/// The shader defs of `defs`, as naga_oil takes them.
fn shader_defs(defs: &[(&str, u32)]) -> HashMap<String, ShaderDefValue> {
    defs.iter()
        .map(|&(k, v)| (k.to_string(), ShaderDefValue::UInt(v)))
        .collect()
}

/// A composer holding `library` and, where `technique` is given, that technique's visibility
/// module a second time under [`TECHNIQUE_ALIAS`].
pub fn composer(
    library: &Library,
    technique: Option<&VisibilityShader>,
) -> Result<Composer, ShaderError> {
    let mut c = Composer::default();
    library.add_to(&mut c)?;
    if let Some(t) = technique {
        t.library.add_to(&mut c)?;
        let m = t
            .library
            .module(t.module)
            .ok_or_else(|| ShaderError(format!("{}: no module {}", t.library.name, t.module)))?;
        add(&mut c, m.source, m.path, Some(TECHNIQUE_ALIAS))?;
        // Now the entry points that import it.
        library.add_to(&mut c)?;
    }
    Ok(c)
}

/// Module `path` of `composer`'s libraries composed as an entry module with `defs`, validated.
pub fn compose_in(
    composer: &mut Composer,
    library: &Library,
    path: &str,
    defs: &[(&str, u32)],
) -> Result<naga::Module, ShaderError> {
    let m = library
        .module(path)
        .ok_or_else(|| ShaderError(format!("{}: no module {path}", library.name)))?;
    composer
        .make_naga_module(NagaModuleDescriptor {
            source: m.source,
            file_path: m.path,
            shader_defs: shader_defs(defs),
            ..Default::default()
        })
        .map_err(|e| ShaderError(format!("{path}: {}", e.emit_to_string(composer))))
}

/// `program` composed and validated, its bindings checked against its declaration.
pub fn compose(program: &Program) -> Result<naga::Module, ShaderError> {
    let mut c = composer(program.library, None)?;
    let module = compose_in(&mut c, program.library, program.module, program.defs)?;
    check_bindings(&module, program.groups)
        .map_err(|e| ShaderError(format!("{}: {e}", program.module)))?;
    Ok(module)
}

/// WGSL text of a composed module (naga's writer: imported items carry naga_oil's decorated
/// names, the entry module's own keep theirs).
pub fn wgsl(module: &naga::Module) -> Result<String, ShaderError> {
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(module)
    .map_err(|e| ShaderError(format!("validation: {e:?}")))?;
    naga::back::wgsl::write_string(module, &info, naga::back::wgsl::WriterFlags::empty())
        .map_err(|e| ShaderError(format!("WGSL output: {e}")))
}

/// The wgpu format of a naga storage format (those the workspace's kernels write).
fn storage_format(f: naga::StorageFormat) -> Option<wgpu::TextureFormat> {
    use naga::StorageFormat as S;
    use wgpu::TextureFormat as T;
    Some(match f {
        S::Rgba8Unorm => T::Rgba8Unorm,
        S::Rgba16Float => T::Rgba16Float,
        S::Rgba32Float => T::Rgba32Float,
        S::R32Float => T::R32Float,
        S::Rg32Float => T::Rg32Float,
        S::Rgba32Uint => T::Rgba32Uint,
        S::R32Uint => T::R32Uint,
        _ => return None,
    })
}

fn view_dimension(dim: naga::ImageDimension, arrayed: bool) -> Option<wgpu::TextureViewDimension> {
    use wgpu::TextureViewDimension as V;
    match (dim, arrayed) {
        (naga::ImageDimension::D2, false) => Some(V::D2),
        (naga::ImageDimension::D2, true) => Some(V::D2Array),
        _ => None,
    }
}

/// Holds every bound global variable of `module` against the binding `groups` declares at its
/// group and index, and every declared binding against a variable of the module: a uniform's
/// size, a storage buffer's access and element stride, a texture's sample type and dimension,
/// a storage texture's format and dimension.
pub fn check_bindings(module: &naga::Module, groups: &[Group]) -> Result<(), String> {
    let mut layouter = naga::proc::Layouter::default();
    layouter
        .update(module.to_ctx())
        .map_err(|e| format!("layout: {e}"))?;
    let mut seen = Vec::new();
    for (_, var) in module.global_variables.iter() {
        let Some(rb) = &var.binding else { continue };
        let name = var.name.as_deref().unwrap_or("?");
        let at = format!("@group({}) @binding({}) `{name}`", rb.group, rb.binding);
        let decl = groups
            .get(rb.group as usize)
            .and_then(|g| g.bindings.get(rb.binding as usize))
            .ok_or_else(|| format!("{at} is not declared"))?;
        seen.push((rb.group as usize, rb.binding as usize));
        let inner = &module.types[var.ty].inner;
        let ok = match (*decl, var.space, inner) {
            (Binding::Uniform { size }, naga::AddressSpace::Uniform, _) => {
                let got = layouter[var.ty].size as u64;
                if got != size {
                    return Err(format!(
                        "{at}: the WGSL uniform is {got} bytes, the Rust declaration {size}"
                    ));
                }
                true
            }
            (
                Binding::Storage {
                    read_only,
                    min_size,
                },
                naga::AddressSpace::Storage { access },
                _,
            ) => {
                if read_only == access.contains(naga::StorageAccess::STORE) {
                    return Err(format!(
                        "{at}: declared {}, the WGSL is {access:?}",
                        if read_only { "read-only" } else { "read-write" }
                    ));
                }
                let got = match inner {
                    naga::TypeInner::Array {
                        stride,
                        size: naga::ArraySize::Dynamic,
                        ..
                    } => *stride as u64,
                    _ => layouter[var.ty].size as u64,
                };
                if got != min_size {
                    return Err(format!(
                        "{at}: the WGSL needs {got} bytes (one element of a runtime-sized array, \
                         or the whole type), the Rust declaration {min_size}"
                    ));
                }
                true
            }
            (
                Binding::Texture { sample, dimension },
                _,
                naga::TypeInner::Image {
                    dim,
                    arrayed,
                    class,
                },
            ) => {
                let class_ok = matches!(
                    (sample, class),
                    (
                        wgpu::TextureSampleType::Float { .. },
                        naga::ImageClass::Sampled {
                            kind: naga::ScalarKind::Float,
                            multi: false,
                        },
                    ) | (
                        wgpu::TextureSampleType::Uint,
                        naga::ImageClass::Sampled {
                            kind: naga::ScalarKind::Uint,
                            multi: false,
                        },
                    ) | (
                        wgpu::TextureSampleType::Depth,
                        naga::ImageClass::Depth { multi: false }
                    )
                );
                class_ok && view_dimension(*dim, *arrayed) == Some(dimension)
            }
            (
                Binding::StorageTexture {
                    format,
                    dimension,
                    read_write,
                },
                _,
                naga::TypeInner::Image {
                    dim,
                    arrayed,
                    class: naga::ImageClass::Storage { format: f, access },
                },
            ) => {
                storage_format(*f) == Some(format)
                    && view_dimension(*dim, *arrayed) == Some(dimension)
                    && access.contains(naga::StorageAccess::LOAD) == read_write
            }
            _ => false,
        };
        if !ok {
            return Err(format!(
                "{at}: declared {decl:?}, the WGSL is {:?} in {:?}",
                inner, var.space
            ));
        }
    }
    for (g, group) in groups.iter().enumerate() {
        for b in 0..group.bindings.len() {
            if !seen.contains(&(g, b)) {
                return Err(format!(
                    "@group({g}) @binding({b}) is declared ({:?}) but the module binds nothing there",
                    group.bindings[b]
                ));
            }
        }
    }
    Ok(())
}

/// soft-shadow-core's modules: the light-space projection (`soft_shadow_core::light_space`:
/// `MapView`, `Bias`, `shadow_coord`, ...), seed packing (`soft_shadow_core::seeds`), the
/// rasterizer and the two evaluation entry points.
pub static SHADERS: Library = Library {
    name: "soft-shadow-core",
    modules: &[
        ShaderModule {
            path: "soft_shadow_core::light_space",
            source: include_str!("light_space.wgsl"),
        },
        ShaderModule {
            path: "soft_shadow_core::seeds",
            source: include_str!("seeds.wgsl"),
        },
        ShaderModule {
            path: "soft_shadow_core::raster",
            source: include_str!("raster.wgsl"),
        },
        ShaderModule {
            path: "soft_shadow_core::views",
            source: include_str!("views.wgsl"),
        },
        ShaderModule {
            path: "soft_shadow_core::evaluate_receivers",
            source: include_str!("evaluate_receivers.wgsl"),
        },
        ShaderModule {
            path: "soft_shadow_core::evaluate_texels",
            source: include_str!("evaluate_texels.wgsl"),
        },
    ],
    depends: &[],
    programs: &[&RASTER],
};

/// `raster.wgsl`: the view-projection matrix, read by the vertex stage.
pub(crate) static RASTER: Program = Program {
    library: &SHADERS,
    module: "soft_shadow_core::raster",
    defs: &[],
    groups: &[Group {
        stages: wgpu::ShaderStages::VERTEX,
        bindings: &[uniform::<[f32; 16]>()],
    }],
};

/// The library of [`NO_GPU_PATH`]: no modules.
static NO_MODULES: Library = Library {
    name: "none",
    modules: &[],
    depends: &[],
    programs: &[],
};

/// The [`ShadowTechnique::VISIBILITY`](crate::ShadowTechnique::VISIBILITY) of a technique type
/// built without its GPU path: a module that does not exist. Such a type's generation answers
/// [`ShadowError::Gpu`](crate::ShadowError::Gpu) (so no maps of it reach an evaluation) and so
/// does its `visibility_wgsl`; composing it directly
/// ([`visibility::pipelines`](crate::gpu::visibility::pipelines)) fails as any unknown module
/// does.
pub static NO_GPU_PATH: VisibilityShader = VisibilityShader {
    library: &NO_MODULES,
    module: "none",
    maps: Group::compute(&[]),
};
