//! glTF 2.0 import (`.glb` or `.gltf` with external `.bin` buffers) into triangle meshes.
//!
//! Every mesh primitive of a triangle mode (list, strip, fan) is read with node transforms applied
//! (the default scene, or every root node when none is marked); point and line primitives cast no
//! shadow and are skipped. A file without triangles, or malformed in any way, is a typed
//! [`ShadowError::Gltf`] naming the problem.
//!
//! Everything read is checked before it is used: buffer, view and accessor ranges, component
//! types and alignment (glTF 2.0 section 3.6.2.4), index bounds, primitive modes, and the mesh's
//! coordinates ([`soft_shadow_core::mesh::MAX_COORDINATE`]). The `gltf` crate still panics on some
//! malformed JSON while it validates (an index out of bounds in `gltf-json`'s mesh validation,
//! `unreachable!` in its mode parsing): the import boundary catches those panics, without
//! printing them, and returns a [`ShadowError::Gltf`] naming the file.

use glam::{Mat4, Vec3};
use gltf::mesh::Mode;
use soft_shadow_core::error::{Result, ShadowError};
use soft_shadow_core::mesh::TriangleMesh;
use std::path::Path;

fn err(source_name: &str, reason: impl Into<String>) -> ShadowError {
    ShadowError::Gltf {
        source_name: source_name.to_string(),
        reason: reason.into(),
    }
}

/// Whether `bytes` start like a GLB (the magic `glTF`) or a glTF JSON document (`{` after
/// optional whitespace and a UTF-8 byte-order mark).
fn looks_like_gltf(bytes: &[u8]) -> bool {
    if bytes.starts_with(b"glTF") {
        return true;
    }
    let text = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    text.iter()
        .find(|b| !b.is_ascii_whitespace())
        .is_some_and(|&b| b == b'{')
}

/// A GLB container of a glTF JSON document and its binary chunk, each padded to 4 bytes (JSON
/// with spaces, binary with zeros), with correct lengths: what tests and tools write files with.
pub fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let pad = |mut v: Vec<u8>, with: u8| {
        while !v.len().is_multiple_of(4) {
            v.push(with);
        }
        v
    };
    let (j, b) = (pad(json.as_bytes().to_vec(), b' '), pad(bin.to_vec(), 0));
    let total = 12 + 8 + j.len() + 8 + b.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(j.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&j);
    out.extend_from_slice(&(b.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&b);
    out
}

/// Imports a `.glb`/`.gltf` file as one world-space mesh (node transforms applied).
pub fn import_gltf_file(path: &Path) -> Result<TriangleMesh> {
    let bytes = std::fs::read(path).map_err(|source| ShadowError::Io {
        path: path.display().to_string(),
        source,
    })?;
    import_gltf_slice(&bytes, &path.display().to_string(), path.parent())
}

/// Imports glTF bytes. `base_dir` resolves external buffer files; `None` accepts only GLB-embedded data.
pub fn import_gltf_slice(
    bytes: &[u8],
    source_name: &str,
    base_dir: Option<&Path>,
) -> Result<TriangleMesh> {
    quiet_panics(|| import_unguarded(bytes, source_name, base_dir)).unwrap_or_else(|message| {
        Err(err(
            source_name,
            format!("the glTF loader (`gltf` crate) panicked on this file: {message}"),
        ))
    })
}

thread_local! {
    static QUIET: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Runs `f`, turning a panic into `Err(message)`; while it runs, this thread's panics are not
/// printed (a process-wide hook, installed once, defers to the previous hook otherwise).
fn quiet_panics<T>(f: impl FnOnce() -> T) -> std::result::Result<T, String> {
    static HOOK: std::sync::Once = std::sync::Once::new();
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !QUIET.with(|q| q.get()) {
                previous(info);
            }
        }));
    });
    let was = QUIET.with(|q| q.replace(true));
    let out = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f));
    QUIET.with(|q| q.set(was));
    out.map_err(|payload| {
        payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown panic".into())
    })
}

fn import_unguarded(
    bytes: &[u8],
    source_name: &str,
    base_dir: Option<&Path>,
) -> Result<TriangleMesh> {
    if !looks_like_gltf(bytes) {
        return Err(err(
            source_name,
            "not a glTF/GLB file (it starts with neither the GLB magic `glTF` nor a JSON object)",
        ));
    }
    let gltf = gltf::Gltf::from_slice(bytes).map_err(|e| err(source_name, e.to_string()))?;
    let mut buffers: Vec<Vec<u8>> = Vec::new();
    for buffer in gltf.document.buffers() {
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => gltf
                .blob
                .clone()
                .ok_or_else(|| err(source_name, "GLB buffer 0 has no binary chunk"))?,
            gltf::buffer::Source::Uri(uri) => {
                if uri.starts_with("data:") {
                    return Err(err(
                        source_name,
                        "data-URI buffers are not supported; use .glb or a .bin file",
                    ));
                }
                let dir = base_dir.ok_or_else(|| {
                    err(
                        source_name,
                        format!("external buffer {uri} needs a base directory"),
                    )
                })?;
                let p = dir.join(uri);
                std::fs::read(&p).map_err(|source| ShadowError::Io {
                    path: p.display().to_string(),
                    source,
                })?
            }
        };
        if data.len() < buffer.length() {
            return Err(err(
                source_name,
                format!(
                    "buffer {} holds {} bytes, needs {}",
                    buffer.index(),
                    data.len(),
                    buffer.length()
                ),
            ));
        }
        buffers.push(data);
    }
    let scene = gltf
        .document
        .default_scene()
        .or_else(|| gltf.document.scenes().next());
    let roots: Vec<gltf::Node> = match scene {
        Some(s) => s.nodes().collect(),
        None => gltf.document.nodes().collect(),
    };
    let mut mesh = TriangleMesh {
        name: source_name.to_string(),
        ..Default::default()
    };
    let mut stack: Vec<(gltf::Node, Mat4)> =
        roots.into_iter().map(|n| (n, Mat4::IDENTITY)).collect();
    let mut visited = 0usize;
    let mut skipped: Vec<String> = Vec::new();
    while let Some((node, parent)) = stack.pop() {
        visited += 1;
        if visited > 1_000_000 {
            return Err(err(source_name, "node hierarchy too deep or cyclic"));
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if let Some(m) = node.mesh() {
            for prim in m.primitives() {
                match prim.mode() {
                    Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan => {
                        read_primitive(&prim, &buffers, world, &mut mesh, source_name)?
                    }
                    other => skipped.push(format!(
                        "mesh {} primitive {} ({other:?})",
                        m.index(),
                        prim.index()
                    )),
                }
            }
        }
        for child in node.children() {
            stack.push((child, world));
        }
    }
    if mesh.indices.is_empty() {
        return Err(if skipped.is_empty() {
            err(source_name, "no triangles found")
        } else {
            err(
                source_name,
                format!(
                    "no triangles found; only triangles cast shadows, skipped {}",
                    skipped.join(", ")
                ),
            )
        });
    }
    mesh.validate()?;
    Ok(mesh)
}

/// The component type, dimensions and alignment of an accessor the import reads: positions are
/// `VEC3` of `f32`, indices `SCALAR` of an unsigned integer; every accessor's offset within its
/// buffer and its view's stride are multiples of its component size.
fn check_accessor(
    acc: &gltf::Accessor,
    semantic: Option<&gltf::Semantic>,
    name: &str,
) -> Result<()> {
    use gltf::accessor::{DataType, Dimensions};
    let what = match semantic {
        Some(s) => format!("accessor {} ({s:?})", acc.index()),
        None => format!("accessor {} (indices)", acc.index()),
    };
    let (ty, dims) = (acc.data_type(), acc.dimensions());
    let ok = match semantic {
        Some(gltf::Semantic::Positions) => ty == DataType::F32 && dims == Dimensions::Vec3,
        None => {
            matches!(ty, DataType::U8 | DataType::U16 | DataType::U32) && dims == Dimensions::Scalar
        }
        Some(_) => true,
    };
    if !ok {
        return Err(err(
            name,
            format!("{what} is {dims:?} of {ty:?}, which glTF does not allow there"),
        ));
    }
    let component = ty.size();
    if let Some(view) = acc.view() {
        let offset = view.offset() + acc.offset();
        if !offset.is_multiple_of(component) {
            return Err(err(
                name,
                format!(
                    "{what} starts at byte {offset} of its buffer, not a multiple of its \
                     {component}-byte components (misaligned)"
                ),
            ));
        }
        if let Some(stride) = view.stride()
            && !stride.is_multiple_of(component)
        {
            return Err(err(
                name,
                format!("{what}: byte stride {stride} is not a multiple of {component}"),
            ));
        }
    }
    Ok(())
}

fn read_primitive(
    prim: &gltf::Primitive,
    buffers: &[Vec<u8>],
    world: Mat4,
    mesh: &mut TriangleMesh,
    name: &str,
) -> Result<()> {
    // Check accessor ranges, types and alignment ourselves: the reader would index past a short
    // buffer, and misaligned floats read as garbage.
    for (semantic, acc) in prim
        .attributes()
        .map(|(s, a)| (Some(s), a))
        .chain(prim.indices().map(|a| (None, a)))
    {
        check_accessor(&acc, semantic.as_ref(), name)?;
        if let Some(view) = acc.view() {
            let end = view.offset() + view.length();
            let have = buffers.get(view.buffer().index()).map_or(0, |b| b.len());
            if end > have {
                return Err(err(
                    name,
                    format!(
                        "buffer view {} ends at byte {end} past its buffer ({have} bytes)",
                        view.index()
                    ),
                ));
            }
            let stride = view.stride().unwrap_or(acc.size());
            let need = acc.offset() + stride * acc.count().saturating_sub(1) + acc.size();
            if acc.count() > 0 && need > view.length() {
                return Err(err(
                    name,
                    format!(
                        "accessor {} reads {need} bytes from a {}-byte view",
                        acc.index(),
                        view.length()
                    ),
                ));
            }
        } else {
            return Err(err(
                name,
                format!(
                    "accessor {} has no buffer view (sparse accessors are not supported)",
                    acc.index()
                ),
            ));
        }
    }
    let reader = prim.reader(|b| buffers.get(b.index()).map(|d| d.as_slice()));
    let positions: Vec<Vec3> = reader
        .read_positions()
        .ok_or_else(|| err(name, "a primitive has no POSITION attribute"))?
        .map(|p| world.transform_point3(Vec3::from(p)))
        .collect();
    let base = mesh.positions.len() as u32;
    let n = positions.len() as u32;
    let indices: Vec<u32> = match reader.read_indices() {
        Some(ix) => ix.into_u32().collect(),
        None => (0..n).collect(),
    };
    if !indices.len().is_multiple_of(3) {
        return Err(err(
            name,
            format!("{} indices is not a multiple of 3", indices.len()),
        ));
    }
    if let Some(bad) = indices.iter().find(|&&i| i >= n) {
        return Err(err(
            name,
            format!("index {bad} out of range for {n} vertices"),
        ));
    }
    mesh.positions.extend(positions);
    mesh.indices.extend(
        indices
            .chunks_exact(3)
            .map(|c| [c[0] + base, c[1] + base, c[2] + base]),
    );
    Ok(())
}
